// Nearest-rank quantiles of a sample: the k-th smallest value, k = ceil(q * n) (at least 1), an
// order statistic of the sample itself, never an interpolation or a bucket. Used wherever a
// median or a 99th percentile is reported: the studies' timings and the renderer's
// per-evaluation costs (engine/render/cost_samples.h).
#pragma once

#include <vector>

namespace penumbra {

// The values below which half, 99% and all of a sample lie.
struct Quantiles {
    double median = 0, p99 = 0, max = 0;
};

// Zeros for an empty sample.
Quantiles quantiles(std::vector<double> v);

}  // namespace penumbra
