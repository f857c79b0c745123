#include "engine/precompute/point_query.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "visibility/face_plane.h"
#include "visibility/form_factor.h"
#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra {
namespace {

// Shortest round-trip decimal form of a double.
std::string formatNumber(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string formatPoint(const Vec3& x) {
    return "(" + formatNumber(x.x) + ", " + formatNumber(x.y) + ", " + formatNumber(x.z) + ")";
}

std::string formatFaceList(const std::vector<uint32_t>& faces) {
    std::string s;
    for (size_t i = 0; i < faces.size(); ++i) {
        if (i > 0) s += i + 1 == faces.size() ? " and " : ", ";
        s += std::to_string(faces[i]);
    }
    return s;
}

Vec3 unitNormal(const vis::PolygonMesh& mesh, uint32_t f) {
    return normalize(mesh.faceAreaNormal(f));
}

// Distance of p from the plane of face f (through its first vertex, unit normal n).
double planeDistance(const vis::PolygonMesh& mesh, uint32_t f, const Vec3& n, const Vec3& p) {
    return std::fabs(dot(n, p - mesh.vertices[mesh.faces[f][0]]));
}

// How far x, projected onto the coordinate plane that drops the dominant axis of n, lies outside
// face f's polygon: the largest 2D distance to the outer side of an edge's line (<= 0 inside).
double outsideProjected(const vis::PolygonMesh& mesh, uint32_t f, const Vec3& n, const Vec3& x) {
    // Dominant axis k; the other two (u, v) in cyclic order, so a polygon counter-clockwise about
    // +axis k stays counter-clockwise in (u, v).
    int k = 2;
    if (std::fabs(n.x) >= std::fabs(n.y) && std::fabs(n.x) >= std::fabs(n.z)) {
        k = 0;
    } else if (std::fabs(n.y) >= std::fabs(n.z)) {
        k = 1;
    }
    const int u = (k + 1) % 3, v = (k + 2) % 3;
    const double orientation = n[k] >= 0 ? 1.0 : -1.0;
    const auto face = mesh.face(f);
    const double px = x[u], py = x[v];
    double outside = -std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < face.size(); ++i) {
        const Vec3 a = mesh.vertices[face[i]], b = mesh.vertices[face[(i + 1) % face.size()]];
        const double ex = b[u] - a[u], ey = b[v] - a[v];
        const double len = std::hypot(ex, ey);
        if (len == 0) continue;  // an edge seen end-on: its neighbours bound the polygon
        const double side = orientation * (ex * (py - a[v]) - ey * (px - a[u])) / len;
        outside = std::max(outside, -side);
    }
    return outside;
}

// x projected as above, inside face f's polygon or within tol of its boundary (the 2D distance
// to each edge's line).
bool insideProjected(const vis::PolygonMesh& mesh, uint32_t f, const Vec3& n, const Vec3& x,
                     double tol) {
    return !(outsideProjected(mesh, f, n, x) > tol);
}

std::vector<Vec3> facePolygon(const vis::PolygonMesh& mesh, uint32_t f) {
    std::vector<Vec3> p;
    p.reserve(mesh.faces[f].size());
    for (uint32_t v : mesh.faces[f]) p.push_back(mesh.vertices[v]);
    return p;
}

}  // namespace

double pointTolerance(const Scene& scene, const Vec3& x) {
    return 1e-9 * scene.mesh.bounds().diagonal() + 1e-12 * length(x);
}

FaceLookup findFaceContaining(const Scene& scene, const Vec3& x) {
    FaceLookup out;
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) {
        out.error = "point " + formatPoint(x) + " is not finite";
        return out;
    }
    const vis::PolygonMesh& mesh = scene.mesh;
    const double tol = pointTolerance(scene, x);
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        if (mesh.faces[f].size() < 3 || !mesh.faceBounds(f).containsGrown(x, tol)) continue;
        const Vec3 n = unitNormal(mesh, f);
        if (planeDistance(mesh, f, n, x) > tol) continue;
        if (insideProjected(mesh, f, n, x, tol)) out.candidates.push_back(f);
    }
    if (out.candidates.empty()) {
        out.error = "point " + formatPoint(x) + " lies on no face";
        return out;
    }
    const uint32_t first = out.candidates.front();
    const Vec3 n0 = unitNormal(mesh, first);
    bool onePlane = true;
    for (size_t i = 1; i < out.candidates.size() && onePlane; ++i) {
        const uint32_t f = out.candidates[i];
        if (dot(n0, unitNormal(mesh, f)) <= 0) onePlane = false;
        for (uint32_t v : mesh.faces[f])
            if (planeDistance(mesh, first, n0, mesh.vertices[v]) > tol) onePlane = false;
    }
    if (onePlane) {
        out.face = first;
    } else {
        out.error = "point " + formatPoint(x) + " is ambiguous: it lies on faces " +
                    formatFaceList(out.candidates) +
                    ", which are not one plane with one orientation (name the face)";
    }
    return out;
}

std::optional<std::string> pointOffFace(const Scene& scene, uint32_t face, const Vec3& x) {
    if (face >= scene.faceCount())
        return "face " + std::to_string(face) + " out of range (the scene has " +
               std::to_string(scene.faceCount()) + " faces)";
    if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z))
        return "point " + formatPoint(x) + " is not finite";
    const vis::PolygonMesh& mesh = scene.mesh;
    const double tol = pointTolerance(scene, x);
    const Vec3 n = unitNormal(mesh, face);
    const double off = planeDistance(mesh, face, n, x);
    const std::string what = "point " + formatPoint(x) + " is not on face " + std::to_string(face);
    const std::string tolerance = " (the lookup tolerance here is " + formatNumber(tol) +
                                  ": 1e-9 of the scene's diagonal + 1e-12 |x|)";
    if (!(off <= tol))
        return what + ": it lies " + formatNumber(off) + " from its plane" + tolerance;
    const double outside = outsideProjected(mesh, face, n, x);
    if (outside > tol)
        return what + ": it lies " + formatNumber(outside) + " outside its boundary" + tolerance;
    return std::nullopt;
}

namespace {

// The range checks every point query makes first.
void checkQueryRange(const Scene& scene, uint32_t face, std::optional<uint32_t> onlyLight) {
    if (face >= scene.faceCount())
        throw std::out_of_range("face " + std::to_string(face) + " out of range (the scene has " +
                                std::to_string(scene.faceCount()) + " faces)");
    if (onlyLight && *onlyLight >= scene.lights.size())
        throw std::out_of_range("light " + std::to_string(*onlyLight) +
                                " out of range (the scene has " +
                                std::to_string(scene.lights.size()) + " lights)");
}

// Runs `answer(r, lightPolygon)` for every asked light of x on `face` (which fills r's fragments
// and the counters of its path), then the numbers every answer derives from its fragments.
template <class Answer>
std::vector<LightAtPoint> forEachLight(const Scene& scene, uint32_t face, const Vec3& x,
                                       std::optional<uint32_t> onlyLight, Answer&& answer) {
    checkQueryRange(scene, face, onlyLight);
    const vis::PolygonMesh& mesh = scene.mesh;
    const Vec3 normal = unitNormal(mesh, face);
    const vis::FacePlane receiverPlane = vis::facePlane(mesh, face);
    const vis::OrientedPlane receiverFront{receiverPlane.a, receiverPlane.b, receiverPlane.c};
    std::vector<LightAtPoint> out;
    const uint32_t begin = onlyLight ? *onlyLight : 0;
    const uint32_t end = onlyLight ? *onlyLight + 1 : static_cast<uint32_t>(scene.lights.size());
    for (uint32_t k = begin; k < end; ++k) {
        LightAtPoint r;
        r.light = k;
        r.lightFace = scene.lights[k];
        const std::vector<Vec3> lightPolygon = facePolygon(mesh, r.lightFace);
        r.lightArea = vis::polygonArea(lightPolygon);
        if (r.lightFace == face) {
            // A light does not light itself.
            r.kind = vis::PairKind::BackFacing;
            out.push_back(std::move(r));
            continue;
        }
        answer(r);
        r.horizonClipped = vis::anyVertexBehind(lightPolygon, receiverFront);
        for (const vis::Polygon3& fragment : r.fragments) {
            r.visibleArea += vis::polygonArea(fragment);
            r.formFactor += vis::formFactor(x, normal, fragment);
        }
        r.fraction = r.lightArea > 0 ? r.visibleArea / r.lightArea : 0.0;
        r.outline = vis::visibleOutline(r.fragments);
        r.outlineFormFactor = vis::formFactorOfLoops(x, normal, r.outline.loops);
        if (vis::facePlane(mesh, r.lightFace).side(x) == vis::Sign::Positive) {
            const std::vector<Vec3> seen = vis::clipConvexPositive(lightPolygon, receiverFront);
            r.unoccludedFormFactor = vis::formFactor(x, normal, seen);
        }
        out.push_back(std::move(r));
    }
    return out;
}

}  // namespace

vis::AnsweredPoint answeredPointOn(const Scene& scene, uint32_t face, const vis::Vec3& x) {
    checkQueryRange(scene, face, std::nullopt);
    return vis::answeredPoint(vis::facePlane(scene.mesh, face).orient(), x);
}

std::vector<LightAtPoint> queryPoint(VisibilityStore& store, uint32_t face, const Vec3& input,
                                     std::optional<uint32_t> onlyLight) {
    const vis::PolygonMesh& mesh = store.scene().mesh;
    checkQueryRange(store.scene(), face, onlyLight);
    const vis::AnsweredPoint x = answeredPointOn(store.scene(), face, input);
    return forEachLight(store.scene(), face, x.at, onlyLight, [&](LightAtPoint& r) {
        const vis::HistoryTree& tree =
            store.getOrBuild(store.layout().keyAt(face, x.at, r.lightFace)).tree;
        r.kind = tree.kind;
        vis::FromPointResult q = vis::fromPointQuery(mesh, tree, x);
        r.fragments = std::move(q.fragments);
        r.trace = std::move(q.trace);
        r.answeredOnContact = q.answeredOnContact;
        r.nodesVisited = q.nodesVisited;
        r.deferredOccluders = static_cast<uint32_t>(tree.deferred.size());
        r.deferredActive = q.deferredActive;
        r.deferredClips = q.deferredClips;
    });
}

std::vector<LightAtPoint> queryPointDirect(const Scene& scene, const vis::BoxTree& faces,
                                           uint32_t face, const Vec3& input,
                                           std::optional<uint32_t> onlyLight, uint64_t workLimit,
                                           const vis::FaceClusters* groups) {
    checkQueryRange(scene, face, onlyLight);
    const vis::AnsweredPoint x = answeredPointOn(scene, face, input);
    vis::FromPointQuery query;
    query.setWorkLimit(workLimit);
    return forEachLight(scene, face, x.at, onlyLight, [&](LightAtPoint& r) {
        r.fromTree = false;
        const vis::FragmentList& fragments =
            query.runDirect(scene.mesh, face, r.lightFace, x, faces, groups);
        r.complete = !query.limitReached();
        r.faceGroups = query.clustersUsed();
        r.solidGroupsLeftOut = query.solidGroupsLeftOut();
        r.solidFacesLeftOut = query.solidFacesLeftOut();
        r.hiddenBySolid = query.hiddenBySolid();
        r.fragments = fragments.polygons();
    });
}

}  // namespace penumbra
