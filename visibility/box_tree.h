// BoxTree: a bounding-volume hierarchy over axis-aligned boxes (of faces, of deferred occluders),
// for two queries: which boxes meet a box (the shaft candidates of a receiver/light pair), and
// which boxes are not certainly outside a set of planes (the occluders that may meet the pyramid
// from a query point over a light).
//
// Node boxes are unions (min / max, no rounding) of the double boxes below them. The box query is
// the closed-box overlap test in doubles, so it returns exactly the items a loop over all items
// would (touching counts). The plane query skips a box only when it is proven strictly outside a
// plane (PlaneBoxCull, bounded once for the root's box, or PlaneOrient::boxNegative): certain,
// never a wrong skip. Built by median splits of the box
// centres along the widest axis, leaves of at most 4 items: O(log n + reported) per query when
// the reported items are clustered. Subtrees of many items are built concurrently where the
// caller gives ParallelLoops: each subtree's nodes have fixed places (a subtree's node count
// follows from its item count alone), so the hierarchy is the same whoever builds which part.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/bounds3.h"
#include "visibility/parallel_loops.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

class BoxTree {
  public:
    BoxTree() = default;
    // boxes[i] is item i's box; items with include[i] == false (when include is given) and items
    // with an empty box are left out of every answer.
    explicit BoxTree(std::span<const Bounds3> boxes, const std::vector<bool>& include = {},
                     const ParallelLoops& loops = {});

    bool empty() const { return nodes_.empty(); }
    // The memory it holds (nodes, items, boxes), in bytes.
    size_t bytes() const {
        return nodes_.capacity() * sizeof(Node) + items_.capacity() * sizeof(uint32_t) +
               boxes_.capacity() * sizeof(Bounds3);
    }

    // Renumbers the items in the order the leaves hold them (the p-th item of the leaves becomes
    // item p, its box with it) and returns each new item's old id. The hierarchy is unchanged: a
    // query visits the same nodes in the same order and finds the same boxes, as new ids, which
    // now increase along the leaves (a caller that keeps its per-item data in that order reads it
    // in order). Every item must be in the hierarchy (none left out by `include` or an empty box).
    std::vector<uint32_t> numberItemsInLeafOrder();

    // Appends to `out` every item whose box meets `query` (closed), in no order.
    void overlapping(const Bounds3& query, std::vector<uint32_t>& out) const;
    // Appends to `out` every item whose box is not certainly outside one of `planes` (strictly on
    // its negative side), in no order. Returns the nodes visited (the query's cost); stops early,
    // with an incomplete answer, once more than maxVisits nodes were visited (0 = no limit).
    uint32_t notOutside(std::span<const PlaneOrient> planes, std::vector<uint32_t>& out,
                        uint64_t maxVisits = 0) const;
    // The same, less the nodes for which `skip(node)` is true (checked after the planes, a
    // node's items left out whole): for a caller that can prove a subtree holds nothing it wants
    // (silhouette_cull.h). The visit count includes the skipped nodes.
    template <class Skip>
    uint32_t notOutsideUnless(std::span<const PlaneOrient> planes, Skip&& skip,
                              std::vector<uint32_t>& out, uint64_t maxVisits = 0) const;
    // The same items, each passed to `stop(item)` as it is found (in no order) until one call
    // returns true: then the search ends and returns true. `visited` gets the nodes visited.
    // For "is any of them hit": the first hit ends the search. Planes beyond kMaxCullPlanes are
    // not used (fewer skips: still sound).
    template <class Stop>
    bool anyNotOutside(std::span<const PlaneOrient> planes, Stop&& stop, uint32_t& visited) const;
    static constexpr size_t kMaxCullPlanes = 32;

    // The hierarchy itself, for walks of its own (face_clusters.h): node 0 is the root, an inner
    // node's children are node + 1 and rightChild(node), and every node's items (those of the
    // leaves below it) are contiguous: nodeItems(node).
    uint32_t nodeCount() const { return static_cast<uint32_t>(nodes_.size()); }
    const Bounds3& nodeBox(uint32_t node) const { return nodes_[node].box; }
    bool isLeaf(uint32_t node) const { return nodes_[node].leaf(); }
    uint32_t rightChild(uint32_t node) const { return nodes_[node].right; }
    std::span<const uint32_t> nodeItems(uint32_t node) const {
        return {items_.data() + nodes_[node].begin, nodes_[node].end - nodes_[node].begin};
    }
    const Bounds3& itemBox(uint32_t item) const { return boxes_[item]; }
    // The first N of `planes` as culling bounds over the root's box, in `out` (planes left out
    // cull nothing: still sound). The hierarchy must not be empty.
    template <size_t N>
    std::span<const PlaneBoxCull> cullPlanes(std::span<const PlaneOrient> planes,
                                             std::array<PlaneBoxCull, N>& out) const {
        const size_t count = std::min(planes.size(), N);
        const Bounds3& region = nodes_[0].box;
        for (size_t i = 0; i < count; ++i) out[i] = PlaneBoxCull(planes[i], region.lo, region.hi);
        return {out.data(), count};
    }
    // Whether a box of the hierarchy (inside the root's) is certainly outside one of them.
    static bool outsideOne(std::span<const PlaneBoxCull> planes, const Bounds3& box) {
        for (const PlaneBoxCull& p : planes)
            if (p.negative(box.lo, box.hi)) return true;
        return false;
    }

    // The same with PlaneOrient::boxNegative per box (any box): the test notOutside makes of each
    // box when the planes are too many to bound.
    static bool outsideOne(std::span<const PlaneOrient> planes, const Bounds3& box);

  private:
    struct Node {
        Bounds3 box;
        uint32_t right = 0;           // inner: the right child (the left one is this + 1); leaf: 0
        uint32_t begin = 0, end = 0;  // the items below it: items_[begin, end)
        bool leaf() const { return right == 0; }  // (the root is no node's child)
    };
    // Builds the subtree of items_[begin, end) at nodes_[index] (its nodes: the next
    // subtreeNodes(end - begin) places, preorder).
    void build(uint32_t index, uint32_t begin, uint32_t end, const std::vector<Vec3>& centre,
               const ParallelLoops& loops);
    static uint32_t subtreeNodes(uint32_t items);
    // notOutsideUnless with PlaneOrient (boxNegative per box) or PlaneBoxCull planes.
    template <class Plane, class Skip>
    uint32_t notOutsideWith(std::span<const Plane> planes, Skip& skip, std::vector<uint32_t>& out,
                            uint64_t maxVisits) const;

    std::vector<Node> nodes_;
    std::vector<uint32_t> items_;  // item ids, grouped by leaf
    std::vector<Bounds3> boxes_;   // per item id
};

template <class Stop>
bool BoxTree::anyNotOutside(std::span<const PlaneOrient> planes, Stop&& stop,
                            uint32_t& visited) const {
    visited = 0;
    if (nodes_.empty()) return false;
    std::array<PlaneBoxCull, kMaxCullPlanes> cull;
    const std::span<const PlaneBoxCull> c = cullPlanes(planes, cull);
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        ++visited;
        if (outsideOne(c, n.box)) continue;
        if (n.leaf()) {
            for (uint32_t i = n.begin; i < n.end; ++i)
                if (!outsideOne(c, boxes_[items_[i]]) && stop(items_[i])) return true;
            continue;
        }
        stack[top++] = n.right;
        stack[top++] = static_cast<uint32_t>(&n - nodes_.data()) + 1;
    }
    return false;
}

template <class Skip>
uint32_t BoxTree::notOutsideUnless(std::span<const PlaneOrient> planes, Skip&& skip,
                                   std::vector<uint32_t>& out, uint64_t maxVisits) const {
    if (nodes_.empty()) return 0;
    if (planes.size() <= kMaxCullPlanes) {
        std::array<PlaneBoxCull, kMaxCullPlanes> cull;
        return notOutsideWith(cullPlanes(planes, cull), skip, out, maxVisits);
    }
    return notOutsideWith(planes, skip, out, maxVisits);
}

template <class Plane, class Skip>
uint32_t BoxTree::notOutsideWith(std::span<const Plane> planes, Skip& skip,
                                 std::vector<uint32_t>& out, uint64_t maxVisits) const {
    uint32_t visited = 0;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        if (maxVisits != 0 && visited > maxVisits) break;
        const uint32_t index = stack[--top];
        const Node& n = nodes_[index];
        ++visited;
        if (outsideOne(planes, n.box) || skip(index)) continue;
        if (n.leaf()) {
            for (uint32_t i = n.begin; i < n.end; ++i)
                if (!outsideOne(planes, boxes_[items_[i]])) out.push_back(items_[i]);
            continue;
        }
        stack[top++] = n.right;
        stack[top++] = index + 1;
    }
    return visited;
}

}  // namespace penumbra::vis
