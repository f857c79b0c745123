// AnsweredPoint: the point a from-point query answers for a point x given on a receiver face B,
// and x itself, whose exact incidences decide the contact rule.
//
// A point a rounding behind B's plane (a projected ray hit, a point typed with decimals) has an
// exact answer of its own, but not one anybody asks for: seen from under B's plane, the occluders
// that cross it cut the light into slivers some ulps wide along the line where that plane meets
// the light, at a cost of seconds (one motorbike point: 93,674 fragments, a visible fraction of
// 8.4e-7, 8.1 s; from the front point none, in milliseconds). So such a point is answered at
// `at`: x projected onto B's plane, then moved along B's normal by the least step the filter
// certifies strictly in front (some ulps). A point that cheap tests certify on or in front of B's
// plane (the filter; for a plane of constant coordinate, the exact sign) is answered as given;
// one they leave undecided (within the filter's error of a tilted plane) is moved like a point
// behind: no exact stage per shading point, and either way the answer is exact for `at`.
//
// The move is a rounded construction, and it can take x off another occluder's plane (a wall
// standing on a tilted floor, x exactly in the wall's plane): the contact rule (a segment that
// touches an occluder only at x is not blocked by it) would then no longer apply at `at`, and the
// answer could change by the whole light. So the contact rule is decided at the input: every
// strategy of the query takes an occluder whose plane holds `input` exactly as touching (it blocks
// nothing), at `at` as at `input` (FromPointQuery::occluderSide). Every path (the tree walk, the
// deferred occluders, the tree-less direct path, the viewer's click, the renderer, `query`)
// answers the same AnsweredPoint for the same input: no rounding of x changes which occluders x
// touches.
#pragma once

#include "visibility/predicates.h"
#include "visibility/vec3.h"

namespace penumbra::vis {

struct AnsweredPoint {
    Vec3 at;     // the point answered: on or strictly in front of B's plane
    Vec3 input;  // the point given; equal to `at` unless it lay behind B's plane
    bool moved() const { return !(at == input); }
};

// A point that is answered as given.
inline AnsweredPoint answeredAsGiven(const Vec3& x) { return {x, x}; }

// x itself where the filter certifies it strictly in front of `plane`, else x moved along the
// plane's normal by the least such step (doubled until the filter certifies it). A plane whose
// rounded normal is zero keeps x (the query still answers it exactly). Filtered tests only.
Vec3 frontPoint(const PlaneOrient& plane, const Vec3& x);

// The point answered for x given on the face whose plane is `receiverPlane` (facePlane(...)
// .orient()): x where it is certainly on or in front (above), else frontPoint of x projected onto
// the plane. Deterministic: a function of the doubles given.
AnsweredPoint answeredPoint(const PlaneOrient& receiverPlane, const Vec3& x);

}  // namespace penumbra::vis
