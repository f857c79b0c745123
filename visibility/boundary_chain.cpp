#include "visibility/boundary_chain.h"

#include <algorithm>
#include <bit>

namespace penumbra::vis {

void BoundaryChain::remaining(std::vector<uint32_t>& refs, std::vector<int>& weights) {
    refs.clear();
    weights.clear();
    // A power of two at least twice the uses: short probe runs. (Uses are added in order, so
    // the first use of an edge is the one that claims its slot: its ref and order are the edge's.)
    const size_t size = std::bit_ceil(std::max<size_t>(16, 2 * uses_.size()));
    keys_.assign(size, kEmpty);
    first_.resize(size);
    const size_t mask = size - 1;
    for (uint32_t u = 0; u < uses_.size(); ++u) {
        const uint64_t key = (uint64_t{uses_[u].lo} << 32) | uses_[u].hi;
        size_t slot = static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & mask;
        while (keys_[slot] != kEmpty && keys_[slot] != key) slot = (slot + 1) & mask;
        if (keys_[slot] == kEmpty) {
            keys_[slot] = key;
            first_[slot] = u;
        } else {
            uses_[first_[slot]].weight += uses_[u].weight;
            uses_[u].weight = 0;
        }
    }
    // The first uses now carry their edge's sum; the others 0. In the order of add().
    for (const Use& use : uses_) {
        if (use.weight == 0) continue;
        refs.push_back(use.ref);
        weights.push_back(use.weight);
    }
}

}  // namespace penumbra::vis
