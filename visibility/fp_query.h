// FPQuery (Mora & Aveneau 2005, Algorithm 2): the exactly visible fragments of the light L from a
// point x on the receiver B, by walking B's history tree with the 3D plane through x and each
// stored edge and clipping L.
//
// Two interfaces: FromPointQuery is a reusable workspace for hot loops (a renderer thread keeps
// one; after warm-up a query allocates nothing); fromPointQuery() is the one-shot convenience.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "visibility/history_tree.h"
#include "visibility/polygon_clip.h"
#include "visibility/region_decisions.h"

namespace penumbra::vis {

using Polygon3 = std::vector<Vec3>;

// Convex polygons stored back to back.
class FragmentList {
  public:
    size_t size() const { return begin_.size() - 1; }
    bool empty() const { return size() == 0; }
    std::span<const Vec3> operator[](size_t i) const {
        return {vertices_.data() + begin_[i], begin_[i + 1] - begin_[i]};
    }
    void clear() {
        vertices_.clear();
        begin_.assign(1, 0);
    }
    void add(std::span<const Vec3> polygon) {
        vertices_.insert(vertices_.end(), polygon.begin(), polygon.end());
        begin_.push_back(static_cast<uint32_t>(vertices_.size()));
    }

  private:
    std::vector<Vec3> vertices_;
    std::vector<uint32_t> begin_{0};
};

// How FromPointQuery decides the side of each vertex (for measuring what exactness costs; the
// product always uses Filtered).
enum class PredicateMode : uint8_t {
    Filtered,     // exact for L's vertices, filtered for constructed ones (polygon_clip.h)
    AlwaysExact,  // every sign through the exact stage, no filter
    Naive,        // the plain double determinant's sign: approximate, can be wrong
};

// A reusable FPQuery. Not thread-safe: one per thread.
class FromPointQuery {
  public:
    explicit FromPointQuery(PredicateMode mode = PredicateMode::Filtered) : mode_(mode) {}

    // The visible fragments of tree.light from x (x should lie on the receiver face; it is not
    // projected): disjoint convex parts of L, counter-clockwise as L. Applies the receiver's front
    // hemisphere and the light's one-sided emission: a point behind the light gets no fragment.
    // When `path` is given, the visited node ids are appended in depth-first order. The result is
    // valid until the next run. A TooComplex tree answers nothing (no fragment): callers check
    // tree.kind and estimate such a pair otherwise.
    // `region`, when given, must have been reset for this tree and a region holding x: nodes it
    // decides for the whole region are followed without a plane test (region_decisions.h).
    const FragmentList& run(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x,
                            std::vector<uint32_t>* path = nullptr,
                            RegionDecisions* region = nullptr);
    uint32_t nodesVisited() const { return nodesVisited_; }

  private:
    void preparePair(const PolygonMesh& mesh, const HistoryTree& tree);
    void visit(uint32_t node, std::span<const Vec3> poly, size_t depth);

    PredicateMode mode_;
    const PolygonMesh* mesh_ = nullptr;
    const HistoryTree* tree_ = nullptr;
    Vec3 x_;
    std::vector<uint32_t>* path_ = nullptr;
    RegionDecisions* region_ = nullptr;
    uint32_t nodesVisited_ = 0;
    FragmentList fragments_;
    // The pair's part that does not depend on x (preparePair): L's vertices, its plane, L clipped
    // to B's front half-space, and what identifies them.
    const PolygonMesh* preparedMesh_ = nullptr;
    uint32_t preparedReceiver_ = 0, preparedLight_ = 0;
    Vec3 receiverPlane_[3];
    PlaneOrient lightPlane_;
    std::vector<Vec3> light_, lightClipped_, discard_;
    // The split parts per recursion depth, reused along the walk and across runs.
    std::vector<SplitParts> parts_;
};

struct FromPointResult {
    std::vector<Polygon3> fragments;  // disjoint convex parts of L visible from x (CCW as L)
    std::vector<uint32_t> path;       // node ids visited, in depth-first order
    uint32_t nodesVisited = 0;
};

// One-shot FromPointQuery::run with the path recorded.
FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x);

}  // namespace penumbra::vis
