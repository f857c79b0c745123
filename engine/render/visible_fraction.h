// How much of its light an exact evaluation saw, and from that which pixels of an exact image lie
// in a penumbra: what the bench's equal-error study (engine/studies/equal_error_study.h) measures
// sampling's error over.
//
// An evaluation's visible fraction is the form factor of its light's visible fragments over that
// of the light above x's horizon (the light clipped to x's front half-space): 0 where nothing of
// it is visible, 1 where all of it is, else in between (the penumbra). It is kept as three counts
// per pixel (RenderSettings::recordVisibleFraction):
//   none   the fragments are empty (a fully hidden pair, or a query that returned nothing);
//   whole  nothing was in the pair's shaft (fully visible or horizon-clipped: no query), or the
//          fragments' form factor is at least 1 - kWholeTolerance of the clipped light's (the two
//          are sums of rounded terms, equal to some 1e-15 where a walk returns the light in
//          pieces: a shadow this small changes no pixel at the study's 0.5%);
//   part   every other exact answer.
// Not counted: the evaluations that see no light above their horizon at all (a back-facing pair,
// x behind the light's plane: the fraction is 0/0) and those over the work limit (not exact).
//
// A pixel's visible fraction is the mean of its counted evaluations' (all passes, all area
// lights); it lies strictly between 0 and 1 exactly when some evaluation saw part of its light, or
// some saw none and some all of theirs: penumbraPixel.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace penumbra {

enum class LightSeen : uint8_t { None, Part, Whole };
inline constexpr size_t kLightSeen = 3;

// Per pixel: how many counted evaluations saw each (indexed by LightSeen).
using SeenCounts = std::array<uint32_t, kLightSeen>;

inline constexpr double kWholeTolerance = 1e-9;

// The evaluation's class from the two form factors (visible: its fragments'; unoccluded: the
// light's above x's horizon, > 0).
constexpr LightSeen lightSeen(bool anyFragment, double visible, double unoccluded) {
    if (!anyFragment) return LightSeen::None;
    return visible >= (1 - kWholeTolerance) * unoccluded ? LightSeen::Whole : LightSeen::Part;
}

// Whether the pixel's visible fraction lies strictly between 0 and 1.
constexpr bool penumbraPixel(const SeenCounts& c) {
    const auto at = [&](LightSeen s) { return c[static_cast<size_t>(s)]; };
    return at(LightSeen::Part) > 0 || (at(LightSeen::None) > 0 && at(LightSeen::Whole) > 0);
}

}  // namespace penumbra
