// Closed forms the tests compare against: hand-derived references, independent of the code.
#pragma once

#include <cmath>
#include <numbers>

namespace penumbra::test {

// Form factor from a differential area to an a x b rectangle in a parallel plane at distance c,
// with one corner directly above the differential area (the classic closed form, e.g. Howell's
// catalogue of configuration factors, C-11).
inline double cornerFormFactor(double a, double b, double c) {
    const double x = a / c, y = b / c;
    const double sx = std::sqrt(1 + x * x), sy = std::sqrt(1 + y * y);
    return (x / sx * std::atan(y / sx) + y / sy * std::atan(x / sy)) / (2 * std::numbers::pi);
}

}  // namespace penumbra::test
