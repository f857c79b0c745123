// FaceBoxTree: a bounding-volume hierarchy over the axis-aligned boxes of a mesh's faces, for
// "which face boxes meet this box" queries (the shaft candidates of a receiver/light pair).
//
// Exact: node boxes are unions (min / max, no rounding) of the double face boxes below them, and
// every test is the closed-box overlap test in doubles, so a query returns exactly the faces a
// loop over all faces would (touching counts). Built by median splits of the face centres along
// the widest axis, leaves of at most 4 faces: O(log faces + faces reported) per query when the
// reported faces are clustered, as they are for a shaft.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "visibility/bounds3.h"

namespace penumbra {

class FaceBoxTree {
  public:
    FaceBoxTree() = default;
    // boxes[f] is face f's box; faces with include[f] == false are left out of every answer.
    FaceBoxTree(std::span<const vis::Bounds3> boxes, const std::vector<bool>& include);

    // Appends to `out` every included face whose box meets `query` (closed), in no order.
    void overlapping(const vis::Bounds3& query, std::vector<uint32_t>& out) const;

  private:
    struct Node {
        vis::Bounds3 box;
        uint32_t first = 0;  // leaf: first index into faces_; inner: index of the right child
        uint32_t count = 0;  // leaf: number of faces (> 0); inner: 0 (left child = this + 1)
    };
    uint32_t build(uint32_t begin, uint32_t end, std::vector<vis::Vec3>& centre);

    std::vector<Node> nodes_;
    std::vector<uint32_t> faces_;      // face ids, grouped by leaf
    std::vector<vis::Bounds3> boxes_;  // per face id
};

}  // namespace penumbra
