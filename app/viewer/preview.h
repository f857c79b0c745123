// Preview: the viewer's progressive preview (PreviewRunner, the CPU renderer in the background) as
// the UI uses it: when to restart it, its newest image and the GL texture that holds it (the
// Preview panel's thumbnail), the rendered view (ViewMode::Rendered: that image in the 3D view,
// the line splitting exact from sampled, the pixel inspector's tooltip), and saving what it shows.
//
// Restarts: what it shows changed (settings, mode, view): a new preview at the next poll once the
// camera rests; the camera set or a scene opened: at the next poll; the camera or the view's size
// changing (a drag, the wheel, a column's edge): once it has rested for 200 ms, and meanwhile, in
// the rendered view, a coarse single pass at most every 100 ms, so that the view follows the
// camera blockily without ever waiting for it. The rendered view shows an image only where it
// pictures the view as it is (picturesView: the rasterised scene until then); at rest, without
// one, a coarse pass comes before the full render.
//
// It reads the viewer's options (the preview's settings, the view mode, the split) as they are at
// each call: the viewer's panels and keys edit them.
#pragma once

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include "app/viewer/gl/scene_renderer.h"
#include "app/viewer/layout.h"
#include "app/viewer/loaded_scene.h"
#include "app/viewer/pixel_inspector.h"
#include "app/viewer/preview_runner.h"
#include "app/viewer/viewer_options.h"
#include "app/viewer/viewport.h"
#include "engine/scene/camera.h"

namespace penumbra::viewer {

class Preview {
  public:
    // Needs the GL table current (makes the texture). `options` must outlive the preview.
    explicit Preview(const ViewerOptions& options);
    ~Preview();  // deletes the texture (the runner's destructor waits for its job)
    Preview(const Preview&) = delete;
    Preview& operator=(const Preview&) = delete;

    // What it shows changed (settings, mode, view): a new preview at the next poll once the
    // camera rests.
    void markDirty() { dirty_ = true; }
    // The camera or the view's size is changing: a new preview once it rests.
    void viewChanging() {
        dirty_ = true;
        lastCameraChange_ = std::chrono::steady_clock::now();
    }
    // The camera was set (given, or a scene opened): a new preview at the next poll.
    void cameraJumped() {
        dirty_ = true;
        lastCameraChange_ = {};
    }
    // Another scene: the old one's image and effects say nothing of it (the running job is
    // cancelled).
    void clear();
    // A light moved (a new version of the scene): as a camera move, coarse passes while it goes on
    // and the full render once it rests.
    void lightMoved() { viewChanging(); }
    // Tree-less: the exact passes evaluate every pair without a tree the store does not hold yet
    // (RenderSettings::minTreeSamples at its maximum: prepare builds none, the direct query answers
    // the rest; the same exact answer), so that after a light move the preview does not wait for
    // the trees the background rebuilds. The viewer turns it on while they are rebuilt.
    void setTreeLess(bool treeLess) { treeLess_ = treeLess; }
    bool treeLess() const { return treeLess_; }

    // Once per frame: restarts when due (above), and takes the runner's newest image into the
    // texture. `layout`: the frame's (the previous frame's when called before the new layout).
    void poll(const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
              const Layout& layout);
    // Starts the pending preview now, if one is pending (headless, before waiting for it).
    void restartPending(const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
                        const Layout& layout);

    PreviewRunner& runner() { return runner_; }
    // As the last poll found them (one moment for the whole frame): the newest image, whether the
    // render goes on (more images to come), and what it simulates.
    const PreviewImage& image() const { return image_; }
    bool running() const { return running_; }
    const EffectsSummary& effects() const { return effects_; }
    GLuint texture() const { return texture_; }

    // Whether the 3D view shows the preview's image now: the rendered view, with an image that
    // pictures the view from `camera` (picturesView: a coarse pass counts, an image of the camera
    // before a move or of the view before a resize does not).
    bool showsImage(const Camera& camera, const Viewport& view) const;
    // What the 3D view shows when that is not the preview's image at the view's resolution: a
    // line for the Preview panel ("" in the raster view, or with the full image shown).
    std::string viewNote(const Camera& camera, const Viewport& view) const;
    // The rendered view's image for this frame when it shows one (showsImage), else nullptr:
    // draw the rasterised scene (before the first pass, and while the camera moves faster than
    // the coarse passes follow).
    const ViewImage* viewImage(const Camera& camera, const Viewport& view);
    // Whether the view shows a side-by-side image, split at a line that the mouse may drag.
    bool splitShown(const Camera& camera, const Viewport& view) const;
    // The rendered side-by-side view's split line over `view` (under the windows), with the names
    // of its two sides; nothing in another view or mode, or while the view shows no image.
    void drawSplitLine(const Camera& camera, const Viewport& view) const;
    // The rendered view's pixel inspector: a tooltip for the pixel of `view` under the mouse,
    // unless the mouse is over a window or dragging (`splitDragged`: the split line).
    void drawPixelInspector(const LoadedScene* scene, const Camera& camera, const Viewport& view,
                            bool splitDragged);
    // This frame's pixel report (nullptr: no tooltip).
    const PixelReport* hover() const { return hover_; }

    // Keep what you see: the image as STEM.png (as shown, 8-bit sRGB; side by side: both
    // halves), its linear exact radiance (the sampled one when the mode renders no exact image)
    // as STEM.pfm and STEM.exr (radianceFilm), and the scene with `camera` as STEM.json
    // (engine/io/scene_file.h: `penumbra view STEM.json` or `penumbra render STEM.json --size WxH`
    // give this view again). Every file atomically. False with the reason in `message` (no image
    // yet, a write failed).
    bool save(const std::filesystem::path& stem, const LoadedScene* scene, const Camera& camera,
              std::string& message) const;

  private:
    // At the thumbnail's scale, or at the view's resolution in the rendered view; `coarse`: one
    // pass at kCoarseScale (the rendered view while the camera moves).
    void restart(const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
                 const Layout& layout, bool coarse = false);
    void upload(const PreviewImage& image);

    const ViewerOptions& options_;
    PreviewRunner runner_;
    PreviewImage image_;
    bool running_ = false;
    EffectsSummary effects_;
    GLuint texture_ = 0;
    bool dirty_ = false;
    bool treeLess_ = false;
    uint64_t sceneVersion_ = 0;  // the scene's version at the last poll
    std::chrono::steady_clock::time_point lastCameraChange_, lastCoarseRestart_;
    // The last restart: whether it was a coarse pass, and for which camera and view.
    bool lastCoarse_ = false;
    Camera coarseCamera_;
    Viewport coarseView_;
    ViewImage viewImage_;
    PixelInspector pixelInspector_;
    const PixelReport* hover_ = nullptr;  // this frame's pixel report (the inspector's)
};

}  // namespace penumbra::viewer
