// OrbitCamera: the viewer's interactive camera, a penumbra::Camera moved by orbit (rotate about
// the target), pan (move eye and target in the image plane) and zoom (move the eye along the view
// direction), plus fit-to-scene.
#pragma once

#include "engine/scene/camera.h"
#include "visibility/bounds3.h"

namespace penumbra::viewer {

class OrbitCamera {
  public:
    OrbitCamera() = default;
    explicit OrbitCamera(const Camera& camera) : camera_(camera) {}

    const Camera& camera() const { return camera_; }
    void set(const Camera& camera) { camera_ = camera; }

    // Rotates by dx, dy pixels of mouse motion (0.5 degree per pixel) about the up axis through the
    // target and about the image's right axis; the view direction stays > 1 degree from the up
    // axis.
    void orbit(double dxPixels, double dyPixels);
    // Moves eye and target so that the point under the cursor at the target's depth follows it.
    void pan(double dxPixels, double dyPixels, int viewportHeight);
    // Wheel steps: each brings the eye 15% closer to the target (negative: further).
    void zoom(double steps);
    // The whole box in view from the current direction (Camera::fitting).
    void fit(const vis::Bounds3& box);

    // Near and far clip distances covering the box from the eye (for the GL projection only).
    void clipRange(const vis::Bounds3& box, double& nearDistance, double& farDistance) const;

  private:
    Camera camera_;
};

}  // namespace penumbra::viewer
