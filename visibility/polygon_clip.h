// Clipping a convex polygon by a plane, with the side of every vertex decided exactly.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "visibility/edge_line.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

// The plane through three points; side(y) = orient3d(a, b, c, y): exact sign for any double y.
struct OrientedPlane {
    OrientedPlane(const Vec3& a_, const Vec3& b_, const Vec3& c_)
        : a(a_), b(b_), c(c_), orient(a_, b_, c_) {}
    Vec3 a, b, c;
    PlaneOrient orient;  // the cross product formed once for many side tests
    Sign side(const Vec3& y) const { return orient.sign(y); }
    BoundedValue value(const Vec3& y) const { return orient.value(y); }
};

// Splits `polygon` into `positive` and `negative` (cleared first, capacity kept: callers reuse
// buffers in hot loops). Same rules as clipConvex.
void clipConvexInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative);
// The same by the plane through a point and an edge line (exact signs for every vertex).
void clipConvexInto(std::span<const Vec3> polygon, const EdgePlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative);

// Where a polygon lies against a plane. The split functions below fill their output buffers only
// for Split: a polygon on one side (or on the plane) goes on unchanged, without a copy.
enum class SplitOutcome : uint8_t {
    OnPlane,   // every vertex on the plane (zero area on either side)
    Positive,  // no vertex strictly negative, some strictly positive
    Negative,  // no vertex strictly positive, some strictly negative
    Split,     // both: `positive` and `negative` hold the two parts
};

// Which parts a split must write (a part bound for a hidden leaf is not needed).
enum class KeepParts : uint8_t { Both, Positive, Negative };

// The two parts of a split polygon, in storage that keeps its capacity across calls (no
// allocation in a hot loop after warm-up). The storage vectors are sized to their capacity; the
// counts say how much of them each part uses.
struct SplitParts {
    std::span<const Vec3> positive() const { return {positiveStorage.data(), positiveCount}; }
    std::span<const Vec3> negative() const { return {negativeStorage.data(), negativeCount}; }

    std::vector<Vec3> positiveStorage, negativeStorage;
    std::vector<double> values;  // per-vertex values of the last split
    size_t positiveCount = 0, negativeCount = 0;
};

// The split of FPQuery's fragments, whose vertices are partly rounded constructions. Vertices equal
// to one of `inputVertices` get their exact sign. Any other vertex whose sign the floating-point
// filter cannot certify is treated as lying on the plane (it goes to both parts, no new vertex): it
// is itself a rounded construction whose rounding error is of the order of the filter's bound, so
// the exact sign of the rounded point carries no information, and taking it would only create
// slivers of rounding width. Areas move by at most that rounding width: for the plane through x
// and an edge (v0, v1) the filter fails only within 7u times its permanent, which puts the vertex
// within 25 u |y - x| / sin(theta) of the plane (u = 2^-53, theta the angle at x between v0 and
// v1); a snap moves at most that width times the fragment's diameter of area, and never decides a
// label. `parts` is written only for SplitOutcome::Split.
// `keep` names the parts written for Split (the other count is 0).
// Plane: PlaneOrient (the plane through x and an input edge) or PencilPlane (through x and a
// chord), each with filtered() and an exact-sign value() (edge_line.h).
template <class Plane>
SplitOutcome splitConstructed(std::span<const Vec3> polygon, const Plane& plane,
                              std::span<const Vec3> inputVertices, SplitParts& parts,
                              KeepParts keep = KeepParts::Both);

// Where `polygon` lies against the plane, with splitConstructed's signs, writing nothing.
template <class Plane>
SplitOutcome sideOfConstructed(std::span<const Vec3> polygon, const Plane& plane,
                               std::span<const Vec3> inputVertices);

// For measuring what exactness costs (FromPointQuery's PredicateMode): every sign through the
// exact stage (no filter), or the plain double determinant's sign (approximate, can be wrong).
SplitOutcome splitExact(std::span<const Vec3> polygon, const PlaneOrient& plane, SplitParts& parts);
SplitOutcome splitNaive(std::span<const Vec3> polygon, const PlaneOrient& plane, SplitParts& parts);

struct ClipResult {
    std::vector<Vec3> positive;  // part with side >= 0 (empty unless some vertex is strictly > 0)
    std::vector<Vec3> negative;  // part with side <= 0 (empty unless some vertex is strictly < 0)
};

// Splits a convex polygon. A vertex exactly on the plane goes to both parts and creates no new
// vertex, so a plane through a vertex leaves no sliver and loses no area; a part without a strict
// vertex has zero area and is returned empty. Crossing points are rounded constructions, placed on
// the segment between the two strictly separated vertices (never outside it).
ClipResult clipConvex(std::span<const Vec3> polygon, const OrientedPlane& plane);

// Only the part with side > 0 (same rules).
std::vector<Vec3> clipConvexPositive(std::span<const Vec3> polygon, const OrientedPlane& plane);

// Whether the plane cuts something off the polygon: some vertex lies strictly behind it (exact
// signs). When none does, clipConvexPositive keeps the whole polygon (vertices on the plane
// included, by the rules above). A receiver's plane that cuts the light is the point's horizon.
bool anyVertexBehind(std::span<const Vec3> polygon, const OrientedPlane& plane);

}  // namespace penumbra::vis
