// Image output of the renderer: tone mapping and file writing (writePfm / writePng are declared in
// renderer.h next to Film, and implemented in image_io.cpp).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "engine/renderer.h"

namespace penumbra {

// The film's mean radiance times `exposure`, clamped to [0, 1] and encoded with the sRGB transfer
// curve, 8 bits per channel, RGB, rows from the top. Non-finite values become 0.
std::vector<uint8_t> toSrgb8(const Film& film, double exposure = 1.0);

// Writes `bytes` to `path` through a temporary file in the same directory, flushed to disk, then
// renamed over the target: readers see the old file or the whole new one. Throws
// std::runtime_error("cannot write 'PATH': REASON") on failure (the temporary is removed).
void writeFileAtomically(const std::string& path, std::string_view bytes);

}  // namespace penumbra
