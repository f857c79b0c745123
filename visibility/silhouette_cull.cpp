#include "visibility/silhouette_cull.h"

#include <algorithm>

#include "visibility/face_plane.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

namespace {

// A counting face's plane as PlaneOrient rounds it (a, the rounded normal n, its permanent).
struct RoundedPlane {
    Vec3 a;
    double n[3] = {0, 0, 0}, perm[3] = {0, 0, 0};
};

}  // namespace

SilhouetteCull::SilhouetteCull(const BoxTree& tree, const Edges& edges,
                               const ParallelLoops& loops) {
    constexpr double u = DBL_EPSILON / 2;
    // Each counting face's rounded plane, once.
    std::vector<RoundedPlane> planes(edges.faces.size());
    loops.run(edges.faces.size(), 8192, [&](size_t begin, size_t end) {
        for (size_t f = begin; f < end; ++f) {
            const PlaneOrient p = facePlane(edges.vertices, edges.faces[f]).orient();
            planes[f].a = p.a;
            for (int i = 0; i < 3; ++i) {
                planes[f].n[i] = p.n[i];
                planes[f].perm[i] = p.perm[i];
            }
        }
    });
    // Each item's balance over its counting uses.
    const size_t items = edges.begin.empty() ? 0 : edges.begin.size() - 1;
    std::vector<uint8_t> balanced(items, 0);
    loops.run(items, 8192, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) {
            int sum = 0;
            for (uint32_t k = edges.begin[i]; k < edges.begin[i + 1]; ++k) {
                if (edges.faceOfUse[k] != kNotCounted) sum += edges.uses[k].forward ? 1 : -1;
            }
            balanced[i] = sum == 0;
        }
    });

    // Each node from all the counting uses below it (a node's items are contiguous ids). The
    // bounds, rigorous for the exact values (u the unit roundoff):
    //  - N_i = n_i +- 8u perm_i (PlaneOrient's claim); n_i -+ 10u perm_i, rounded, lies beyond
    //    that (the subtraction's rounding is at most u (|n_i| + 10u perm_i), |n_i| <= (1+u)
    //    perm_i).
    //  - E = (c - a) . N: with d = c - a rounded, the exact E differs from d . n by at most
    //    sum |c_i - a_i| (8u perm_i + u |n_i|) plus the rounded products and sum (3u sum |d_i
    //    n_i|): under 12.1u sum |d_i| perm_i; 20u covers that and the rounding of e -+ bound.
    nodes_.resize(tree.nodeCount());
    loops.run(tree.nodeCount(), 256, [&](size_t begin, size_t end) {
        for (size_t index = begin; index < end; ++index) {
            const uint32_t node = static_cast<uint32_t>(index);
            Node& out = nodes_[node];
            const Bounds3& box = tree.nodeBox(node);
            out.c[0] = box.lo.x + (box.hi.x - box.lo.x) * 0.5;
            out.c[1] = box.lo.y + (box.hi.y - box.lo.y) * 0.5;
            out.c[2] = box.lo.z + (box.hi.z - box.lo.z) * 0.5;
            bool any = false, allBalanced = true;
            if (tree.nodeItems(node).size() > kMaxBoundedItems) {
                // Never certain (N = 0, E in [-1, 1]: every bound straddles zero).
                out.elo = -1;
                continue;
            }
            for (uint32_t item : tree.nodeItems(node)) {
                allBalanced = allBalanced && balanced[item];
                for (uint32_t k = edges.begin[item]; k < edges.begin[item + 1]; ++k) {
                    const uint32_t f = edges.faceOfUse[k];
                    if (f == kNotCounted) continue;
                    const RoundedPlane& p = planes[f];
                    const double d[3] = {out.c[0] - p.a.x, out.c[1] - p.a.y, out.c[2] - p.a.z};
                    const double e = d[0] * p.n[0] + d[1] * p.n[1] + d[2] * p.n[2];
                    const double bound =
                        20 * u *
                            (std::fabs(d[0]) * p.perm[0] + std::fabs(d[1]) * p.perm[1] +
                             std::fabs(d[2]) * p.perm[2]) +
                        0x1p-1060;
                    double lo[3], hi[3];
                    for (int i = 0; i < 3; ++i) {
                        lo[i] = p.n[i] - 10 * u * p.perm[i];
                        hi[i] = p.n[i] + 10 * u * p.perm[i];
                    }
                    if (!any) {
                        any = true;
                        out.elo = e - bound;
                        out.ehi = e + bound;
                        for (int i = 0; i < 3; ++i) {
                            out.nlo[i] = lo[i];
                            out.nhi[i] = hi[i];
                        }
                        continue;
                    }
                    out.elo = std::min(out.elo, e - bound);
                    out.ehi = std::max(out.ehi, e + bound);
                    for (int i = 0; i < 3; ++i) {
                        out.nlo[i] = std::min(out.nlo[i], lo[i]);
                        out.nhi[i] = std::max(out.nhi[i], hi[i]);
                    }
                }
            }
            // No counting use below: every weight is zero whatever the point; the defaults
            // (N = 0, E = 1) say "strictly positive" everywhere.
            out.balanced = allBalanced;
        }
    });
}

}  // namespace penumbra::vis
