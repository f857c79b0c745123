#include "engine/scene/default_light.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "engine/scene/scene.h"
#include "engine/scene/scene_validation.h"
#include "visibility/form_factor.h"

namespace penumbra {
namespace default_light_detail {

std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
}

// The up direction as (axis, sign): the camera's up snapped to its largest component, else +y.
void upAxis(const Scene& scene, int& axis, int& sign, bool& fromCamera) {
    axis = 1;
    sign = 1;
    fromCamera = false;
    if (!scene.camera) return;
    const Vec3 u = scene.camera->up;
    int best = 0;
    for (int i = 1; i < 3; ++i)
        if (std::fabs(u[i]) > std::fabs(u[best])) best = i;
    if (!(std::fabs(u[best]) > 0)) return;  // a zero up: keep the convention
    axis = best;
    sign = u[best] > 0 ? 1 : -1;
    fromCamera = true;
}

Vec3 fromAxes(int axis, double up, int a, double ua, int b, double ub) {
    double c[3] = {0, 0, 0};
    c[axis] = up;
    c[a] = ua;
    c[b] = ub;
    return {c[0], c[1], c[2]};
}

}  // namespace default_light_detail

std::string DefaultLight::upName() const { return std::string(sign > 0 ? "+" : "-") + "xyz"[axis]; }

std::string DefaultLight::announcement(std::string_view file) const {
    using default_light_detail::fmt;
    return std::string(file) + " has no lights: added a default area light, a " + fmt(side) +
           " x " + fmt(side) + " square " + fmt(height) +
           " above the scene, facing down, emission " + fmt(emission) + " (up " + upName() +
           (upFromCamera ? ", the scene camera's" : ", the convention without a camera") +
           "; --no-default-light turns it off)";
}

bool needsDefaultLight(const Scene& scene) {
    return scene.faceCount() > 0 && scene.lights.empty() && scene.pointLights.empty();
}

void addDefaultLight(Scene& scene) {
    using namespace default_light_detail;
    DefaultLight light;
    upAxis(scene, light.axis, light.sign, light.upFromCamera);
    const int k = light.axis, a = (k + 1) % 3, b = (k + 2) % 3;
    const vis::Bounds3 box = scene.fileBounds();
    const double diagonal = box.diagonal();
    const double extA = box.hi[a] - box.lo[a], extB = box.hi[b] - box.lo[b];
    light.side = std::max(extA, extB) > 0 ? 0.25 * std::max(extA, extB) : 0.25 * diagonal;
    light.height = 0.5 * diagonal;
    // The plane strictly beyond the top, whatever the rounding.
    const double top = light.sign > 0 ? box.hi[k] : box.lo[k];
    double plane = top + light.sign * light.height;
    while (light.sign > 0 ? plane <= top : plane >= top)
        plane = std::nextafter(plane, light.sign * HUGE_VAL);
    const double ca = 0.5 * (box.lo[a] + box.hi[a]), cb = 0.5 * (box.lo[b] + box.hi[b]);
    const double a0 = ca - 0.5 * light.side, a1 = ca + 0.5 * light.side;
    const double b0 = cb - 0.5 * light.side, b1 = cb + 0.5 * light.side;
    // (a, b, up) is right-handed: (a0,b0), (a0,b1), (a1,b1), (a1,b0) turns clockwise seen from
    // +up, so its normal is -up; for up = -axis the other order.
    if (light.sign > 0)
        light.corners = {fromAxes(k, plane, a, a0, b, b0), fromAxes(k, plane, a, a0, b, b1),
                         fromAxes(k, plane, a, a1, b, b1), fromAxes(k, plane, a, a1, b, b0)};
    else
        light.corners = {fromAxes(k, plane, a, a0, b, b0), fromAxes(k, plane, a, a1, b, b0),
                         fromAxes(k, plane, a, a1, b, b1), fromAxes(k, plane, a, a0, b, b1)};
    for (const Vec3& c : light.corners)
        if (const auto problem = coordinateProblem(c))
            throw makeSceneError(scene.sourcePath, 0,
                                 "the default light would break the coordinate contract (" +
                                     *problem + "): give the scene a light of its own");
    const Vec3 topCentre = fromAxes(k, top, a, ca, b, cb);
    const double f = vis::formFactor(topCentre, fromAxes(k, light.sign, a, 0, b, 0),
                                     std::span<const Vec3>(light.corners));
    light.emission = 1.0 / f;

    const uint32_t faces = scene.faceCount();
    if (scene.faceMaterial.empty()) scene.faceMaterial.assign(faces, -1);
    if (!scene.faceSourceLine.empty()) scene.faceSourceLine.push_back(0);
    Material m;
    m.name = std::string(kDefaultLightMaterial);
    m.kd = {0, 0, 0};
    m.ke = {light.emission, light.emission, light.emission};
    scene.materials.push_back(m);
    scene.faceMaterial.push_back(static_cast<int32_t>(scene.materials.size() - 1));
    light.firstVertex = static_cast<uint32_t>(scene.mesh.vertices.size());
    std::vector<uint32_t> face;
    for (const Vec3& c : light.corners) {
        face.push_back(static_cast<uint32_t>(scene.mesh.vertices.size()));
        scene.mesh.vertices.push_back(c);
    }
    scene.mesh.faces.push_back(std::move(face));
    light.face = faces;
    scene.lights.push_back(faces);
    scene.defaultLight = light;
    try {
        validateLights(scene);
    } catch (const SceneError& e) {
        throw makeSceneError(
            scene.sourcePath, 0,
            "the default light: " + e.message + ": give the scene a light of its own");
    }
}

}  // namespace penumbra
