#include "engine/render/default_camera.h"

#include <cmath>
#include <numbers>
#include <vector>

#include "visibility/face_plane.h"

namespace penumbra {
namespace default_camera_detail {

constexpr int kGrid = 24;

struct Candidate {
    Camera camera;
    int score = 0;               // grid rays hitting the front of a face
    bool seesLightBack = false;  // some ray reaches the back of a light first
    bool eligible() const { return score > 0 && !seesLightBack; }
};

// Whether the eye, strictly behind light face `light`'s plane, sees some of it inside the
// kGrid x kGrid image: rays to its centroid and to its vertices pulled 1% toward it, the ones
// that project into the image, reaching that face first.
bool seesBackOf(const Scene& scene, const EmbreeScene& bvh, const Camera& c, uint32_t light) {
    const auto face = scene.mesh.face(light);
    Vec3 centroid;
    for (uint32_t v : face) centroid += scene.mesh.vertices[v];
    centroid = centroid / static_cast<double>(face.size());
    std::vector<Vec3> targets{centroid};
    for (uint32_t v : face) targets.push_back(scene.mesh.vertices[v] * 0.99 + centroid * 0.01);
    for (const Vec3& t : targets) {
        double px = 0, py = 0;
        if (!c.project(t, kGrid, kGrid, px, py) || px < 0 || py < 0 || px >= kGrid || py >= kGrid)
            continue;
        const auto hit = bvh.intersect(c.eye, t - c.eye);
        if (hit && hit->face == light) return true;
    }
    return false;
}

Candidate evaluate(const Scene& scene, const EmbreeScene& bvh, const Camera& c) {
    Candidate out{c};
    // The lights whose plane the eye is strictly behind (exact): only their backs can be seen.
    std::vector<char> backTowardEye(scene.faceCount(), 0);
    bool anyBack = false;
    for (uint32_t light : scene.lights) {
        if (vis::facePlane(scene.mesh, light).side(c.eye) == vis::Sign::Negative) {
            backTowardEye[light] = 1;
            anyBack = true;
        }
    }
    for (int y = 0; y < kGrid; ++y)
        for (int x = 0; x < kGrid; ++x) {
            const Ray r = c.ray(x + 0.5, y + 0.5, kGrid, kGrid);
            const auto hit = bvh.intersect(r.origin, r.direction);
            if (!hit) continue;
            if (backTowardEye[hit->face]) out.seesLightBack = true;
            if (dot(scene.mesh.faceAreaNormal(hit->face), r.direction) < 0) ++out.score;
        }
    // A light small in the image may fall between the grid's rays.
    if (anyBack && !out.seesLightBack)
        for (uint32_t light : scene.lights)
            if (backTowardEye[light] && seesBackOf(scene, bvh, c, light)) {
                out.seesLightBack = true;
                break;
            }
    return out;
}

// The candidates from the 8 horizontal directions raised by `elevationDegrees`, for up `u`.
std::vector<Candidate> candidates(const Scene& scene, const EmbreeScene& bvh, const Vec3& u,
                                  double elevationDegrees) {
    const vis::Bounds3 bounds = scene.fileBounds();
    const double elevation = std::tan(elevationDegrees * std::numbers::pi / 180);
    // Horizontal directions (in the plane normal to `up`), raised by `elevation` along `up`.
    const double h[8][2] = {{0, -1},      {0, 1},      {-1, 0},     {1, 0},
                            {-0.7, -0.7}, {0.7, -0.7}, {-0.7, 0.7}, {0.7, 0.7}};
    // Two unit directions spanning the plane normal to u (any other up than +y and +z).
    const Vec3 n = normalize(u);
    const Vec3 a = normalize(cross(std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}, n));
    const Vec3 b = cross(n, a);
    std::vector<Candidate> out;
    for (const auto& d : h) {
        const Vec3 from = u == Vec3{0, 1, 0}   ? Vec3{d[0], elevation, d[1]}
                          : u == Vec3{0, 0, 1} ? Vec3{d[0], d[1], elevation}
                                               : a * d[0] + b * d[1] + n * elevation;
        out.push_back(evaluate(scene, bvh, Camera::fitting(bounds, from, 45, u)));
    }
    return out;
}

// The first candidate of highest score, among the eligible ones only when `eligibleOnly`.
const Candidate* best(const std::vector<Candidate>& cs, bool eligibleOnly) {
    const Candidate* b = nullptr;
    for (const Candidate& c : cs)
        if ((!eligibleOnly || c.eligible()) && (b == nullptr || c.score > b->score)) b = &c;
    return b;
}

}  // namespace default_camera_detail

Camera defaultCamera(const Scene& scene, const EmbreeScene& bvh, std::optional<Vec3> up) {
    using namespace default_camera_detail;
    if (scene.camera) {
        Camera c = *scene.camera;
        if (up) c.up = *up;
        return c;
    }
    // y up first (OBJ's usual convention, the Cornell box), then z up (CAD-style scenes).
    const std::vector<Vec3> ups =
        up ? std::vector<Vec3>{*up} : std::vector<Vec3>{Vec3{0, 1, 0}, Vec3{0, 0, 1}};
    std::vector<Candidate> all;
    for (const Vec3& u : ups) {
        const std::vector<Candidate> raised = candidates(scene, bvh, u, 20);
        all.insert(all.end(), raised.begin(), raised.end());
    }
    const Candidate* first = best(all, false);
    if (first->eligible()) return first->camera;
    // It sees the back of a light (or nothing): the best of the others, then of the same
    // directions raised only 5 degrees (an eye below a light that hangs over the scene).
    if (const Candidate* c = best(all, true)) return c->camera;
    std::vector<Candidate> low;
    for (const Vec3& u : ups) {
        const std::vector<Candidate> l = candidates(scene, bvh, u, 5);
        low.insert(low.end(), l.begin(), l.end());
    }
    if (const Candidate* c = best(low, true)) return c->camera;
    return first->camera;
}

}  // namespace penumbra
