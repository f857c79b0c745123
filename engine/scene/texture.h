// Textures: a material's base-colour map (glTF baseColorTexture, OBJ map_Kd), decoded once on
// load (engine/io/texture_io.h) into 8-bit sRGB texels, and its filtered lookup.
//
// Conventions:
//   - texture coordinates (Uv) are glTF's: (0, 0) is the image's top-left corner, u to the right,
//     v down; OBJ's vt (v up) is flipped on load (v' = 1 - v);
//   - texel (i, j) (column i, row j from the top) covers [i, i + 1] / width x [j, j + 1] / height:
//     its centre is at ((i + 1/2) / width, (j + 1/2) / height);
//   - texels are sRGB-encoded (the glTF rule for base colour, and what image files of colours
//     hold) and decoded to linear before filtering: the lookup returns a linear colour that
//     multiplies the material's factor (glTF baseColorFactor, MTL Kd);
//   - alpha is ignored; no mipmaps (a minified texture aliases: the exact render's pixels average
//     their jittered samples, the raster view leaves it to the GPU's magnification filter).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "visibility/vec3.h"

namespace penumbra {

using vis::Vec3;

struct Uv {
    double u = 0, v = 0;
    friend bool operator==(const Uv&, const Uv&) = default;
};

// What a lookup outside [0, 1] reads (glTF sampler wrapS / wrapT).
enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };
// Bilinear between the four nearest texel centres, or the texel the point lies in (glTF
// magFilter NEAREST).
enum class TextureFilter : uint8_t { Linear, Nearest };

// KHR_texture_transform: uv' = T(offset) R(rotation) S(scale) uv, that is
//   u' =  cos(r) s_u u + sin(r) s_v v + o_u,
//   v' = -sin(r) s_u u + cos(r) s_v v + o_v
// (the UVs rotated counter-clockwise by r as seen in the image, v down: the image turns
// clockwise; the extension's example, offset (0, 1), rotation pi/2, scale 1/2, reads the image's
// lower-left quadrant).
struct UvTransform {
    Uv offset{0, 0};
    double rotation = 0;  // radians
    Uv scale{1, 1};
    Uv apply(const Uv& uv) const;
    bool isIdentity() const { return offset == Uv{0, 0} && rotation == 0 && scale == Uv{1, 1}; }
};

// A decoded image: width * height texels of 3 sRGB-encoded bytes (R, G, B), rows from the top.
struct TextureImage {
    std::string source;  // the file it came from (or "FILE image N" for an embedded one)
    int width = 0, height = 0;
    std::vector<uint8_t> srgb;
    // Texel (i, j) as a linear colour; i, j must be in range.
    Vec3 texel(int i, int j) const;
};

// A material's use of an image: which one, how it wraps and filters, the UV transform.
struct TextureRef {
    int32_t image = -1;  // index into Scene::textures; -1: none
    TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;
    TextureFilter filter = TextureFilter::Linear;
    UvTransform transform;
    bool present() const { return image >= 0; }
};

// The sRGB transfer curve inverted (IEC 61966-2-1): the linear value of an encoded byte.
double srgbToLinear(uint8_t encoded);

// The linear colour of `image` at `uv` (before `ref`'s transform: it is applied here), wrapped and
// filtered as `ref` says. Non-finite coordinates read texel (0, 0).
Vec3 sampleTexture(const TextureImage& image, const TextureRef& ref, const Uv& uv);

}  // namespace penumbra
