#include "visibility/fp_query/contact_rule.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

bool ContactRule::onContact(const HistoryTree& tree, const Vec3& x) const {
    for (const PlaneOrient& plane : tree.contactPlanes) {
        BoundedValue v;
        if (plane.filtered(x, v)) continue;  // certainly off the plane (the inline filter)
        if (plane.value(x).sign() == Sign::Zero) return true;
    }
    return false;
}

bool ContactRule::nearContact(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x) {
    // The lines from x to L, followed back from x to B's plane, sweep the part R of the cone
    // with apex x over the reflected L that lies in front of B's plane: the convex hull of x and
    // the points x - t_i (l_i - x) with t_i = b(x) / (b(l_i) - b(x)), b the plane's orient3d
    // value (a common scale), for L's vertices l_i. So every point of R lies within
    // D = max_i b(x) |l_i - x| / (b(l_i) - b(x)) of x (in each coordinate), and below b(x):
    // an inserted occluder that does not reach B's plane is clear of it where b(x) stays below
    // contactClearance, and one that reaches it is where its box misses x +- D. Every bound
    // rounds outwards; where one fails the answer is "may" (the direct answer: the same exact
    // answer the contract asks for, only slower).
    if (tree.contactBoxes.empty() && !(tree.contactClearance < HUGE_VAL)) return false;
    q_.run.pair.prepare(mesh, tree.receiver, tree.light);  // (once per pair)
    const PlaneOrient& plane = q_.run.pair.frontB().orient;
    // x on B's plane or behind it has no sliver. Where the filter cannot tell (a projected
    // point, almost always), its bound of b(x) from above goes to the tests first: they can
    // only answer "may" for a larger bound, so a "no" there is x's; only a "may" asks for the
    // exact sign and the tests again with the accurate value (the same decisions as the exact
    // value throughout, without the exact stage for every projected point: on the Cornell box
    // that stage was some 3% of the render's CPU).
    BoundedValue bx;
    if (plane.filtered(x, bx)) return bx.sign() == Sign::Positive && mayMeetSliver(tree, x, bx);
    if (!mayMeetSliver(tree, x, bx)) return false;
    bx = plane.value(x);
    return bx.sign() == Sign::Positive && mayMeetSliver(tree, x, bx);
}

bool ContactRule::mayMeetSliver(const HistoryTree& tree, const Vec3& x, const BoundedValue& bx) {
    // (nearContact's tests, for b(x) <= bx.value + bx.error; the pair prepared.)
    const PairSetup& pair = q_.run.pair;
    const PlaneOrient& plane = pair.frontB().orient;
    const std::vector<Vec3>& light = pair.lightPolygon();
    const double high = bx.value + bx.error;
    if (!(high < tree.contactClearance)) return true;
    if (tree.contactBoxes.empty()) return false;
    if (lowGeneration_ != pair.generation()) {
        lightLow_.clear();
        for (const Vec3& l : light) {
            const BoundedValue bl = plane.value(l);
            lightLow_.push_back(bl.value - bl.error);
        }
        lowGeneration_ = pair.generation();
    }
    double reach = 0;
    for (size_t i = 0; i < light.size(); ++i) {
        const Vec3& l = light[i];
        const double gap = lightLow_[i] - high;
        if (!(gap > 0)) return true;
        const double dist = std::fabs(l.x - x.x) + std::fabs(l.y - x.y) + std::fabs(l.z - x.z);
        reach = std::fmax(reach, high * dist / gap);
    }
    // (|.|_1 bounds each coordinate; the pads cover the rounding of the quotient and of a box
    // grown by it near x.)
    const double pad = std::fmax(std::fabs(x.x), std::fmax(std::fabs(x.y), std::fabs(x.z)));
    reach = reach * (1 + 0x1p-40) + pad * 0x1p-50 + DBL_TRUE_MIN;
    // An occluder whose box reaches the sliver may still have it strictly on one side of its
    // plane: |P(p) - P(x)| = |n . (p - x)| <= (|n|_1 + 8u |perm|_1) D for p in R (the rounded
    // normal within 8u of its permanent of the exact one).
    for (size_t i = 0; i < tree.contactBoxes.size(); ++i) {
        if (!tree.contactBoxes[i].containsGrown(x, reach)) continue;
        const PlaneOrient& p = tree.contactPlanes[i];
        const BoundedValue px = p.value(x);
        const double slope = (p.normL1() + p.permanentL1() * 0x1p-50) * (1 + 0x1p-40);
        if (!(std::fabs(px.value) - px.error > slope * reach * (1 + 0x1p-40))) return true;
    }
    return false;
}

void ContactRule::gatherCandidates(const HistoryTree& tree) {
    QueryRun& r = q_.run;
    const PolygonMesh& mesh = r.mesh();
    std::vector<uint32_t>& candidates = r.candidates;
    candidates.assign(tree.occluders.begin(), tree.occluders.end());
    for (const DeferredOccluder& d : tree.deferred) candidates.push_back(d.face);
    std::sort(candidates.begin(), candidates.end());
    candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
    // A face whose every vertex lies strictly farther from L's plane than x (the filter's
    // bounds, which hold whether or not it certifies a sign) meets no segment from x to L:
    // those lie between L's plane and its parallel through x. (The common contact answer:
    // the floor below a wall whose plane cuts the light, an occluder of the wall's grown
    // patches; activating it took the exact stage for its chords' pencil planes.)
    const PlaneOrient& lightPlane = r.pair.lightPlane();
    BoundedValue bound;
    lightPlane.filtered(r.x, bound);
    const double xHigh = bound.value + bound.error;
    std::erase_if(candidates, [&](uint32_t f) {
        for (uint32_t v : mesh.faces[f]) {
            lightPlane.filtered(mesh.vertices[v], bound);
            if (!(bound.value - bound.error > xHigh)) return false;
        }
        return true;
    });
}

}  // namespace penumbra::vis
