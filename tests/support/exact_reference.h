// Independent references for the visibility core, for tests only (compiled into the test binary;
// the exact one uses CGAL).
//
// Semantics (the same as the core's): for a point x on receiver face B and light face L, a point y
// of L is visible iff
//   - y is strictly in front of B's plane (the exact plane through B's first three vertices),
//   - x is strictly in front of L's plane (lights emit to their front only; otherwise nothing is
//     visible), and
//   - the open segment (x, y) meets no other face of the mesh (every face except B and L
//     occludes, from both sides) in front of B's plane: only a face's part in the closed
//     half-space in front of it occludes, and a face with no point strictly in front of it (one
//     in B's plane) none. (For x on B's plane or in front of it that is the whole segment; x a
//     rounding behind it, the core clips its occluders to B's front half-space, so the
//     segment's part between x and B's plane is not tested.)
#pragma once

#include <cstdint>

#include "visibility/polygon_mesh.h"
#include "visibility/vec3.h"

namespace penumbra::test {

struct ReferenceResult {
    double lightArea = 0;             // area of L (3D, double)
    double visibleArea = 0;           // fraction * lightArea
    double fraction = 0;              // visible area / area of L, from exact 2D areas
    double formFactor = 0;            // point-to-polygon form factor of the visible part of L
    double unoccludedFormFactor = 0;  // form factor of L clipped to B's front halfspace
    // The exact visible region's boundaries: its outer boundaries and its holes.
    int boundaryLoops = 0;
};

// Exact reference (CGAL Epeck + Polygon_set_2). The visible region is computed exactly: L is
// clipped to B's front halfspace (L'); every occluder is clipped to B's front halfspace and to the
// pyramid conv(x, L') (the slab between x and L intersected with the cone from x through L': the
// same occlusion, and the central projection stays bounded), projected centrally from x onto L's
// plane, mapped to 2D by dropping the dominant axis of L's normal; the union of the projections
// is subtracted from L'. `fraction` is the exact area ratio rounded to the nearest double; the
// form factors are Lambert's contour integral over the exact region's boundary (holes included)
// evaluated in long double, positive for a light that faces x. Occluders in a plane through x, in
// L's plane or in B's, are skipped (they hide a set of measure zero); non-planar faces are
// fan-triangulated.
ReferenceResult exactReference(const vis::PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                               vis::Vec3 x);

// Monte Carlo estimate of `fraction`: `samples` points uniform in the area of L (fan
// triangulation), each tested in double precision against every occluder (segment-plane
// intersection, then inside-convex-polygon test). Deterministic in `seed`. If stddev is not null
// it receives the standard deviation of the estimate, sqrt(p (1 - p) / samples).
double monteCarloFraction(const vis::PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                          vis::Vec3 x, int samples, uint64_t seed, double* stddev);

}  // namespace penumbra::test
