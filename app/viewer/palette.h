// Colours shared by the 3D overlays, the 2D light inset and the tests that look for them in
// screenshots: fragment i of a light is drawn in fragmentColour(i) everywhere.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>

namespace penumbra::viewer {

struct Rgb {
    uint8_t r, g, b;
};

inline constexpr std::array<Rgb, 10> kFragmentColours = {{
    {230, 25, 75},
    {60, 180, 75},
    {0, 130, 200},
    {245, 130, 48},
    {145, 30, 180},
    {70, 240, 240},
    {240, 50, 230},
    {210, 245, 60},
    {0, 128, 128},
    {170, 110, 40},
}};
inline Rgb fragmentColour(std::size_t i) { return kFragmentColours[i % kFragmentColours.size()]; }

inline constexpr Rgb kMarkerColour{255, 255, 0};    // the picked point and its normal
inline constexpr Rgb kPathEdgeColour{255, 160, 0};  // occluder edges met on the path
inline constexpr Rgb kPieceEdgeColour{90, 90, 90};  // the fragments' own edges
inline constexpr Rgb kOutlineColour{0, 0, 0};       // the visible region's boundary
inline constexpr Rgb kBackground{38, 41, 48};       // behind the scene

// The difference heat map's colours: black -> red -> yellow -> white as t goes 0 -> 1 (the
// preview's image and its colour scale).
inline Rgb heatColour(double t) {
    t = std::clamp(t, 0.0, 1.0) * 3;
    return {static_cast<uint8_t>(255 * std::min(t, 1.0)),
            static_cast<uint8_t>(255 * std::clamp(t - 1, 0.0, 1.0)),
            static_cast<uint8_t>(255 * std::clamp(t - 2, 0.0, 1.0))};
}

}  // namespace penumbra::viewer
