// What a from-point query answers: the visible fragments of the light (FragmentList), and the
// walk's trace (TraceStep: the nodes visited and the side each sent the light polygon to).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/vec3.h"

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
    // The polygons, each copied into its own vector (what outlives the query's next run).
    std::vector<Polygon3> polygons() const {
        std::vector<Polygon3> out;
        out.reserve(size());
        for (size_t i = 0; i < size(); ++i) out.emplace_back((*this)[i].begin(), (*this)[i].end());
        return out;
    }

  private:
    std::vector<Vec3> vertices_;
    std::vector<uint32_t> begin_{0};
};

// Where a visited node sent the light polygon: the positive side of the plane through x and the
// node's edge (child[0]), the negative side (child[1]), both (the plane split it in two), or none
// strictly (every vertex in the plane: x on the edge's line; it follows child[0] whole, a
// measure-zero set of points, documented rule).
enum class NodeSide : uint8_t { Positive, Negative, Both, OnPlane };
const char* toString(NodeSide side);

// One visited node of a walk (FromPointQuery::run's trace): the node, its depth in the tree (0 at
// the root) and where the polygon went. A node decided for a whole region (RegionDecisions)
// records the side it decided.
struct TraceStep {
    uint32_t node = 0;
    uint32_t depth = 0;
    NodeSide side = NodeSide::Positive;
};

// The node ids of a trace, in its order (e.g. the path to highlight in a tree browser).
std::vector<uint32_t> traceNodes(std::span<const TraceStep> trace);

}  // namespace penumbra::vis
