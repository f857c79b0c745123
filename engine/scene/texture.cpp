#include "engine/scene/texture.h"

#include <array>
#include <cmath>

namespace penumbra {
namespace texture_detail {

// The 256 linear values of the sRGB bytes, computed once.
const std::array<double, 256>& srgbTable() {
    static const std::array<double, 256> table = [] {
        std::array<double, 256> t{};
        for (int i = 0; i < 256; ++i) {
            const double c = i / 255.0;
            t[static_cast<size_t>(i)] =
                c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
        }
        return t;
    }();
    return table;
}

// Texel index i (any integer) wrapped into [0, n).
int wrapIndex(int64_t i, int n, TextureWrap wrap) {
    switch (wrap) {
        case TextureWrap::ClampToEdge:
            return static_cast<int>(i < 0 ? 0 : i >= n ? n - 1 : i);
        case TextureWrap::MirroredRepeat: {
            const int64_t period = 2 * static_cast<int64_t>(n);
            int64_t m = i % period;
            if (m < 0) m += period;
            return static_cast<int>(m < n ? m : period - 1 - m);
        }
        case TextureWrap::Repeat:
            break;
    }
    int64_t m = i % n;
    if (m < 0) m += n;
    return static_cast<int>(m);
}

// floor(x) as an integer, with x clamped far outside any image (a UV of 1e300 reads some texel).
int64_t floorIndex(double x) {
    constexpr double kLimit = 0x1p52;
    if (!(x > -kLimit)) return -static_cast<int64_t>(kLimit);
    if (!(x < kLimit)) return static_cast<int64_t>(kLimit);
    return static_cast<int64_t>(std::floor(x));
}

}  // namespace texture_detail

Uv UvTransform::apply(const Uv& uv) const {
    const double c = std::cos(rotation), s = std::sin(rotation);
    const double su = scale.u * uv.u, sv = scale.v * uv.v;
    return {c * su + s * sv + offset.u, -s * su + c * sv + offset.v};
}

double srgbToLinear(uint8_t encoded) { return texture_detail::srgbTable()[encoded]; }

Vec3 TextureImage::texel(int i, int j) const {
    const size_t k = 3 * (static_cast<size_t>(j) * static_cast<size_t>(width) + i);
    return {srgbToLinear(srgb[k]), srgbToLinear(srgb[k + 1]), srgbToLinear(srgb[k + 2])};
}

Vec3 sampleTexture(const TextureImage& image, const TextureRef& ref, const Uv& uvIn) {
    using texture_detail::floorIndex;
    using texture_detail::wrapIndex;
    if (image.width < 1 || image.height < 1) return {1, 1, 1};
    Uv uv = ref.transform.isIdentity() ? uvIn : ref.transform.apply(uvIn);
    if (!std::isfinite(uv.u) || !std::isfinite(uv.v)) uv = {0, 0};
    // In texel units: texel i spans [i, i + 1], its centre at i + 1/2.
    const double x = uv.u * image.width, y = uv.v * image.height;
    if (ref.filter == TextureFilter::Nearest)
        return image.texel(wrapIndex(floorIndex(x), image.width, ref.wrapU),
                           wrapIndex(floorIndex(y), image.height, ref.wrapV));
    // Bilinear between the centres around (x, y): columns i0, i0 + 1 and rows j0, j0 + 1.
    const int64_t i0 = floorIndex(x - 0.5), j0 = floorIndex(y - 0.5);
    const double fx = std::fmin(std::fmax(x - 0.5 - static_cast<double>(i0), 0.0), 1.0);
    const double fy = std::fmin(std::fmax(y - 0.5 - static_cast<double>(j0), 0.0), 1.0);
    const int ia = wrapIndex(i0, image.width, ref.wrapU);
    const int ib = wrapIndex(i0 + 1, image.width, ref.wrapU);
    const int ja = wrapIndex(j0, image.height, ref.wrapV);
    const int jb = wrapIndex(j0 + 1, image.height, ref.wrapV);
    const Vec3 top = image.texel(ia, ja) * (1 - fx) + image.texel(ib, ja) * fx;
    const Vec3 bottom = image.texel(ia, jb) * (1 - fx) + image.texel(ib, jb) * fx;
    return top * (1 - fy) + bottom * fy;
}

}  // namespace penumbra
