// VisibleOutline: the boundary of the visible part of a light seen from a point. FPQuery answers
// with disjoint convex fragments (a tree walk or a boundary chain cuts the light into many, most
// of them side by side); their union's boundary is what bounds the shadow, and what a user
// debugging it wants to see: closed loops in the light's plane, outer boundaries turning as the
// fragments do and holes the other way. Lambert's formula is a sum over edges, so the edges two
// fragments share cancel and the form factor integrated over the loops (formFactorOfLoops) is the
// fragments' own.
//
// Approximate, for the debugger and the reports; it decides nothing. The fragments' vertices are
// rounded constructions: two fragments meet along an edge that each side may have cut at other
// points (a T-junction: a later split of one side only) and rounding may have bent by some ulps.
// So vertices within the weld distance (2^-40 of the fragments' extent, plus 2^-46 of their
// largest coordinate: some 64 ulps, for lights far from the origin) are taken as one, and a
// vertex within it of another fragment's edge splits that edge; then the edges that run both ways
// between the same two vertices cancel, and the rest are chained into loops (where two loops touch
// at a vertex, each turns as far left as it can, so touching regions stay apart). Which lines from
// the point see the light was decided by the fragments' exact labels; the outline only regroups
// their edges. Its form factor is the fragments' to within the weld distance times its perimeter.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "visibility/vec3.h"

namespace penumbra::vis {

struct VisibleOutline {
    // Closed loops (no vertex repeated at the end), each with straight runs merged into one edge.
    std::vector<std::vector<Vec3>> loops;
    // The edges of all loops.
    size_t edges() const;
    // The region's area: Newell's normal summed over the loops (holes subtract).
    double area() const;
};

// The outline of the union of `fragments`: disjoint convex polygons in one plane, all turning
// the same way (FPQuery's fragments are counter-clockwise as the light is). Fragments that the
// weld leaves with fewer than three vertices (slivers thinner than it) are dropped. Cost: about
// the fragments' edges times the vertices in the x-range of each edge (a sweep by x).
VisibleOutline visibleOutline(std::span<const std::vector<Vec3>> fragments);

}  // namespace penumbra::vis
