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

}  // namespace penumbra
