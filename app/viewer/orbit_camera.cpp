#include "app/viewer/orbit_camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace penumbra::viewer {
namespace {

// v rotated by `angle` radians about the unit axis k (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& k, double angle) {
    const double c = std::cos(angle), s = std::sin(angle);
    return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

}  // namespace

void OrbitCamera::orbit(double dxPixels, double dyPixels) {
    const double degree = std::numbers::pi / 180;
    const Vec3 up = normalize(camera_.up);
    Vec3 offset = camera_.eye - camera_.target;
    offset = rotate(offset, up, -dxPixels * 0.5 * degree);
    Vec3 right, trueUp, forward;
    camera_.frame(right, trueUp, forward);
    right = normalize(cross(-offset, up));
    const Vec3 tilted = rotate(offset, right, -dyPixels * 0.5 * degree);
    // Refuse a tilt that would bring the view within a degree of the up axis (the frame flips).
    const double cosUp = dot(normalize(tilted), up);
    if (std::fabs(cosUp) < std::cos(degree)) offset = tilted;
    camera_.eye = camera_.target + offset;
}

void OrbitCamera::pan(double dxPixels, double dyPixels, int viewportHeight) {
    Vec3 right, trueUp, forward;
    camera_.frame(right, trueUp, forward);
    const double distance = length(camera_.target - camera_.eye);
    const double worldPerPixel = 2 * distance *
                                 std::tan(camera_.fovYDegrees * std::numbers::pi / 360) /
                                 std::max(viewportHeight, 1);
    const Vec3 shift = right * (-dxPixels * worldPerPixel) + trueUp * (dyPixels * worldPerPixel);
    camera_.eye += shift;
    camera_.target += shift;
}

void OrbitCamera::zoom(double steps) {
    const Vec3 offset = camera_.eye - camera_.target;
    const double scale = std::pow(0.85, steps);
    camera_.eye = camera_.target + offset * std::clamp(scale, 1e-3, 1e3);
}

void OrbitCamera::fit(const vis::Bounds3& box) {
    Vec3 from = camera_.eye - camera_.target;
    if (length(from) == 0) from = {0.3, 0.4, 1.0};
    camera_ = Camera::fitting(box, from, camera_.fovYDegrees, camera_.up);
}

void OrbitCamera::clipRange(const vis::Bounds3& box, double& nearDistance,
                            double& farDistance) const {
    const double radius = box.empty() ? 1.0 : std::max(0.5 * box.diagonal(), 1e-9);
    const Vec3 centre = box.empty() ? Vec3{} : 0.5 * (box.lo + box.hi);
    const double toCentre = length(centre - camera_.eye);
    farDistance = toCentre + 1.05 * radius;
    // Inside or near the box the near plane must come close; 1e-4 of the far distance keeps
    // enough depth precision for a 24-bit buffer.
    nearDistance = std::max(toCentre - 1.05 * radius, 1e-4 * farDistance);
}

}  // namespace penumbra::viewer
