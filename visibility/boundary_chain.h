// BoundaryChain: the edges of a set of occluder faces, seen from a point x, that can bound a
// shadow: those that do not cancel between the faces sharing them.
//
// Seen from x, a face in front of which x lies projects counter-clockwise and one behind which x
// lies clockwise. Give each face the weight s = +1 or -1 accordingly; then the number of faces a
// line from x crosses, c(y) for the line through y, is the winding number about y of the chain
// sum_f s_f * (boundary of f) (each face's projection adds s_f times its own winding, +1 on its
// inside). An edge shared by two faces of a consistently oriented surface that both face x, or
// both face away, appears with opposite directions and cancels; so does any set of uses of one
// edge whose signed directions sum to zero (non-manifold edges, inconsistent orientation). Across
// a cancelled edge c does not change, so only the remaining edges (silhouettes relative to x,
// borders of open surfaces, edges where a face was left out, chords of a clip) can bound the
// region where c = 0, the part of the light that is seen. Exact: the weights are exact orient3d
// signs and edges are identified by their mesh vertex ids (faces that share an edge must share
// its vertices; a mesh with duplicated vertices only cancels less).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra::vis {

class BoundaryChain {
  public:
    void clear() { uses_.clear(); }
    // One use of the directed edge v0 -> v1 by a face of weight `side` (+1 or -1); `ref` is
    // returned for the edge if it does not cancel (the first use's, in the order of add()).
    void add(uint32_t v0, uint32_t v1, int side, uint32_t ref) {
        const bool forward = v0 < v1;
        uses_.push_back({forward ? v0 : v1, forward ? v1 : v0, forward ? side : -side, ref});
    }
    size_t uses() const { return uses_.size(); }
    // The refs of the edges whose uses do not sum to zero, in the order of their first use,
    // and each one's sum: the weight of the edge directed from its lower vertex id to its higher
    // (c(y) grows by it when y passes from the positive to the negative side of the plane
    // through x, the lower and the higher vertex, across the edge). The uses are summed per
    // edge in a hash table: O(n), no sort.
    void remaining(std::vector<uint32_t>& refs, std::vector<int>& weights);

  private:
    struct Use {
        uint32_t lo, hi;
        int weight;
        uint32_t ref;
    };
    std::vector<Use> uses_;
    // remaining()'s table, open addressing: per slot the edge's packed (lo, hi) key (kEmpty when
    // free) and the index of its first use in uses_, whose weight becomes the sum (the later
    // uses' become 0; a second call sums again to the same).
    static constexpr uint64_t kEmpty = ~uint64_t{0};
    std::vector<uint64_t> keys_;
    std::vector<uint32_t> first_;
};

}  // namespace penumbra::vis
