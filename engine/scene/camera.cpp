#include "engine/scene/camera.h"

#include <cmath>
#include <numbers>

namespace penumbra {

void Camera::frame(Vec3& right, Vec3& trueUp, Vec3& forward) const {
    forward = normalize(target - eye);
    right = cross(forward, up);
    if (length(right) < 1e-12) {
        // up parallel to the view direction: pick any perpendicular axis.
        right = cross(forward, std::fabs(forward.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0});
    }
    right = normalize(right);
    trueUp = cross(right, forward);
}

Ray Camera::ray(double px, double py, int width, int height) const {
    return CameraRays(*this, width, height)(px, py);
}

CameraRays::CameraRays(const Camera& camera, int width, int height)
    : eye_(camera.eye), width_(width), height_(height) {
    camera.frame(right_, trueUp_, forward_);
    const double tanHalf = std::tan(camera.fovYDegrees * std::numbers::pi / 360.0);
    const double aspect = static_cast<double>(width) / height;
    scaleX_ = tanHalf * aspect;
    scaleY_ = tanHalf;
}

bool Camera::project(const Vec3& p, int width, int height, double& px, double& py) const {
    Vec3 right, trueUp, forward;
    frame(right, trueUp, forward);
    const Vec3 d = p - eye;
    const double z = dot(d, forward);
    if (z <= 0) return false;
    const double tanHalf = std::tan(fovYDegrees * std::numbers::pi / 360.0);
    const double aspect = static_cast<double>(width) / height;
    const double sx = dot(d, right) / (z * tanHalf * aspect);
    const double sy = dot(d, trueUp) / (z * tanHalf);
    px = (sx + 1.0) * 0.5 * width;
    py = (1.0 - sy) * 0.5 * height;
    return true;
}

Camera Camera::fitting(const vis::Bounds3& box, Vec3 from, double fovYDegrees, Vec3 up) {
    Camera c;
    c.fovYDegrees = fovYDegrees;
    c.up = up;
    c.target = box.empty() ? Vec3{0, 0, 0} : 0.5 * (box.lo + box.hi);
    const double radius = box.empty() ? 1.0 : std::max(0.5 * box.diagonal(), 1e-300);
    const double distance = radius / std::sin(fovYDegrees * std::numbers::pi / 360.0);
    c.eye = c.target + distance * normalize(from);
    return c;
}

}  // namespace penumbra
