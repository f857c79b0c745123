// The occluders of one (receiver B, light L) pair: the parts of the other faces that can block a
// line segment from B to L.
//
// Each candidate face is clipped to the region in front of both B's and L's planes (the only
// region a segment from a point of B to a point of L that each face the other can cross), so a
// stabbing line that meets the clipped occluder meets it between B and L. The clip is exact and
// constructs no point (clipped_occluder.h): the occluder's edges are input edges and the chords
// where its plane meets B's or L's, and every decision about it (empty or not, outside the hull
// of B and L or not, which way segments cross it) is an exact function of the input doubles.
#pragma once

#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "visibility/face_plane.h"
#include "visibility/history_tree.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct Occluder {
    uint32_t face = 0;
    // The clipped polygon's edges in the face's order, in HistoryNode's (v0, v1) encoding.
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    // Which side of each of its edge hyperplanes the blocked lines (oriented from B to L) lie on:
    // +1 or -1 when the occluder's plane separates B from L (all crossings in one direction), 0
    // when it cuts B or L and both can occur.
    int blockedSign = 0;
    // Approximate (doubles, a heuristic only): the clipped polygon's area.
    double area = 0;
    // The area of L it hides from the centroid of B (approximate, in doubles): the insertion
    // order, largest first.
    double shadow = 0;
};

struct PairOccluders {
    bool backFacing = false;
    std::vector<Occluder> occluders;  // most important first (largest shadow, then area)
};

// candidates: faces that may occlude (superset is fine); empty = every face of the mesh.
// receiverRegion: the part of the receiver face the pair is about (all of it, or a patch).
PairOccluders gatherOccluders(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                              std::span<const uint32_t> candidates,
                              std::span<const Vec3> receiverRegion);

// The supporting planes of conv(B u L) through an edge of one polygon and a vertex of the other,
// and B's and L's own planes where they support it (B and L planar: their first three vertices),
// oriented so that every vertex of B and L lies on their closed positive side. Every segment from
// B to L lies in that hull, so a polygon with no vertex strictly on the positive side of one of
// these planes meets the segments in a set of measure zero at most. Exact: the planes go through
// the input points and every side is an orient3d sign.
std::vector<PlaneOrient> hullPlanes(std::span<const Vec3> b, std::span<const Vec3> l);

// The side planes of the pyramid from `apex` over the convex polygon `polygon` (one per edge, the
// plane through the apex and the edge), oriented so that the polygon lies on their closed positive
// side; a plane the polygon's next vertex lies on (the apex in the polygon's plane) is left out.
// Exact signs. Into `out` (cleared: hot loops reuse its capacity).
void pyramidPlanes(const Vec3& apex, std::span<const Vec3> polygon, std::vector<PlaneOrient>& out);

// Whether some plane has no vertex of `polygon` strictly on its positive side (exact signs): then
// the polygon meets the region on the positive side of all of them in a set of measure zero at
// most (hullPlanes, pyramidPlanes).
bool outsideOnePlane(std::span<const PlaneOrient> planes, std::span<const Vec3> polygon);

}  // namespace penumbra::vis
