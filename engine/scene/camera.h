// Camera: a pinhole camera looking from `eye` at `target`, shared by the renderer and the viewer.
// Image coordinates: pixel (0, 0) is the top-left corner, x to the right, y down; a point (px, py)
// in pixel units (continuous, pixel centres at +0.5) maps to a ray through the image plane.
#pragma once

#include "visibility/bounds3.h"
#include "visibility/vec3.h"

namespace penumbra {

using vis::Vec3;

struct Ray {
    Vec3 origin;
    Vec3 direction;  // unit length
};

struct Camera {
    Vec3 eye{0, 0, 1};
    Vec3 target{0, 0, 0};
    Vec3 up{0, 1, 0};
    double fovYDegrees = 45;  // vertical field of view

    bool operator==(const Camera&) const = default;  // the same view, bit for bit

    // The ray through continuous pixel position (px, py) of a width x height image.
    Ray ray(double px, double py, int width, int height) const;
    // Orthonormal frame: right, true up, forward (unit, forward = normalize(target - eye)).
    void frame(Vec3& right, Vec3& trueUp, Vec3& forward) const;
    // Projects a world point to continuous pixel coordinates; false when it is behind the eye.
    bool project(const Vec3& p, int width, int height, double& px, double& py) const;

    // A camera looking at the whole box from the direction `from` (eye - target, need not be unit),
    // far enough back that the box's bounding sphere fits the vertical field of view.
    static Camera fitting(const vis::Bounds3& box, Vec3 from = {0.3, 0.4, 1.0},
                          double fovYDegrees = 45, Vec3 up = {0, 1, 0});
};

// The primary rays of one camera and image size, with the frame and the image-plane scale formed
// once (Camera::ray forms them per call): for the renderer's per-pixel loop. Same rays as
// Camera::ray, bit for bit.
class CameraRays {
  public:
    CameraRays(const Camera& camera, int width, int height);
    Ray operator()(double px, double py) const {
        const double sx = (2.0 * px / width_ - 1.0) * scaleX_;
        const double sy = (1.0 - 2.0 * py / height_) * scaleY_;
        return {eye_, normalize(forward_ + sx * right_ + sy * trueUp_)};
    }

  private:
    Vec3 eye_, right_, trueUp_, forward_;
    double width_, height_;
    double scaleX_, scaleY_;  // tan(fov / 2) times the aspect ratio, and tan(fov / 2)
};

}  // namespace penumbra
