#include "visibility/polygon_clip.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <type_traits>

namespace penumbra::vis {

namespace {

Vec3 crossing(const Vec3& p, const Vec3& q, double dp, double dq) {
    // dp and dq have opposite exact signs; their doubles may be tiny or even disagree in sign, so
    // clamp the parameter to the segment.
    double t = dp / (dp - dq);
    if (!(t >= 0)) t = 0;  // also catches NaN
    if (t > 1) t = 1;
    return p + (q - p) * t;
}

// Each vertex's signed value (its sign decides, zero = on the plane) into d, and the outcome.
template <typename ValueOf>
SplitOutcome classify(std::span<const Vec3> polygon, ValueOf valueOf, double* d) {
    const size_t n = polygon.size();
    if (n < 3) return SplitOutcome::OnPlane;
    bool anyPos = false, anyNeg = false;
    for (size_t i = 0; i < n; ++i) {
        d[i] = valueOf(polygon[i]);
        anyPos |= d[i] > 0;
        anyNeg |= d[i] < 0;
    }
    if (!anyNeg) return anyPos ? SplitOutcome::Positive : SplitOutcome::OnPlane;
    return anyPos ? SplitOutcome::Split : SplitOutcome::Negative;
}

// Room each part needs: a vertex goes to one or both parts and every sign change adds a crossing
// to both (two for a convex polygon, at most n for a rounded, barely convex one).
constexpr size_t partCapacity(size_t n) { return 2 * n; }

// The two parts of a split polygon into pos and neg (partCapacity(n) each); returns the counts.
void writeParts(std::span<const Vec3> polygon, const double* d, Vec3* pos, size_t& positiveCount,
                Vec3* neg, size_t& negativeCount) {
    const size_t n = polygon.size();
    size_t np = 0, nn = 0;
    for (size_t i = 0; i < n; ++i) {
        const size_t j = i + 1 == n ? 0 : i + 1;
        const double si = d[i], sj = d[j];
        if (si >= 0) pos[np++] = polygon[i];
        if (si <= 0) neg[nn++] = polygon[i];
        if ((si > 0 && sj < 0) || (si < 0 && sj > 0)) {
            const Vec3 p = crossing(polygon[i], polygon[j], si, sj);
            pos[np++] = p;
            neg[nn++] = p;
        }
    }
    positiveCount = np;
    negativeCount = nn;
}

// One part of a split polygon (side +1: values >= 0, side -1: values <= 0), as writeParts
// writes it.
size_t writePart(std::span<const Vec3> polygon, const double* d, int side, Vec3* out) {
    const size_t n = polygon.size();
    size_t count = 0;
    for (size_t i = 0; i < n; ++i) {
        const size_t j = i + 1 == n ? 0 : i + 1;
        const double si = d[i] * side, sj = d[j] * side;
        if (si >= 0) out[count++] = polygon[i];
        if ((si > 0 && sj < 0) || (si < 0 && sj > 0))
            out[count++] = crossing(polygon[i], polygon[j], d[i], d[j]);
    }
    return count;
}

// The split into SplitParts (written only for Split).
template <typename ValueOf>
SplitOutcome splitInto(std::span<const Vec3> polygon, ValueOf valueOf, SplitParts& parts,
                       KeepParts keep = KeepParts::Both) {
    const size_t n = polygon.size();
    if (parts.values.size() < n) parts.values.resize(n);
    const SplitOutcome outcome = classify(polygon, valueOf, parts.values.data());
    if (outcome != SplitOutcome::Split) return outcome;
    if (parts.positiveStorage.size() < partCapacity(n)) {
        parts.positiveStorage.resize(partCapacity(n));
        parts.negativeStorage.resize(partCapacity(n));
    }
    switch (keep) {
        case KeepParts::Both:
            writeParts(polygon, parts.values.data(), parts.positiveStorage.data(),
                       parts.positiveCount, parts.negativeStorage.data(), parts.negativeCount);
            break;
        case KeepParts::Positive:
            parts.positiveCount =
                writePart(polygon, parts.values.data(), +1, parts.positiveStorage.data());
            parts.negativeCount = 0;
            break;
        case KeepParts::Negative:
            parts.negativeCount =
                writePart(polygon, parts.values.data(), -1, parts.negativeStorage.data());
            parts.positiveCount = 0;
            break;
    }
    return outcome;
}

// The split into two vectors, both written whatever the outcome (clipConvexInto's contract).
template <typename ValueOf>
void splitIntoVectors(std::span<const Vec3> polygon, ValueOf valueOf, std::vector<Vec3>& positive,
                      std::vector<Vec3>& negative) {
    const size_t n = polygon.size();
    constexpr size_t kInline = 32;
    double inlineVals[kInline];
    std::vector<double> heapVals;
    double* d = inlineVals;
    if (n > kInline) {
        heapVals.resize(n);
        d = heapVals.data();
    }
    const SplitOutcome outcome = classify(polygon, valueOf, d);
    positive.clear();
    negative.clear();
    switch (outcome) {
        case SplitOutcome::OnPlane:
            return;
        case SplitOutcome::Positive:
            positive.assign(polygon.begin(), polygon.end());
            return;
        case SplitOutcome::Negative:
            negative.assign(polygon.begin(), polygon.end());
            return;
        case SplitOutcome::Split:
            break;
    }
    positive.resize(partCapacity(n));
    negative.resize(partCapacity(n));
    size_t np = 0, nn = 0;
    writeParts(polygon, d, positive.data(), np, negative.data(), nn);
    positive.resize(np);
    negative.resize(nn);
}

// The filter could not decide: exact for an input vertex, on the plane for a constructed one,
// unless the plane through x and the edge is ill-conditioned (x sees an input edge under an
// angle of some ulps, or lies within some ulps of a chord's line): then the snap width
// 25 u |y - x| / sin(theta) spans the fragment, and putting its vertices on both sides made parts
// that overlap (found by fuzzing: a light's visible area 1.26 times its area). There the rounded
// vertex takes its exact sign: the parts stay a partition, each vertex off by its own rounding
// only.
template <class Plane>
[[gnu::noinline]] double uncertainValue(const Plane& plane, std::span<const Vec3> inputVertices,
                                        const Vec3& y) {
    for (const Vec3& input : inputVertices)
        if (input.x == y.x && input.y == y.y && input.z == y.z) return plane.value(y).value;
    if (!plane.wellConditioned()) return plane.value(y).value;
    return 0.0;
}

// splitConstructed's value of a vertex: exact sign for input vertices, the filter's otherwise (an
// uncertain constructed vertex counts as on the plane). The filter's path inlined: it is the
// from-point query's innermost loop.
template <class Plane>
[[gnu::always_inline]] inline double constructedValue(const Plane& plane,
                                                      std::span<const Vec3> inputVertices,
                                                      const Vec3& y) {
    BoundedValue v;
    if (plane.filtered(y, v)) return v.value;
    return uncertainValue(plane, inputVertices, y);
}

// The value's sign is exact (filtered, exact fallback), its magnitude is for placement: the
// filter's on a plane that places well, the exact value's on one that does not (a sliver
// receiver's plane, seen rotated: its normal mostly rounding; the light clipped by it was off by
// 6e-6 of its area).
template <class Plane>
void clipByPlaneInto(std::span<const Vec3> polygon, const Plane& plane, std::vector<Vec3>& positive,
                     std::vector<Vec3>& negative) {
    if (plane.placesWell()) {
        splitIntoVectors(
            polygon, [&](const Vec3& y) { return plane.value(y).value; }, positive, negative);
        return;
    }
    splitIntoVectors(
        polygon, [&](const Vec3& y) { return plane.accurate(y).value; }, positive, negative);
}

}  // namespace

void clipConvexInto(std::span<const Vec3> polygon, const OrientedPlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative) {
    clipByPlaneInto(polygon, plane.orient, positive, negative);
}

void clipConvexInto(std::span<const Vec3> polygon, const EdgePlane& plane,
                    std::vector<Vec3>& positive, std::vector<Vec3>& negative) {
    clipByPlaneInto(polygon, plane, positive, negative);
}

template <class Plane>
SplitOutcome splitConstructed(std::span<const Vec3> polygon, const Plane& plane,
                              std::span<const Vec3> inputVertices, SplitParts& parts,
                              KeepParts keep) {
    if (plane.placesWell()) {
        return splitInto(
            polygon, [&](const Vec3& y) { return constructedValue(plane, inputVertices, y); },
            parts, keep);
    }
    // The same signs; the magnitudes that place the crossings from the exact values (placesWell).
    // An accurate value has the exact sign of y, which is the filter's where it certified one.
    return splitInto(
        polygon,
        [&](const Vec3& y) {
            const double v = constructedValue(plane, inputVertices, y);
            return v == 0 ? 0.0 : plane.accurate(y).value;
        },
        parts, keep);
}

template <class Plane>
SplitOutcome sideOfConstructed(std::span<const Vec3> polygon, const Plane& plane,
                               std::span<const Vec3> inputVertices) {
    bool anyPos = false, anyNeg = false;
    for (const Vec3& y : polygon) {
        const double d = constructedValue(plane, inputVertices, y);
        anyPos |= d > 0;
        anyNeg |= d < 0;
        if (anyPos && anyNeg) return SplitOutcome::Split;
    }
    if (polygon.size() < 3) return SplitOutcome::OnPlane;
    if (!anyNeg) return anyPos ? SplitOutcome::Positive : SplitOutcome::OnPlane;
    return SplitOutcome::Negative;
}

// The plane types FPQuery splits by (edge_line.h).
template SplitOutcome splitConstructed<PlaneOrient>(std::span<const Vec3>, const PlaneOrient&,
                                                    std::span<const Vec3>, SplitParts&, KeepParts);
template SplitOutcome splitConstructed<PencilPlane>(std::span<const Vec3>, const PencilPlane&,
                                                    std::span<const Vec3>, SplitParts&, KeepParts);
template SplitOutcome sideOfConstructed<PlaneOrient>(std::span<const Vec3>, const PlaneOrient&,
                                                     std::span<const Vec3>);
template SplitOutcome sideOfConstructed<PencilPlane>(std::span<const Vec3>, const PencilPlane&,
                                                     std::span<const Vec3>);

SplitOutcome splitExact(std::span<const Vec3> polygon, const PlaneOrient& plane,
                        SplitParts& parts) {
    return splitInto(
        polygon,
        [&](const Vec3& y) {
            const double v = orient3dApprox(plane.a, plane.b, plane.c, y);
            const Sign s = orientSignExact(plane.a, plane.b, plane.c, y);
            // The exact sign with the double's magnitude for placement.
            if (s == Sign::Zero) return 0.0;
            const double m = std::max(std::fabs(v), DBL_TRUE_MIN);
            return toInt(s) > 0 ? m : -m;
        },
        parts);
}

SplitOutcome splitNaive(std::span<const Vec3> polygon, const PlaneOrient& plane,
                        SplitParts& parts) {
    return splitInto(
        polygon, [&](const Vec3& y) { return orient3dApprox(plane.a, plane.b, plane.c, y); },
        parts);
}

ClipResult clipConvex(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    ClipResult r;
    clipConvexInto(polygon, plane, r.positive, r.negative);
    return r;
}

std::vector<Vec3> clipConvexPositive(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    return clipConvex(polygon, plane).positive;
}

bool anyVertexBehind(std::span<const Vec3> polygon, const OrientedPlane& plane) {
    for (const Vec3& v : polygon)
        if (plane.side(v) == Sign::Negative) return true;
    return false;
}

}  // namespace penumbra::vis
