#include "visibility/clipped_occluder.h"

#include <algorithm>

#include "visibility/edge_line.h"
#include "visibility/exact_orient.h"
#include "visibility/history_tree.h"

namespace penumbra::vis {

void ClippedOccluder::clip(const PolygonMesh& mesh, uint32_t face, const PlaneOrient& receiverPlane,
                           const PlaneOrient& lightPlane) {
    mesh_ = &mesh;
    face_ = face;
    planes_[0] = receiverPlane;
    planes_[1] = lightPlane;
    const auto& ids = mesh.faces[face];
    const size_t n = ids.size();
    points_.clear();
    for (uint32_t v : ids) points_.push_back(mesh.vertices[v]);
    vertices_.clear();
    edges_.clear();
    empty_ = true;
    clipped_ = false;
    bool front[2] = {false, false}, behind[2] = {false, false};
    for (int k = 0; k < 2; ++k) {
        signs_[k].resize(n);
        for (size_t i = 0; i < n; ++i) {
            const Sign s = planes_[k].sign(points_[i]);
            signs_[k][i] = s;
            front[k] |= s == Sign::Positive;
            behind[k] |= s == Sign::Negative;
        }
    }
    // A convex face with no vertex strictly in front of a plane has no part of positive area
    // there.
    if (n < 3 || !front[0] || !front[1]) return;
    if (!behind[0] && !behind[1]) {
        // Nothing behind either plane (the common case): the face itself, no clip.
        empty_ = false;
        for (uint32_t i = 0; i < n; ++i) {
            vertices_.push_back(Vertex{Vertex::Kind::Input, 0, i});
            edges_.push_back(Edge{ids[i], ids[(i + 1) % n]});
        }
        return;
    }
    poly_.clear();
    for (uint32_t i = 0; i < n; ++i)
        poly_.push_back({Vertex{Vertex::Kind::Input, 0, i}, Edge{ids[i], ids[(i + 1) % n]}, i});
    polySigns_.assign(signs_[0].begin(), signs_[0].end());
    if (behind[0]) {
        clipped_ = true;
        clipBy(0);
    }
    // The part in front of B has positive area (a vertex strictly in front); the part of it in
    // front of L has positive area iff one of its vertices is strictly in front of L.
    polySigns_.resize(poly_.size());
    bool anyFront = false, anyBehind = false;
    for (size_t k = 0; k < poly_.size(); ++k) {
        polySigns_[k] = *side(poly_[k].vertex, planes_[1]);  // no corner yet: always decided
        anyFront |= polySigns_[k] == Sign::Positive;
        anyBehind |= polySigns_[k] == Sign::Negative;
    }
    if (!anyFront) return;
    if (anyBehind) {
        clipped_ = true;
        clipBy(1);
    }
    empty_ = false;
    for (const Entry& e : poly_) {
        vertices_.push_back(e.vertex);
        if (std::find(edges_.begin(), edges_.end(), e.edge) == edges_.end())
            edges_.push_back(e.edge);
    }
}

void ClippedOccluder::clipBy(uint8_t which) {
    // Sutherland-Hodgman on symbolic vertices, with the exact signs in polySigns_. Each entry
    // carries the edge that leaves it: a vertex on the plane whose successor is behind leaves
    // along the chord, a crossing into the front leaves along its input edge.
    const Edge chord{kClipEdge | face_, which == 0 ? kReceiverPlaneEdge : kLightPlaneEdge};
    auto crossing = [&](const Entry& from) {
        if (from.faceEdge == UINT32_MAX) return Vertex{Vertex::Kind::Corner, which, 0};
        return Vertex{Vertex::Kind::Crossing, which, from.faceEdge};
    };
    next_.clear();
    const size_t m = poly_.size();
    for (size_t k = 0; k < m; ++k) {
        const Entry& cur = poly_[k];
        const Sign sc = polySigns_[k], sn = polySigns_[(k + 1) % m];
        if (sc != Sign::Negative) {
            if (sc == Sign::Zero && sn == Sign::Negative)
                next_.push_back({cur.vertex, chord, UINT32_MAX});
            else
                next_.push_back(cur);
            if (sc == Sign::Positive && sn == Sign::Negative)
                next_.push_back({crossing(cur), chord, UINT32_MAX});
        } else if (sn == Sign::Positive) {
            next_.push_back({crossing(cur), cur.edge, cur.faceEdge});
        }
    }
    std::swap(poly_, next_);
}

Sign ClippedOccluder::crossingSide(uint32_t edge, const PlaneOrient& x, Sign fromSide,
                                   const PlaneOrient& h) const {
    const Vec3& p = points_[edge];
    const Vec3& q = points_[(edge + 1) % points_.size()];
    // c = (piX(p) q - piX(q) p) / (piX(p) - piX(q)); the denominator has the sign of piX(p).
    const Sign s = pencilValue(x, h, p, q).sign();
    return fromSide == Sign::Positive ? s : -s;
}

std::optional<Sign> ClippedOccluder::side(const Vertex& v, const PlaneOrient& h) const {
    switch (v.kind) {
        case Vertex::Kind::Input:
            return h.sign(points_[v.index]);
        case Vertex::Kind::Crossing:
            return crossingSide(v.index, planes_[v.plane], signs_[v.plane][v.index], h);
        case Vertex::Kind::Corner:
            break;
    }
    return std::nullopt;
}

std::optional<Sign> ClippedOccluder::lineSide(const Vertex& v, const Vec3& p, bool fromP,
                                              const EdgeLine& e) const {
    auto side = [&](const Vec3& q) { return fromP ? sideValue(p, q, e) : sideValue(q, p, e); };
    switch (v.kind) {
        case Vertex::Kind::Input:
            return side(points_[v.index]).sign();
        case Vertex::Kind::Crossing: {
            const Vec3& q0 = points_[v.index];
            const Vec3& q1 = points_[(v.index + 1) % points_.size()];
            const PlaneOrient& x = planes_[v.plane];
            const BoundedValue r =
                differenceOfProducts(x.value(q0), side(q1), x.value(q1), side(q0));
            Sign s = r.sign();
            if (!r.certain()) {
                // Exact zeros are common here: p and c both in B's (or L's) plane, against an edge
                // line in that plane too (coplanar lines: side 0). Recognised directly; anything
                // else uncertain goes to rationals, so that the culling still applies.
                auto inX = [&](const Vec3& q) { return x.sign(q) == Sign::Zero; };
                const bool lineInX =
                    e.kind == EdgeLine::Kind::Planes
                        ? (e.first.a == x.a && e.first.b == x.b && e.first.c == x.c)
                        : inX(e.p) && inX(e.q);
                if (lineInX && inX(p)) return Sign::Zero;
                auto exactSide = [&](const Vec3& q) {
                    return fromP ? sideExact(p, q, e) : sideExact(q, p, e);
                };
                const mpq_class v0 = orientExact(x.a, x.b, x.c, q0) * exactSide(q1) -
                                     orientExact(x.a, x.b, x.c, q1) * exactSide(q0);
                s = sgn(v0) > 0 ? Sign::Positive : (sgn(v0) < 0 ? Sign::Negative : Sign::Zero);
            }
            return signs_[v.plane][v.index] == Sign::Positive ? s : -s;
        }
        case Vertex::Kind::Corner:
            break;
    }
    return std::nullopt;
}

bool ClippedOccluder::outside(const PlaneOrient& h) const {
    for (const Vertex& v : vertices_) {
        Sign s;
        if (v.kind == Vertex::Kind::Input) {
            s = h.sign(points_[v.index]);
        } else if (v.kind == Vertex::Kind::Crossing) {
            // The filter alone: a culling test may say "not certainly outside" when it cannot
            // tell (a pyramid plane through x and an edge of L clipped at B's plane is nearly B's
            // plane, and so nearly through every crossing with it), and rationals would cost more
            // than the occluder they might skip.
            const Vec3& q0 = points_[v.index];
            const Vec3& q1 = points_[(v.index + 1) % points_.size()];
            const PlaneOrient& x = planes_[v.plane];
            const BoundedValue r =
                differenceOfProducts(x.value(q0), h.value(q1), x.value(q1), h.value(q0));
            if (!r.certain()) return false;
            s = signs_[v.plane][v.index] == Sign::Positive ? r.sign() : -r.sign();
        } else {
            return false;  // a corner: not decided
        }
        if (s == Sign::Positive) return false;
    }
    return true;
}

}  // namespace penumbra::vis
