// The boundary chain of a from-point query's occluders (boundary_chain.h): the occluder edges
// whose weighted uses do not cancel (closed and smooth surfaces leave their silhouette and
// border), with the silhouette path's kept edges and the face groups' boundaries, kept where
// they may meet L's cone. ChainCells cuts L by it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "visibility/boundary_chain.h"
#include "visibility/fp_query/from_point_query.h"

namespace penumbra::vis {

struct QueryParts;

class ChainBuild {
  public:
    // An edge of the chain: its plane (a ref, active_occluders.h) and, for an input edge, the
    // whole input segment (which contains the clipped one).
    struct Edge {
        uint32_t ref = 0;
        bool segment = false;
        // An input edge with an end point strictly behind B's plane (exact): its face is cut by
        // B's plane and c(y) changes only across its part in front (ChainCells).
        bool behindB = false;
        Vec3 a, b;
        // How c(y) changes when y passes from the positive to the negative side of the ref's
        // plane across the segment (the edge's weight, boundary_chain.h; 0 for a chord, whose
        // jump is not known: a path may cross its plane only where that is shown not to matter).
        int jump = 0;
    };

    explicit ChainBuild(QueryParts& q) : q_(q) {}

    void reset() {
        built_ = false;
        crossings_ = false;
        counts_ = {};
    }
    // Whether what reaches a visible leaf is cut by the chain (built at the first ask) rather
    // than clipped by Algorithm 1: on the silhouette path and with face groups always, else where
    // there are enough occluders and enough of their edges cancel (ChainOptions).
    bool use();

    const std::vector<Edge>& edges() const { return chain_; }
    const Edge& operator[](size_t i) const { return chain_[i]; }
    // A chord (of unknown jump) is in the chain.
    bool hasChords() const { return chords_; }
    // x on or in front of B's plane and some chord on B's plane left out of the chain: a cell is
    // labelled only from a point strictly in front of B's plane.
    bool chordsOnBLeftOut() const { return chordsOnBLeftOut_; }
    // Cells may be labelled by crossings (ChainCells::countByCrossings): no occluder cut by L's
    // plane, and a long enough chain.
    bool crossings() const { return crossings_; }
    ChainCounts& counts() { return counts_; }
    const ChainCounts& counts() const { return counts_; }

  private:
    void build();
    // build() on the light-edge path (edge_path.h).
    void buildFromLightEdges();
    // The uses of the active occluders' edges, the silhouette path's kept edges in the cone and
    // the used face groups' boundaries, into builder_ (uses returns the silhouette uses summed
    // outside it); false when the work limit stopped it.
    bool addUses(uint32_t& surfaceUses);
    // The remaining group and silhouette edges get their planes through x (the others never do).
    void planesForRemaining();
    // The remaining edges that may meet L's open cone, into ChainCells' root list, in the order
    // the cells are cut.
    void keepEdgesInCone();
    void orderRoot(std::vector<uint32_t>& root);

    // Above the ids of a ref: a silhouette use (its index in DeferredSilhouettes::uses) or a face
    // group boundary edge (its index in clusterEdges_), before their planes are made.
    static constexpr uint32_t kSurfaceRef = 0x40000000u;
    static constexpr uint32_t kClusterRef = 0x20000000u;
    // A chain of kLongestFirstMin edges or more cuts along its longest edges first.
    static constexpr size_t kLongestFirstMin = 32;

    QueryParts& q_;
    bool built_ = false, pays_ = false;
    bool chords_ = false, chordsOnBLeftOut_ = false, crossings_ = false;
    std::vector<Edge> chain_;
    BoundaryChain builder_;
    std::vector<uint32_t> refs_;
    std::vector<int> weights_;  // per ref, its weight from the lower vertex id
    std::vector<uint32_t> surfaceRemaining_;
    std::vector<int> surfaceSums_;  // per surfaceRemaining_, its weight
    std::vector<std::pair<uint32_t, uint32_t>> clusterEdges_;
    std::vector<std::pair<double, uint32_t>> orderKeys_;
    ChainCounts counts_;
};

}  // namespace penumbra::vis
