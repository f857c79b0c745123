#include "engine/scene/scene_validation.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "visibility/orient2d.h"
#include "visibility/predicates.h"

namespace penumbra {
namespace {

using vis::Vec3;
using P2 = vis::Point2;
using vis::collinear3;
using vis::orient2d;
using vis::orient2dFiltered;
using vis::project;

// ---- per-face checks ----------------------------------------------------------------------------

std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

using Kind = FaceDefect::Kind;
FaceDefect degenerate(std::string message) {
    return FaceDefect{Kind::Degenerate, std::move(message)};
}
FaceDefect invalid(std::string message) { return FaceDefect{Kind::Invalid, std::move(message)}; }
FaceDefect nonPlanar(std::string message) {
    return FaceDefect{Kind::NonPlanar, std::move(message)};
}
FaceDefect nonConvex(std::string message) {
    return FaceDefect{Kind::NonConvex, std::move(message)};
}

// The face's indices alone: at least 3, all in range. A repeated index goes to `repeated`.
std::optional<FaceDefect> indexDefect(const std::vector<uint32_t>& idx, size_t nv,
                                      std::vector<uint32_t>& sorted,
                                      std::optional<std::string>& repeated) {
    const size_t k = idx.size();
    if (k < 3) {
        return invalid("only " + std::to_string(k) + " vertices (a face needs at least 3)");
    }
    for (uint32_t i : idx) {
        if (i >= nv) {
            return invalid("vertex index " + std::to_string(i) + " out of range (scene has " +
                           std::to_string(nv) + " vertices)");
        }
    }
    sorted.assign(idx.begin(), idx.end());
    std::sort(sorted.begin(), sorted.end());
    const auto dup = std::adjacent_find(sorted.begin(), sorted.end());
    if (dup != sorted.end()) repeated = "vertex index " + std::to_string(*dup) + " repeated";
    return std::nullopt;
}

// Reads the face's positions into p: all coordinates finite. Two consecutive positions equal go
// to `repeated`.
std::optional<FaceDefect> positionDefect(const vis::PolygonMesh& mesh,
                                         const std::vector<uint32_t>& idx, std::vector<Vec3>& p,
                                         std::optional<std::string>& repeated) {
    const size_t k = idx.size();
    p.resize(k);
    for (size_t i = 0; i < k; ++i) {
        p[i] = mesh.vertices[idx[i]];
        if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z)) {
            return invalid("vertex " + std::to_string(idx[i]) + " has a non-finite coordinate");
        }
    }
    for (size_t i = 0; i < k && !repeated; ++i) {
        if (p[i] == p[(i + 1) % k]) {
            repeated = "zero-length edge: vertices " + std::to_string(idx[i]) + " and " +
                       std::to_string(idx[(i + 1) % k]) + " coincide";
        }
    }
    return std::nullopt;
}

// The first vertex off the line through p[0] and p[1] (distinct, see positionDefect), decided
// exactly; 0 when every vertex is on it.
size_t firstVertexOffLine(const std::vector<Vec3>& p) {
    size_t offLine = 0;
    for (size_t i = 2; i < p.size() && offLine == 0; ++i) {
        if (!collinear3(p[0], p[1], p[i])) offLine = i;
    }
    return offLine;
}

// Whether the face's distinct positions all lie on one line (zero area), exactly; for a face
// with repeated positions.
bool allCollinear(const std::vector<Vec3>& p) {
    size_t second = 1;
    while (second < p.size() && p[second] == p[0]) ++second;
    for (size_t i = second + 1; i < p.size(); ++i)
        if (!(p[i] == p[0]) && !(p[i] == p[second]) && !collinear3(p[0], p[second], p[i]))
            return false;
    return true;
}

// An approximate normal of the face, computed on copies q of its vertices scaled so that nothing
// overflows; `exponent` turns lengths in q back into scene units (ldexp).
struct ScaledFace {
    Vec3 normal;
    int exponent = 0;
};

ScaledFace scaledNormal(const std::vector<Vec3>& p, size_t offLine, std::vector<Vec3>& q) {
    const size_t k = p.size();
    // Scale by powers of two (exact up to underflow, which does not matter for an approximate
    // plane) so that nothing overflows: first to magnitude < 1, then, after centring on the
    // centroid, to an extent of about 1 so that a small face far from the origin keeps its digits.
    // `exponent` undoes both scalings.
    auto exponentOf = [](double m) {
        int e = 0;
        if (m > 0 && std::isfinite(m)) std::frexp(m, &e);
        return e;
    };
    auto scaleAll = [](std::vector<Vec3>& pts, int e) {
        for (Vec3& a : pts) a = {std::ldexp(a.x, -e), std::ldexp(a.y, -e), std::ldexp(a.z, -e)};
    };
    q.assign(p.begin(), p.end());
    double magnitude = 0;
    for (const Vec3& a : q) magnitude = std::fmax(magnitude, vis::maxAbs(a));
    int exponent = exponentOf(magnitude);
    scaleAll(q, exponent);
    Vec3 centroid{};
    for (const Vec3& a : q) centroid += a;
    centroid = centroid / static_cast<double>(k);
    double extent = 0;
    for (Vec3& a : q) {
        a -= centroid;
        extent = std::fmax(extent, vis::maxAbs(a));
    }
    const int second = exponentOf(extent);
    scaleAll(q, second);
    exponent += second;
    Vec3 n{};
    for (size_t i = 0; i < k; ++i) n += vis::cross(q[i], q[(i + 1) % k]);
    if (n == Vec3{}) {
        // Zero net area (a bow tie with equal lobes): fall back to a non-collinear vertex triple;
        // such a face is rejected below anyway.
        n = vis::cross(q[1] - q[0], q[offLine] - q[0]);
    }
    return {n, exponent};
}

// The face diameter of the planarity tolerance (scene_validation.h).
double diameterOf(const std::vector<Vec3>& q) {
    const size_t k = q.size();
    double diameter = 0;
    if (k <= 1024) {
        for (size_t i = 0; i < k; ++i)
            for (size_t j = i + 1; j < k; ++j) diameter = std::fmax(diameter, length(q[i] - q[j]));
    } else {
        Vec3 lo = q[0], hi = q[0];
        for (const Vec3& qi : q) {
            lo = {std::fmin(lo.x, qi.x), std::fmin(lo.y, qi.y), std::fmin(lo.z, qi.z)};
            hi = {std::fmax(hi.x, qi.x), std::fmax(hi.y, qi.y), std::fmax(hi.z, qi.z)};
        }
        diameter = length(hi - lo);
    }
    return diameter;
}

// Exact planarity: every vertex in the plane of p[0], p[1] and p[offLine] (not collinear), by the
// exact orient3d sign. The message gives the largest deviation, approximately (on the centred and
// scaled vertices q).
std::optional<FaceDefect> planarityDefect(const std::vector<uint32_t>& idx,
                                          const std::vector<Vec3>& p, size_t offLine,
                                          const std::vector<Vec3>& q, const ScaledFace& face) {
    const size_t k = p.size();
    size_t off = 0;
    for (size_t i = 2; i < k && off == 0; ++i)
        if (i != offLine && vis::orientSign(p[0], p[1], p[offLine], p[i]) != vis::Sign::Zero)
            off = i;
    if (off == 0) return std::nullopt;
    const Vec3 unit = vis::normalize(face.normal);
    size_t worst = off;
    double deviation = -1;
    for (size_t i = 0; i < k; ++i) {
        const double d = std::fabs(dot(q[i], unit));
        if (d > deviation) {
            deviation = d;
            worst = i;
        }
    }
    return nonPlanar("non-planar: vertex " + std::to_string(idx[off]) +
                     " lies off the plane of vertices " + std::to_string(idx[0]) + ", " +
                     std::to_string(idx[1]) + " and " + std::to_string(idx[offLine]) +
                     " (exact test; the largest deviation, vertex " + std::to_string(idx[worst]) +
                     ", is about " + fmt(std::ldexp(deviation, face.exponent)) +
                     " from the plane through the centroid, face diameter " +
                     fmt(std::ldexp(diameterOf(q), face.exponent)) + ")");
}

// The coordinate axis d whose dropping projects the face with every turn strict: into `axis`,
// with the projected vertices in scratch.s and the turn signs in scratch.turn. The axes are tried
// in the order of the normal's dominant component: with (u, v) = (d+1, d+2) mod 3 the projected
// polygon's signed area has the sign of n[d]. A zero turn is either true collinearity in 3D (an
// error) or, for a sliver so thin that the approximate n picked an axis the face is exactly
// parallel to, an artefact of the projection: then the next axis is tried (for a planar face some
// axis has a nonzero normal component, and every turn is strict in that projection).
std::optional<FaceDefect> strictProjection(const std::vector<uint32_t>& idx,
                                           const std::vector<Vec3>& p, const Vec3& n,
                                           FaceCheckScratch& scratch, int& axis) {
    const size_t k = p.size();
    int order[3] = {0, 1, 2};
    std::stable_sort(order, order + 3,
                     [&](int a, int b) { return std::fabs(n[a]) > std::fabs(n[b]); });
    std::vector<P2>& s = scratch.s;
    std::vector<int>& turn = scratch.turn;
    s.resize(k);
    turn.resize(k);
    int d = -1;
    for (int attempt = 0; attempt < 3 && d < 0; ++attempt) {
        const int candidate = order[attempt];
        const int u = (candidate + 1) % 3, v = (candidate + 2) % 3;
        for (size_t i = 0; i < k; ++i) s[i] = project(p[i], u, v);
        bool spurious = false;
        for (size_t i = 0; i < k && !spurious; ++i) {
            const size_t prev = (i + k - 1) % k, next = (i + 1) % k;
            turn[i] = orient2d(s[prev], s[i], s[next]);
            if (turn[i] != 0) continue;
            if (collinear3(p[prev], p[i], p[next])) {
                return nonConvex("collinear vertices: vertex " + std::to_string(idx[i]) +
                                 " lies on the line through its neighbours " +
                                 std::to_string(idx[prev]) + " and " + std::to_string(idx[next]) +
                                 " (zero turn)");
            }
            spurious = true;
        }
        if (!spurious) d = candidate;
    }
    if (d < 0) return nonConvex("non-convex: no projection keeps every turn strict");
    axis = d;
    return std::nullopt;
}

// How often the edge direction of the projected polygon s passes angle 0 going round (in the
// counter-clockwise frame: `flip` -1 mirrors a clockwise polygon, exactly): once for a convex
// polygon, more for a star. Each strict turn rotates the direction by less than pi, so the count
// of transitions from the lower half-plane [pi, 2pi) to the upper [0, pi) is exactly the number
// of revolutions. Only signs of coordinate differences are used, and those are exact in doubles.
size_t revolutions(const std::vector<P2>& s, double flip) {
    const size_t k = s.size();
    auto upperHalf = [&](size_t i) {
        const P2& a = s[i];
        const P2& b = s[(i + 1) % k];
        const double du = b.u - a.u, dv = flip * (b.v - a.v);
        return dv > 0 || (dv == 0 && du > 0);
    };
    size_t count = 0;
    for (size_t i = 0; i < k; ++i) {
        if (!upperHalf(i) && upperHalf((i + 1) % k)) ++count;
    }
    return count;
}

// Strict convexity, given strict turns in the projection that drops `axis` (strictProjection):
// all turns the same way, and the boundary going round once.
std::optional<FaceDefect> convexityDefect(const std::vector<uint32_t>& idx, const Vec3& n, int axis,
                                          const FaceCheckScratch& scratch) {
    const std::vector<int>& turn = scratch.turn;
    const size_t k = turn.size();
    bool allPositive = true, allNegative = true;
    for (size_t i = 0; i < k; ++i) {
        allPositive = allPositive && turn[i] > 0;
        allNegative = allNegative && turn[i] < 0;
    }
    if (!allPositive && !allNegative) {
        const int expected = n[axis] > 0 ? 1 : -1;
        for (size_t i = 0; i < k; ++i) {
            if (turn[i] != expected) {
                return nonConvex("non-convex: reflex vertex " + std::to_string(idx[i]) +
                                 " (the face turns the other way there)");
            }
        }
    }
    const size_t count = revolutions(scratch.s, allPositive ? 1.0 : -1.0);
    if (count != 1) {
        return nonConvex("non-convex: self-intersecting (the boundary winds " +
                         std::to_string(count) + " times around)");
    }
    return std::nullopt;
}

}  // namespace

std::optional<FaceDefect> checkFace(const vis::PolygonMesh& mesh, uint32_t f,
                                    FaceCheckScratch& scratch) {
    const std::vector<uint32_t>& idx = mesh.faces[f];
    std::optional<std::string> repeated;
    if (auto defect = indexDefect(idx, mesh.vertices.size(), scratch.sorted, repeated))
        return defect;
    if (auto defect = positionDefect(mesh, idx, scratch.p, repeated)) return defect;
    if (repeated) {
        if (allCollinear(scratch.p))
            return degenerate("degenerate (zero area): " + *repeated +
                              ", and the other vertices are collinear");
        return nonConvex(*repeated);
    }
    const size_t offLine = firstVertexOffLine(scratch.p);
    if (offLine == 0) return degenerate("degenerate (zero area): all vertices are collinear");
    const ScaledFace scaled = scaledNormal(scratch.p, offLine, scratch.q);
    // Triangles are planar.
    if (idx.size() > 3) {
        if (auto defect = planarityDefect(idx, scratch.p, offLine, scratch.q, scaled))
            return defect;
    }
    int axis = -1;
    if (auto defect = strictProjection(idx, scratch.p, scaled.normal, scratch, axis)) return defect;
    if (auto defect = convexityDefect(idx, scaled.normal, axis, scratch)) return defect;
    // Convex and not collinear, but so thin that its area rounds to zero in doubles (a sliver of
    // 1e-80 on a unit scene, found by fuzzing): a light's visible fraction divides by its area, so
    // such a face counts as degenerate too.
    if (!(mesh.faceArea(f) > 0))
        return degenerate("degenerate: its area rounds to zero (a sliver below double precision)");
    return std::nullopt;
}

std::optional<std::string> coordinateProblem(const Vec3& p) {
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(p[i])) return "non-finite coordinate";
        if (std::fabs(p[i]) > kMaxCoordinate)
            return "coordinate " + fmt(p[i]) +
                   " beyond the supported magnitude 2^59 = 5.8e17 (README, scene contract)";
    }
    return std::nullopt;
}

double lightResolutionWeight(const vis::PolygonMesh& mesh, uint32_t f, double sceneSize) {
    // W = sum over axes i of M_i (E_j + E_k): M_i the largest |coordinate| along i, or the scene's
    // size S (its bounding box's diagonal) when larger, E the face's extents along the other two
    // axes (a rounding of u M_i along i moves the area by at most that times the extent across it;
    // the planes through a point x and the occluders' edges decide the light's vertices to within
    // about u |y - x| <= u S).
    double m[3] = {sceneSize, sceneSize, sceneSize}, lo[3], hi[3];
    for (int i = 0; i < 3; ++i) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
    }
    for (uint32_t v : mesh.faces[f]) {
        const Vec3& p = mesh.vertices[v];
        for (int i = 0; i < 3; ++i) {
            m[i] = std::max(m[i], std::fabs(p[i]));
            lo[i] = std::min(lo[i], p[i]);
            hi[i] = std::max(hi[i], p[i]);
        }
    }
    double w = 0;
    for (int i = 0; i < 3; ++i)
        w += m[i] * ((hi[(i + 1) % 3] - lo[(i + 1) % 3]) + (hi[(i + 2) % 3] - lo[(i + 2) % 3]));
    return w;
}

std::optional<std::string> lightAreaProblem(const vis::PolygonMesh& mesh, uint32_t f,
                                            double sceneSize) {
    const double area = mesh.faceArea(f);
    const double least = kMinLightAreaFactor * lightResolutionWeight(mesh, f, sceneSize);
    if (area > least) return std::nullopt;
    return "an area light of area " + fmt(area) +
           ", too thin for doubles to resolve where it lies (the least is 2^-40 * W = " +
           fmt(least) +
           ", W the sum over the axes of the largest coordinate, or the scene's size when larger, "
           "times the light's extents across it; README, scene contract)";
}

void validateSceneStructure(const Scene& scene) {
    const vis::PolygonMesh& mesh = scene.mesh;
    const std::string& file = scene.sourcePath;
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
        if (const auto problem = coordinateProblem(mesh.vertices[v]))
            throw makeSceneError(file, 0, "vertex " + std::to_string(v) + ": " + *problem);
    for (size_t k = 0; k < scene.pointLights.size(); ++k)
        if (const auto problem = coordinateProblem(scene.pointLights[k].position))
            throw makeSceneError(file, 0, "point light " + std::to_string(k) + ": " + *problem);
    if (scene.camera) {
        for (const Vec3* p : {&scene.camera->eye, &scene.camera->target})
            if (const auto problem = coordinateProblem(*p))
                throw makeSceneError(file, 0, "camera: " + *problem);
    }
    if (mesh.vertices.size() > kMaxSceneElements) {
        throw makeSceneError(
            file, 0,
            "too many vertices (" + std::to_string(mesh.vertices.size()) + ", the limit is 2^30)");
    }
    if (mesh.faces.size() > kMaxSceneElements) {
        throw makeSceneError(
            file, 0,
            "too many faces (" + std::to_string(mesh.faces.size()) + ", the limit is 2^30)");
    }
    const size_t nf = mesh.faces.size();
    if (!scene.faceMaterial.empty() && scene.faceMaterial.size() != nf) {
        throw makeSceneError(file, 0,
                             "faceMaterial has " + std::to_string(scene.faceMaterial.size()) +
                                 " entries for " + std::to_string(nf) + " faces");
    }
    if (!scene.faceSourceLine.empty() && scene.faceSourceLine.size() != nf) {
        throw makeSceneError(file, 0,
                             "faceSourceLine has " + std::to_string(scene.faceSourceLine.size()) +
                                 " entries for " + std::to_string(nf) + " faces");
    }
    for (uint32_t f = 0; f < scene.faceMaterial.size(); ++f) {
        const int32_t m = scene.faceMaterial[f];
        if (m < -1 || (m >= 0 && static_cast<size_t>(m) >= scene.materials.size())) {
            const int64_t line = f < scene.faceSourceLine.size() ? scene.faceSourceLine[f] : 0;
            throw makeSceneError(file, line,
                                 "face " + std::to_string(f) + ": material index " +
                                     std::to_string(m) + " out of range (scene has " +
                                     std::to_string(scene.materials.size()) + " materials)");
        }
    }
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const int32_t image = scene.materials[m].kdMap.image;
        if (image < -1 || (image >= 0 && static_cast<size_t>(image) >= scene.textures.size()))
            throw makeSceneError(file, 0,
                                 "material " + std::to_string(m) + ": texture index " +
                                     std::to_string(image) + " out of range (scene has " +
                                     std::to_string(scene.textures.size()) + " textures)");
    }
    for (size_t t = 0; t < scene.textures.size(); ++t) {
        const TextureImage& image = scene.textures[t];
        if (image.width < 1 || image.height < 1 ||
            image.srgb.size() != 3 * static_cast<size_t>(image.width) * image.height)
            throw makeSceneError(file, 0,
                                 "texture " + std::to_string(t) + " (" + image.source +
                                     "): its texels do not match its size");
    }
    if (!scene.faceUv.empty() && scene.faceUv.size() != nf) {
        throw makeSceneError(file, 0,
                             "faceUv has " + std::to_string(scene.faceUv.size()) + " entries for " +
                                 std::to_string(nf) + " faces");
    }
    for (uint32_t f = 0; f < scene.faceUv.size(); ++f) {
        const std::vector<Uv>& uvs = scene.faceUv[f];
        const int64_t line = f < scene.faceSourceLine.size() ? scene.faceSourceLine[f] : 0;
        if (!uvs.empty() && uvs.size() != mesh.faces[f].size())
            throw makeSceneError(file, line,
                                 "face " + std::to_string(f) + ": " + std::to_string(uvs.size()) +
                                     " texture coordinates for " +
                                     std::to_string(mesh.faces[f].size()) + " vertices");
        for (const Uv& uv : uvs)
            if (!std::isfinite(uv.u) || !std::isfinite(uv.v))
                throw makeSceneError(
                    file, line, "face " + std::to_string(f) + ": non-finite texture coordinate");
    }
    for (uint32_t light : scene.lights) {
        if (light >= nf) {
            throw makeSceneError(file, 0,
                                 "light face " + std::to_string(light) +
                                     " out of range (scene has " + std::to_string(nf) + " faces)");
        }
    }
    validateLights(scene);
}

void validateLights(const Scene& scene) {
    if (scene.lights.empty()) return;
    const double sceneSize = scene.mesh.bounds().diagonal();  // once: a scene may have many lights
    for (uint32_t light : scene.lights) {
        if (light >= scene.faceCount() || scene.mesh.faces[light].size() < 3)
            continue;  // validateSceneStructure and checkFace report these
        if (const auto problem = lightAreaProblem(scene.mesh, light, sceneSize)) {
            const int64_t line =
                light < scene.faceSourceLine.size() ? scene.faceSourceLine[light] : 0;
            throw makeSceneError(scene.sourcePath, line,
                                 "face " + std::to_string(light) + ": " + *problem);
        }
    }
}

void validateScene(const Scene& scene) {
    validateSceneStructure(scene);
    FaceCheckScratch scratch;
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        if (std::optional<FaceDefect> defect = checkFace(scene.mesh, f, scratch)) {
            const int64_t line = f < scene.faceSourceLine.size() ? scene.faceSourceLine[f] : 0;
            throw makeSceneError(scene.sourcePath, line,
                                 "face " + std::to_string(f) + ": " + defect->message);
        }
    }
}

}  // namespace penumbra
