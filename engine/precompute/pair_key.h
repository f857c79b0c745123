// PairKey: the name of one history tree of a scene, a (receiver face, receiver patch, light face)
// triple, and its hash. The patch field also encodes the sub-patches of query-driven refinement
// (patch_layout.h says how); the store keys its trees by it (visibility_store.h).
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>

namespace penumbra {

struct PairKey {
    uint32_t receiver = 0;   // receiver face
    uint32_t patch = 0;      // patch of the receiver (0 for a face that is one patch)
    uint32_t lightFace = 0;  // light face (not the light number)
    auto operator<=>(const PairKey&) const = default;
};

// The hash of a PairKey for unordered containers (the store's shards, the scheduler's batch, the
// renderer's pair sets).
struct PairKeyHash {
    size_t operator()(const PairKey& k) const noexcept;
};

}  // namespace penumbra
