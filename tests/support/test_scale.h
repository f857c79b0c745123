// How much work the heavy tests do: PENUMBRA_TEST_SCALE (default 1) multiplies their point
// counts, so the sanitizer run in CI can do a quarter of the work with the same assertions.
#pragma once

#include <algorithm>
#include <cstdlib>

namespace penumbra::test {

inline int scaled(int count) {
    const char* s = std::getenv("PENUMBRA_TEST_SCALE");
    const double f = s ? std::atof(s) : 1.0;
    return std::max(1, static_cast<int>(count * (f > 0 ? f : 1.0)));
}

}  // namespace penumbra::test
