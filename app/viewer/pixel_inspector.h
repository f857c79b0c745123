// PixelInspector: what the rendered view shows under the mouse. For a pixel of the 3D view: its
// linear radiance in the exact and in the sampled image of the preview (when the mode renders
// them, and the image pictures this view: the pixel of a coarse pass covering it while the full
// render runs, nothing while the image is of another camera), how the exact render answered it
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

// Where a pixel's radiance comes from: the preview's image at the view's resolution; a coarser
// image of the same view (a coarse pass while the camera moved, the thumbnail: one of its pixels
// covers several of the view's); or none: no image yet, or one of another camera or view shape
// (the camera moved or the view was resized since, and the new image is being rendered).
enum class PixelSource { NoImage, ViewPixel, CoarsePixel, OtherView };
const char* toString(PixelSource source);  // "none", "view", "coarse", "other view"

struct PixelReport {
    int x = 0, y = 0;  // in the view, from its top-left corner
    PixelSource source = PixelSource::NoImage;
    int imageX = 0, imageY = 0;  // the image's pixel read (ViewPixel, CoarsePixel)
    int imageWidth = 0, imageHeight = 0;
    // Linear radiance of that pixel in each image; none for an image the preview's mode does not
    // render, or no source.
    std::optional<Vec3> exact, sampled;
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
    // preview's newest image: its radiance is read when it pictures this view from `camera`
    // (picturesView), at the image's pixel covering (px, py).
    const PixelReport* inspect(const LoadedScene& scene, const Camera& camera, const Viewport& view,
                               const PreviewImage& image, double px, double py);
    void clear() { valid_ = false; }

  private:
    PixelReport report_;
    bool valid_ = false;
    const LoadedScene* scene_ = nullptr;
    Camera camera_;
    int passes_ = -1;
    // Of the image the report read (a coarse pass and the full one differ in width, the image of
    // the camera before and of this one in camera).
    int imageWidth_ = -1;
    Camera imageCamera_;
};

}  // namespace penumbra::viewer
