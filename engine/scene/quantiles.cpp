#include "engine/scene/quantiles.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace penumbra {

Quantiles quantiles(std::vector<double> v) {
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    auto rank = [&](double q) {
        const size_t k = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
        return v[std::clamp<size_t>(k, 1, v.size()) - 1];
    };
    return {rank(0.5), rank(0.99), v.back()};
}

}  // namespace penumbra
