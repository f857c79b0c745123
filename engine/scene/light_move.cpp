#include "engine/scene/light_move.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <sstream>
#include <unordered_set>

#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace light_move_detail {

// The rotation by `degrees` about coordinate axis `axis` (0 x, 1 y, 2 z), with exact cosines and
// sines at multiples of 90 degrees (std::cos(pi / 2) is 6e-17, not 0: a quarter turn of an
// axis-aligned light would leave it planar only to rounding).
Affine3 axisRotation(int axis, double degrees) {
    double c = 0, s = 0;
    const double quarters = degrees / 90;
    if (quarters == std::round(quarters)) {
        const long q = ((static_cast<long>(std::fmod(quarters, 4.0)) % 4) + 4) % 4;
        constexpr std::array<double, 4> kCos{1, 0, -1, 0}, kSin{0, 1, 0, -1};
        c = kCos[static_cast<size_t>(q)];
        s = kSin[static_cast<size_t>(q)];
    } else {
        const double radians = degrees * (std::numbers::pi / 180);
        c = std::cos(radians);
        s = std::sin(radians);
    }
    Affine3 r;
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane it turns, i towards j
    r.m[i][i] = c;
    r.m[i][j] = -s;
    r.m[j][i] = s;
    r.m[j][j] = c;
    return r;
}

// The linear part of a move: rotate(z) rotate(y) rotate(x) scale.
Affine3 linearPart(const LightMove& move) {
    return axisRotation(2, move.rotateDegrees.z) * axisRotation(1, move.rotateDegrees.y) *
           axisRotation(0, move.rotateDegrees.x) * Affine3::scaling(move.scale);
}

bool isFinite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// The face `vertices` as a mesh of its own, checked as the loader checks a face.
std::optional<FaceDefect> faceDefect(std::span<const Vec3> vertices) {
    vis::PolygonMesh mesh;
    mesh.vertices.assign(vertices.begin(), vertices.end());
    mesh.faces.emplace_back();
    for (uint32_t i = 0; i < vertices.size(); ++i) mesh.faces[0].push_back(i);
    FaceCheckScratch scratch;
    return checkFace(mesh, 0, scratch);
}

// `q` rebuilt in a plane doubles hold exactly (light_move.h). Nullopt when a vertex lies too far
// from the base triangle's span for the exact construction (|a| or |b| above 8: never for a convex
// light, whose base triangle is its largest one from vertex 0).
std::optional<std::vector<Vec3>> exactlyPlanar(std::vector<Vec3> q) {
    const size_t n = q.size();
    double largest = 0;
    for (const Vec3& p : q)
        largest = std::max({largest, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    if (!(largest > 0)) return std::nullopt;
    // Coordinates on the grid 2^e are below 2^(e + 24) in magnitude.
    const int e = std::ilogb(largest) + 1 - 24;
    const auto snap = [e](const Vec3& p) {
        const auto one = [e](double x) { return std::ldexp(std::nearbyint(std::ldexp(x, -e)), e); };
        return Vec3{one(p.x), one(p.y), one(p.z)};
    };
    // The base: vertex 0, the vertex farthest from it, and the one that makes the largest triangle
    // with those two.
    size_t i1 = 1, i2 = 2;
    for (size_t i = 1; i < n; ++i)
        if (vis::length(q[i] - q[0]) > vis::length(q[i1] - q[0])) i1 = i;
    double best = -1;
    for (size_t i = 1; i < n; ++i) {
        const double area = vis::length(vis::cross(q[i1] - q[0], q[i] - q[0]));
        if (i != i1 && area > best) best = area, i2 = i;
    }
    const Vec3 b0 = snap(q[0]), b1 = snap(q[i1]), b2 = snap(q[i2]);
    const Vec3 d1 = b1 - b0, d2 = b2 - b0;  // exact: grid multiples below 2^(e + 25)
    const double g11 = vis::dot(d1, d1), g12 = vis::dot(d1, d2), g22 = vis::dot(d2, d2);
    const double det = g11 * g22 - g12 * g12;
    if (!(det > 0)) return std::nullopt;
    for (size_t i = 0; i < n; ++i) {
        if (i == 0 || i == i1 || i == i2) {
            q[i] = i == 0 ? b0 : i == i1 ? b1 : b2;
            continue;
        }
        // q[i] - b0 ~ a d1 + b d2 (least squares), a and b on the grid 2^-23.
        const Vec3 r = q[i] - b0;
        const double r1 = vis::dot(r, d1), r2 = vis::dot(r, d2);
        const double a =
            std::ldexp(std::nearbyint(std::ldexp((r1 * g22 - r2 * g12) / det, 23)), -23);
        const double b =
            std::ldexp(std::nearbyint(std::ldexp((r2 * g11 - r1 * g12) / det, 23)), -23);
        if (!(std::fabs(a) <= 8 && std::fabs(b) <= 8)) return std::nullopt;
        // Each term and sum exact: in units of 2^(e - 23), b0 is below 2^47 of them, each
        // product below 2^26 * 2^25 = 2^51, the sum below 2^53.
        q[i] = b0 + a * d1 + b * d2;
    }
    return q;
}

std::string number(double x) {
    std::ostringstream out;
    out << x;
    return out.str();
}

std::string lightName(uint32_t light) { return "light " + std::to_string(light); }

}  // namespace light_move_detail

bool LightMove::isIdentity() const { return *this == LightMove{}; }

Affine3 LightMove::worldFromLight(const Vec3& centre) const {
    return Affine3::translation(centre + translate) * light_move_detail::linearPart(*this) *
           Affine3::translation(-1.0 * centre);
}

std::optional<std::string> lightMoveProblem(const LightMove& move) {
    using light_move_detail::isFinite;
    if (!isFinite(move.translate)) return "translate: a coordinate is not finite";
    if (!isFinite(move.rotateDegrees)) return "rotate: an angle is not finite";
    if (!isFinite(move.scale)) return "scale: a factor is not finite";
    const std::array<double, 3> s{move.scale.x, move.scale.y, move.scale.z};
    for (int i = 0; i < 3; ++i)
        if (!(s[static_cast<size_t>(i)] > 0))
            return std::string(
                       "scale: every factor must be positive (0 flattens the light, a "
                       "negative one mirrors it to emit backwards), got ") +
                   light_move_detail::number(s[static_cast<size_t>(i)]) + " along " + "xyz"[i];
    return std::nullopt;
}

Vec3 lightCentre(const Scene& scene, uint32_t light) {
    const std::vector<uint32_t>& face = scene.mesh.faces[scene.lights.at(light)];
    Vec3 sum{0, 0, 0};
    for (uint32_t v : face) sum = sum + scene.mesh.vertices[v];
    return (1.0 / static_cast<double>(face.size())) * sum;
}

std::vector<Vec3> movedLightVertices(const Scene& scene, uint32_t light, const LightMove& move) {
    using namespace light_move_detail;
    const std::string where = lightName(light);
    if (light >= scene.lights.size())
        throw makeSceneError(
            scene.sourcePath, 0,
            where + ": no such light (the scene has " + std::to_string(scene.lights.size()) + ")");
    if (const auto problem = lightMoveProblem(move))
        throw makeSceneError(scene.sourcePath, 0, where + ": " + *problem);
    const Vec3 c = lightCentre(scene, light);
    const Affine3 linear = linearPart(move);
    std::vector<Vec3> q;
    for (uint32_t v : scene.mesh.faces[scene.lights[light]]) {
        const Vec3 p = scene.mesh.vertices[v];
        const Vec3 d = p - c;
        // p + t + (L d - d): a translation alone adds t to each coordinate, as one would by hand.
        q.push_back((p + move.translate) + (linear.vector(d) - d));
    }
    const std::optional<FaceDefect> defect = faceDefect(q);
    if (defect && defect->kind == FaceDefect::Kind::NonPlanar)
        if (std::optional<std::vector<Vec3>> planar = exactlyPlanar(q)) return std::move(*planar);
    return q;  // placeLight refuses what is still wrong, with the reason
}

void placeLight(Scene& scene, uint32_t light, std::span<const Vec3> vertices,
                const std::string& where) {
    using namespace light_move_detail;
    const auto fail = [&](const std::string& message) {
        throw makeSceneError(scene.sourcePath, 0, where + ": " + message);
    };
    if (light >= scene.lights.size())
        fail("no such light (the scene has " + std::to_string(scene.lights.size()) + ")");
    const uint32_t f = scene.lights[light];
    std::vector<uint32_t>& face = scene.mesh.faces[f];
    if (vertices.size() != face.size())
        fail("expected " + std::to_string(face.size()) + " vertices (light " +
             std::to_string(light) + " is face " + std::to_string(f) + "), got " +
             std::to_string(vertices.size()));
    for (size_t i = 0; i < vertices.size(); ++i)
        if (const auto problem = coordinateProblem(vertices[i]))
            fail("vertex " + std::to_string(i) + ": " + *problem);
    if (const auto defect = faceDefect(vertices))
        fail("the moved light is not a face the scene contract accepts: " + defect->message);

    // Shared vertices: the face gets its own.
    const std::unordered_set<uint32_t> own(face.begin(), face.end());
    bool shared = false;
    for (uint32_t g = 0; g < scene.faceCount() && !shared; ++g)
        if (g != f)
            for (uint32_t v : scene.mesh.faces[g])
                if (own.count(v) > 0) {
                    shared = true;
                    break;
                }
    const std::vector<uint32_t> oldFace = face;
    const size_t oldVertexCount = scene.mesh.vertices.size();
    std::vector<Vec3> oldPositions;
    for (uint32_t v : face) oldPositions.push_back(scene.mesh.vertices[v]);
    for (size_t i = 0; i < face.size(); ++i) {
        if (shared) {
            face[i] = static_cast<uint32_t>(scene.mesh.vertices.size());
            scene.mesh.vertices.push_back(vertices[i]);
        } else {
            scene.mesh.vertices[face[i]] = vertices[i];
        }
    }
    if (const auto problem = lightAreaProblem(scene.mesh, f, scene.mesh.bounds().diagonal())) {
        for (size_t i = 0; i < oldFace.size(); ++i)
            scene.mesh.vertices[oldFace[i]] = oldPositions[i];
        face = oldFace;
        scene.mesh.vertices.resize(oldVertexCount);
        fail(*problem);
    }
    if (scene.defaultLight && scene.defaultLight->face == f && face.size() == 4)
        for (size_t i = 0; i < 4; ++i) scene.defaultLight->corners[i] = vertices[i];
}

void moveLight(Scene& scene, uint32_t light, const LightMove& move) {
    const std::vector<Vec3> vertices = movedLightVertices(scene, light, move);
    placeLight(scene, light, vertices, light_move_detail::lightName(light));
}

}  // namespace penumbra
