#include "engine/precompute/pair_key.h"

#include <initializer_list>

namespace penumbra {

size_t PairKeyHash::operator()(const PairKey& k) const noexcept {
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (uint32_t v : {k.receiver, k.patch, k.lightFace}) {
        h ^= v;
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return static_cast<size_t>(h);
}

}  // namespace penumbra
