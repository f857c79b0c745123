// SilhouetteCull: per node of the light-edge hierarchy (light_edge_index.h), bounds on the planes
// of the faces its edges belong to, so that a point's edge finder (fp_query/edge_path.h) can skip
// a whole subtree when none of its edges can have a nonzero weight seen from x.
//
// Why it pays: the S_L edges near a hard point's cone are mostly no silhouette from x (on the
// motorbike 95% of those found have weight 0), and most lie in parts of the surface that x sees
// entirely from one side. An edge's weight is the sum over its uses by Front faces (the only faces
// that count, light_edge_index.h) of +-s_f, s_f the side of x against f's plane. If every Front
// face of every edge below a node has x strictly on the same side s, and each edge's Front uses
// run as often lo -> hi as hi -> lo ("balanced", fixed per edge), every weight below is
// s * 0 = 0: the node holds no chain edge and is skipped.
//
// Exact where it decides: a node is skipped only when a rigorous interval bound, in doubles, on
// the exact orient3d value of x against every one of those planes excludes zero (the bound is
// wider than the rounding of every step; see the .cpp). Where the bound cannot certify the sign,
// the node is searched as before: the cull is conservative, never a wrong skip. The point's own
// exclusions are the caller's: faces that count for nothing at this point (the receiver B, whose
// uses the weights leave out) are not known here, so the caller must not skip a node holding one
// of B's edges, and the contact rule (an occluder whose plane holds the query's input point
// counts for nothing) is the caller's too (oneSideOfEvery at that point).
//
// Only the nodes of at most kMaxBoundedItems edges are bounded: each node's bounds are taken from
// every face below it (a node's reference point is its own), so the build costs the edges times
// the levels bounded, and a node larger than that is never skipped (on the motorbike and the
// dragon no node of more than 2,047 edges ever was: a hard point's cone sees both sides of so
// large a part). The walk descends into it as into any node not skipped.
//
// Memory: 11 doubles and a flag per node of the hierarchy.
#pragma once

#include <array>
#include <cfloat>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/mesh_edges.h"
#include "visibility/parallel_loops.h"
#include "visibility/vec3.h"

namespace penumbra::vis {

class SilhouetteCull {
  public:
    // The hierarchy's items (edges) with their uses: item i's are uses[begin[i], begin[i + 1]).
    // Only the uses by counting faces count: use k's face is faces[faceOfUse[k]], or none where
    // faceOfUse[k] is kNotCounted. A counting face's plane is that of its first three vertices
    // (face_plane.h), given as indices into `vertices` (copies of the input coordinates). A use
    // may name another face than its own where that face's plane is the same three points, the
    // use turned where their order is reversed: every use's term +-s_f, and so every weight, is
    // the same (LightEdgeIndex counts a repeated triangle as its first copy so).
    struct Edges {
        std::span<const MeshEdges::Use> uses;
        std::span<const uint32_t> begin;
        std::span<const uint32_t> faceOfUse;
        std::span<const std::array<uint32_t, 3>> faces;
        std::span<const Vec3> vertices;
    };
    static constexpr uint32_t kNotCounted = UINT32_MAX;

    SilhouetteCull() = default;
    // For each node of `tree`, over `edges` (the tree's items).
    SilhouetteCull(const BoxTree& tree, const Edges& edges, const ParallelLoops& loops = {});

    bool empty() const { return nodes_.empty(); }
    size_t bytes() const { return nodes_.capacity() * sizeof(Node); }

    // True only if every Front face of every edge below `node` has p strictly on the same side of
    // its plane, and every edge below is balanced: then each edge's weight seen from p is zero.
    bool noSilhouetteFrom(uint32_t node, const Vec3& p) const {
        const Node& n = nodes_[node];
        return n.balanced && oneSide(n, p);
    }
    // True only if p lies strictly on one side of every Front face's plane below (the same side
    // for all): off every one of them, as the contact rule's check at a moved query's input
    // needs.
    bool oneSideOfEvery(uint32_t node, const Vec3& p) const { return oneSide(nodes_[node], p); }
    // Every node's bounds equal (a build given ParallelLoops against a serial one).
    bool operator==(const SilhouetteCull&) const = default;
    static constexpr size_t kMaxBoundedItems = 4096;

  private:
    struct Node {
        double c[3] = {0, 0, 0};    // the node's reference point (its box's centre, rounded)
        double nlo[3] = {0, 0, 0};  // bounds on every exact normal (b - a) x (c - a) below
        double nhi[3] = {0, 0, 0};
        double elo = 1, ehi = 1;  // bounds on every exact (c - a) . N below
        bool balanced = false;    // every edge below balanced over its Front uses
        bool operator==(const Node&) const = default;
    };
    static bool oneSide(const Node& n, const Vec3& p);

    std::vector<Node> nodes_;
};

inline bool SilhouetteCull::oneSide(const Node& n, const Vec3& p) {
    // Every exact value below is (p - c) . N + E with N in [nlo, nhi] and E in [elo, ehi]
    // (rigorous, built so). With t = p - c rounded (|t* - t| <= u |t|), the exact value lies in
    // [sum min(t_i nlo_i, t_i nhi_i) + elo, sum max(...) + ehi] up to u |t_i| max|N_i| per term,
    // and the rounded sums here are off by at most 4u (|E| + sum |t_i| max|N_i|): the margin 8u
    // times that covers both (and 2^-1060 any underflow). NaN or infinity: false.
    constexpr double u = DBL_EPSILON / 2;
    const double t[3] = {p.x - n.c[0], p.y - n.c[1], p.z - n.c[2]};
    double lo = n.elo, hi = n.ehi;
    double reach = std::fabs(n.elo) > std::fabs(n.ehi) ? std::fabs(n.elo) : std::fabs(n.ehi);
    for (int i = 0; i < 3; ++i) {
        const double a = t[i] * n.nlo[i], b = t[i] * n.nhi[i];
        lo += a < b ? a : b;
        hi += a < b ? b : a;
        const double l = std::fabs(n.nlo[i]), h = std::fabs(n.nhi[i]);
        reach += std::fabs(t[i]) * (l > h ? l : h);
    }
    const double margin = 8 * u * reach + 0x1p-1060;
    return lo - margin > 0 || hi + margin < 0;
}

}  // namespace penumbra::vis
