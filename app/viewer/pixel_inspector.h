// PixelInspector: what the rendered view shows under the mouse. For a pixel of the 3D view: its
// linear radiance in the exact and in the sampled image of the preview (when the mode renders
// them, and the preview is at the view's resolution), how the exact render answered it
// (answers.h), and per light the exactly visible fraction
// and form factor of the surface point its centre ray hits (picking.h), from the tree-less exact
// query (point_query.h queryPointDirect) within a small work budget, so that hovering never
// stalls a frame. The answer for the last pixel is kept: a still mouse costs nothing.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "app/viewer/loaded_scene.h"
#include "app/viewer/picking.h"
#include "app/viewer/preview_runner.h"
#include "app/viewer/viewport.h"
#include "engine/precompute/point_query.h"

namespace penumbra::viewer {

struct PixelReport {
    int x = 0, y = 0;                     // in the view, from its top-left corner
    std::optional<Vec3> exact, sampled;   // linear radiance of the pixel in each image
    std::optional<AnswerCounts> answers;  // the exact image's evaluations by answer
    std::optional<PickedPoint> hit;       // the surface point under the pixel's centre
    // Per light, at `hit` (empty without a hit): the direct query's answer; a light whose query
    // reached the work budget has complete = false (its numbers are then a lower bound).
    std::vector<LightAtPoint> lights;
};

class PixelInspector {
  public:
    // Plane tests each light's query may take: about a millisecond at worst.
    static constexpr uint64_t kHoverWork = uint64_t{1} << 15;

    // The report for framebuffer pixel (px, py) of `view` (nullptr outside it). `image` is the
    // preview's newest image: its radiance is read when it has the view's size.
    const PixelReport* inspect(const LoadedScene& scene, const Camera& camera, const Viewport& view,
                               const PreviewImage& image, double px, double py);
    void clear() { valid_ = false; }

  private:
    PixelReport report_;
    bool valid_ = false;
    const LoadedScene* scene_ = nullptr;
    Camera camera_;
    int passes_ = -1;
};

}  // namespace penumbra::viewer
