#include "engine/render/cost_samples.h"

namespace penumbra {

void CostSamples::thin() {
    size_t n = 0;
    for (size_t i = 0; i < kept_.size(); i += 2) kept_[n++] = kept_[i];
    kept_.resize(n);
    stride_ *= 2;
}

CostSamples& CostSamples::operator+=(const CostSamples& o) {
    while (stride_ < o.stride_) thin();
    const uint64_t step = stride_ / o.stride_;  // strides are powers of two
    for (size_t i = 0; i < o.kept_.size(); i += step) kept_.push_back(o.kept_[i]);
    count_ += o.count_;
    sum_ += o.sum_;
    while (kept_.size() > kCapacity) thin();
    return *this;
}

Quantiles CostSamples::quantiles() const {
    return penumbra::quantiles(std::vector<double>(kept_.begin(), kept_.end()));
}

}  // namespace penumbra
