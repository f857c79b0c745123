#include "visibility/boundary_chain.h"

#include <algorithm>

namespace penumbra::vis {

void BoundaryChain::remaining(std::vector<uint32_t>& refs, std::vector<int>& weights) {
    refs.clear();
    weights.clear();
    std::sort(uses_.begin(), uses_.end(), [](const Use& a, const Use& b) {
        return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.order < b.order;
    });
    kept_.clear();
    for (size_t i = 0; i < uses_.size();) {
        size_t j = i;
        int weight = 0;
        for (; j < uses_.size() && uses_[j].lo == uses_[i].lo && uses_[j].hi == uses_[i].hi; ++j)
            weight += uses_[j].weight;
        if (weight != 0) kept_.push_back({uses_[i].order, uses_[i].ref, weight});
        i = j;
    }
    std::sort(kept_.begin(), kept_.end(),
              [](const Kept& a, const Kept& b) { return a.order < b.order; });
    for (const Kept& k : kept_) {
        refs.push_back(k.ref);
        weights.push_back(k.weight);
    }
}

}  // namespace penumbra::vis
