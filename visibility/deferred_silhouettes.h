// DeferredSilhouettes: a partial tree's deferred occluders as a surface: their edges grouped by
// the faces that share them, for the boundary chain (boundary_chain.h) of each query point
// without activating every face in its pyramid.
//
// Seen from a point x, an edge shared by faces that both face x (or both face away) cancels in
// the boundary chain: the number of faces a line from x crosses does not change across it. Which
// way a face faces x is the exact sign of its plane at x. So the query needs, per point, only the
// sign of each face near its cone (one orient3d) and, per edge, the sum of its uses' signed
// directions: no per-point clip, no sort. Over a box Q around the tree's receiver patch, a
// face's sign is constant when it is the same at Q's eight corners (the plane's value is affine
// in x): then the query does not even take it, and an edge whose faces all have such a sign and
// cancel is dropped here, for every point of Q. (Near the occluders, large patches decide few
// faces: the planes of most faces of a mesh standing on the floor cross the floor's patch.)
//
// What is exact: every side is an exact orient3d sign at an input point or a corner of Q (a
// double); a query point uses the decided sides only when it lies in Q (exact comparisons), where
// they are its own. Q is the patch's box grown by a margin (approximate, only a size: a point
// outside Q is answered by the per-point path).
//
// Faces that cross B's or L's plane (clipped by the query, with chords that depend on x) are
// listed apart, in `clipped`: the query activates them as before, and the edges they share with
// the surface (groupWithClipped) are summed with their uses.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "visibility/bounds3.h"
#include "visibility/box_tree.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

struct HistoryTree;

struct DeferredSilhouettes {
    // One use of the directed edge v0 -> v1 by deferred occluder `slot` (an index in
    // HistoryTree::deferred), whose face faces Q with `side` (+1: Q in front of its plane, -1:
    // behind, 0: not decided for Q, the query takes the sign at x).
    struct Use {
        uint32_t v0 = 0, v1 = 0, slot = 0;
        int8_t side = 0;
    };
    Bounds3 region;  // Q; empty: not usable (the query uses the per-point path)
    // The uses of the edges that do not cancel for all of Q, grouped by edge: group g is
    // uses[groupBegin[g], groupBegin[g + 1]); groupWithClipped[g]: a Clipped face uses it too.
    std::vector<Use> uses;
    std::vector<uint32_t> groupBegin;
    std::vector<bool> groupWithClipped;
    BoxTree groups;  // over the groups' segment boxes
    // Per slot, what the query does with the deferred occluder: a Surface face (in front of both
    // planes, nowhere behind either) is counted by the cells' line tests and its edges are in
    // `uses` (or cancelled); a Clipped one (some vertex behind B's or L's plane) is activated per
    // point as before (ClippedOccluder); an Empty one (no vertex strictly in front of one of the
    // planes) blocks nothing.
    enum class Slot : uint8_t { Surface, Clipped, Empty };
    std::vector<Slot> slots;
    std::vector<int8_t> sides;      // per Surface slot, its Use::side
    std::vector<uint32_t> clipped;  // the Clipped slots, in increasing order
    // Of the uses of the non-empty deferred occluders (one per side of each face): all, those
    // kept in `uses` (with the Clipped faces'), and those no other face shares (borders of open
    // surfaces, separate faces, faces whose neighbour the tree inserted, Clipped faces). Where
    // it is not usable only totalUses and loneUses are computed (keptUses 0), unless too many
    // were kept (kSilhouetteMaxKeptPercent: keptUses is then the count).
    uint64_t totalUses = 0, keptUses = 0, loneUses = 0;

    size_t groupCount() const { return groupBegin.empty() ? 0 : groupBegin.size() - 1; }
    // Whether the query uses it (prepareSilhouettes kept it).
    bool usable() const { return !region.empty(); }
};

// Fills tree.silhouettes for tree.deferred (prepareForQueries calls it), for the query points in
// `receiverRegion` (the tree's patch of B; empty = all of B). Kept only where it pays: at most
// 1 / kSilhouetteGain of the uses are lone (closed and smooth surfaces); separate faces (leaves)
// cancel nothing, and the query goes on face by face there (only the totals are kept).
inline constexpr uint64_t kSilhouetteGain = 3;
// And only where at least 15% of the uses cancel for the whole patch (at most this share kept):
// with nearly every edge kept, the chain over them costs more than clipping the faces one by one
// (stairs: 92% kept, per-point p99 11.6 -> 8.9 us without them; the bunny's trees that pay keep
// 55-85%).
inline constexpr uint64_t kSilhouetteMaxKeptPercent = 85;
// Nor for trees that defer more faces than this: preparing costs some 2 us of CPU per deferred
// face (memory-bound; exact signs for the vertices on B's plane), and on the motorbike (14
// partial trees of 35k-240k deferred faces, 61% of its points sampled) it added 1.1 s to the
// precompute and saved no shading time. The bunny's partial trees defer up to 23k.
inline constexpr size_t kMaxSilhouetteFaces = 65536;
// `maxKeptPercent` (tests force the silhouettes with 100).
void prepareSilhouettes(const PolygonMesh& mesh, HistoryTree& tree,
                        std::span<const Vec3> receiverRegion = {},
                        uint64_t maxKeptPercent = kSilhouetteMaxKeptPercent);

}  // namespace penumbra::vis
