// Texture images read for materials (engine/scene/texture.h): decoded with stb_image (Debian's
// libstb), which reads PNG, JPEG, BMP, TGA, GIF (the first frame), PSD, PNM and Radiance HDR, to
// 8-bit sRGB RGB (grey expanded, alpha dropped; 16-bit and HDR images are reduced to 8 bits as
// stb_image does).
//
// A texture that cannot be used is reported, never fatal here: the loaders decide (repair mode: a
// warning naming the file and the reason, the material keeps its colour factor alone; strict
// mode: a SceneError; docs/formats.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>

#include "engine/scene/texture.h"

namespace penumbra {

// The largest image decoded, in texels (8192 x 8192): a header claiming more is refused before
// anything is allocated.
inline constexpr size_t kMaxTextureTexels = size_t{1} << 26;
// The largest image file read (a regular file; anything else is refused unread).
inline constexpr uintmax_t kMaxTextureFileBytes = uintmax_t{512} << 20;

// What reading a texture gave: the image, or why there is none ("cannot read file: No such file
// or directory", "cannot decode it: corrupt JPEG", "16384 x 16384 texels, more than ...").
struct TextureRead {
    std::optional<TextureImage> image;
    std::string problem;
};

// Decodes an image held in memory; `source` names it (TextureImage::source).
TextureRead decodeTexture(std::span<const unsigned char> bytes, std::string source);
// Reads and decodes an image file.
TextureRead readTextureFile(const std::filesystem::path& path);

}  // namespace penumbra
