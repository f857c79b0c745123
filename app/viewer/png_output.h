// Writing RGBA8 images as PNG files, atomically (a temporary file beside the target, then rename).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace penumbra::viewer {

// rgba: width * height * 4 bytes, top row first. Throws std::runtime_error naming the file.
void writeRgbaPng(const std::filesystem::path& path, int width, int height,
                  const std::vector<uint8_t>& rgba);

// Writes text atomically (for --state-out). Throws std::runtime_error naming the file.
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace penumbra::viewer
