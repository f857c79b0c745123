// Synthetic history trees for the tree-browser tests and benchmark: random shapes and deep chains.
// Only the structure is meaningful (edges and occluders are arbitrary ids).
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "visibility/history_tree.h"

namespace penumbra::devkit {

// `nodes` inner nodes grown by attaching each new node to a uniformly random open child slot
// (the shape of a random binary search tree: depth about 4.3 ln n at most); the slots left open
// become visible or hidden leaves at random. Node indices are shuffled (the root stays 0), so
// index order is not tree order.
inline vis::HistoryTree randomHistoryTree(uint32_t nodes, uint64_t seed) {
    std::mt19937_64 rng(seed);
    vis::HistoryTree t;
    t.kind = vis::PairKind::Penumbra;
    if (nodes == 0) return t;
    std::vector<uint32_t> label(nodes);
    std::iota(label.begin(), label.end(), 0u);
    std::shuffle(label.begin() + 1, label.end(), rng);
    t.nodes.resize(nodes);
    t.nodeOccluder.resize(nodes);
    // Open slots as (node << 1 | side); a new node fills one chosen uniformly.
    std::vector<uint32_t> open{label[0] << 1, (label[0] << 1) | 1};
    for (uint32_t k = 1; k < nodes; ++k) {
        const size_t pick = std::uniform_int_distribution<size_t>(0, open.size() - 1)(rng);
        const uint32_t slot = open[pick];
        open[pick] = open.back();
        open.pop_back();
        t.nodes[slot >> 1].child[slot & 1] = label[k];
        open.push_back(label[k] << 1);
        open.push_back((label[k] << 1) | 1);
    }
    for (uint32_t slot : open)
        t.nodes[slot >> 1].child[slot & 1] = (rng() & 1) ? vis::kVisibleLeaf : vis::kHiddenLeaf;
    for (uint32_t i = 0; i < nodes; ++i) {
        t.nodes[i].v0 = uint32_t(rng() % 1000);
        t.nodes[i].v1 = uint32_t(rng() % 1000);
        t.nodeOccluder[i] = uint32_t(rng() % 100);
    }
    t.meshVertexCount = 1000;
    return t;
}

// A chain of `nodes` nodes, node i's child on side `side(i)` being node i + 1 and its other
// child a leaf (visible for even i); the last node has two leaves. zigzag alternates the side.
inline vis::HistoryTree chainHistoryTree(uint32_t nodes, bool zigzag) {
    vis::HistoryTree t;
    t.kind = vis::PairKind::Penumbra;
    t.nodes.resize(nodes);
    for (uint32_t i = 0; i < nodes; ++i) {
        const uint32_t leaf = i % 2 == 0 ? vis::kVisibleLeaf : vis::kHiddenLeaf;
        const int side = zigzag ? int(i % 2) : 0;
        t.nodes[i].child[side] = i + 1 < nodes ? i + 1 : vis::kHiddenLeaf;
        t.nodes[i].child[1 - side] = leaf;
    }
    return t;
}

}  // namespace penumbra::devkit
