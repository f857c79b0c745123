// OpenEXR output (Debian's libopenexr-dev): linear radiance as a scanline image of three 32-bit
// float channels R, G, B, ZIP-compressed (lossless), rows from the top. Float, not half: the
// same values as the PFM of the same film (a half keeps 11 significant bits and stops at 65504,
// which would blur the small differences between exact and sampled images and clip bright
// emitters). The file is written with writeFileAtomically (atomic_file.h) like every other.
#pragma once

#include <span>
#include <string>

namespace penumbra {

// The bytes of the OpenEXR file of a width x height image; `rgb` holds 3 floats per pixel, rows
// from the top. Throws std::runtime_error when the image is empty or does not match its size, or
// the library cannot encode it.
std::string encodeExr(int width, int height, std::span<const float> rgb);

}  // namespace penumbra
