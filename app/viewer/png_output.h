// Writing the viewer's RGBA8 screenshots as PNG files and its state as text, atomically
// (engine/io/atomic_file.h).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::viewer {

// rgba: width * height * 4 bytes, top row first. Throws std::runtime_error naming the file.
void writeRgbaPng(const std::filesystem::path& path, int width, int height,
                  const std::vector<uint8_t>& rgba);

// Writes text atomically (for --state-out). Throws std::runtime_error naming the file.
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace penumbra::viewer
