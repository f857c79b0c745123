#include "visibility/box_tree.h"

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>

namespace penumbra::vis {

namespace {
constexpr uint32_t kLeafSize = 4;
// Subtrees over at least this many items are built concurrently (where loops are given).
constexpr uint32_t kParallelItems = 8192;

}  // namespace

// Every box of the hierarchy lies inside the root's: the planes' culling bounds are formed once
// per query for that region (PlaneBoxCull). Queries with more planes than kMaxCullPlanes use
// boxNegative per box.
bool BoxTree::outsideOne(std::span<const PlaneOrient> planes, const Bounds3& box) {
    for (const PlaneOrient& p : planes)
        if (p.boxNegative(box.lo, box.hi)) return true;
    return false;
}

BoxTree::BoxTree(std::span<const Bounds3> boxes, const std::vector<bool>& include,
                 const ParallelLoops& loops)
    : boxes_(boxes.begin(), boxes.end()) {
    std::vector<Vec3> centre(boxes.size());
    for (uint32_t f = 0; f < boxes.size(); ++f) {
        if ((!include.empty() && !include[f]) || boxes[f].empty()) continue;
        items_.push_back(f);
        centre[f] = (boxes[f].lo + boxes[f].hi) * 0.5;
    }
    if (items_.empty()) return;
    nodes_.resize(subtreeNodes(static_cast<uint32_t>(items_.size())));
    build(0, 0, static_cast<uint32_t>(items_.size()), centre, loops);
}

// A subtree over n items: one node, and above kLeafSize items the subtrees over n / 2 and
// n - n / 2 (build's split). Taken for the pair (n, n + 1) from the pair (n / 2, n / 2 + 1): the
// halves of two adjacent counts are among those two. O(log n).
uint32_t BoxTree::subtreeNodes(uint32_t items) {
    struct Pair {
        uint32_t at, next;  // the node counts of a and a + 1 items
    };
    auto pair = [](auto& self, uint32_t a) -> Pair {
        if (a + 1 <= kLeafSize) return {1, 1};
        if (a <= kLeafSize)
            return {1, 1 + self(self, (a + 1) / 2).at + self(self, (a + 1) / 2).next};
        const Pair h = self(self, a / 2);
        if (a % 2 == 0) return {1 + 2 * h.at, 1 + h.at + h.next};
        return {1 + h.at + h.next, 1 + 2 * h.next};
    };
    return pair(pair, items).at;
}

void BoxTree::build(uint32_t index, uint32_t begin, uint32_t end, const std::vector<Vec3>& centre,
                    const ParallelLoops& loops) {
    Bounds3 box, centres;
    for (uint32_t i = begin; i < end; ++i) {
        const Bounds3& b = boxes_[items_[i]];
        box.add(b.lo);
        box.add(b.hi);
        centres.add(centre[items_[i]]);
    }
    Node& node = nodes_[index];
    node.box = box;
    node.begin = begin;
    node.end = end;
    if (end - begin <= kLeafSize) return;  // a leaf (right stays 0)
    const Vec3 extent = centres.hi - centres.lo;
    const int axis =
        extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                     [&](uint32_t a, uint32_t b) { return centre[a][axis] < centre[b][axis]; });
    // The left child is index + 1, the right one follows the left's subtree.
    const uint32_t right = index + 1 + subtreeNodes(mid - begin);
    node.right = right;
    auto left = [&] { build(index + 1, begin, mid, centre, loops); };
    auto rightBuild = [&] { build(right, mid, end, centre, loops); };
    if (end - begin >= kParallelItems) {
        loops.both(left, rightBuild);
    } else {
        left();
        rightBuild();
    }
}

std::vector<uint32_t> BoxTree::numberItemsInLeafOrder() {
    if (items_.size() != boxes_.size())
        throw std::logic_error("BoxTree::numberItemsInLeafOrder: an item is left out");
    std::vector<uint32_t> old = items_;
    std::vector<Bounds3> boxes(boxes_.size());
    for (uint32_t p = 0; p < old.size(); ++p) {
        boxes[p] = boxes_[old[p]];
        items_[p] = p;
    }
    boxes_ = std::move(boxes);
    return old;
}

void BoxTree::overlapping(const Bounds3& query, std::vector<uint32_t>& out) const {
    if (nodes_.empty()) return;
    uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const Node& n = nodes_[stack[--top]];
        if (!n.box.overlaps(query)) continue;
        if (n.leaf()) {
            for (uint32_t i = n.begin; i < n.end; ++i)
                if (boxes_[items_[i]].overlaps(query)) out.push_back(items_[i]);
            continue;
        }
        // Depth is at most log2(faces / kLeafSize) + 1 (median splits): 64 levels suffice.
        stack[top++] = n.right;
        stack[top++] = static_cast<uint32_t>(&n - nodes_.data()) + 1;
    }
}

uint32_t BoxTree::notOutside(std::span<const PlaneOrient> planes, std::vector<uint32_t>& out,
                             uint64_t maxVisits) const {
    return notOutsideUnless(
        planes, [](uint32_t) { return false; }, out, maxVisits);
}

}  // namespace penumbra::vis
