// PreviewRunner: the progressive preview of the CPU renderer (engine/render/renderer.h) in the
// viewer. Passes run as oneTBB tasks; the UI thread only polls (takeUpdate: a short mutex to swap
// the newest image). A restart (camera, scene or settings changed) never waits: it raises the
// running job's cancel flag and starts a new job at once; the old job's images are dropped.
//
// Modes: Exact (FPQuery fragments, analytic form factors), Sampled (N shadow rays per light per
// shading point), SideBySide (exact left, sampled right), Difference (heat map of
// |sampled - exact| luminance) and Answers (how the exact render answered each pixel, in the
// colours of engine/render/answers.h). The error figure is the RMS of the luminance difference over
// the image, relative to the exact image's mean luminance: approximate (both images carry
// primary-ray jitter, which vanishes as passes accumulate).
#pragma once

#include <tbb/task_group.h>

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "app/viewer/loaded_scene.h"
#include "engine/render/effects_summary.h"
#include "engine/render/renderer.h"
#include "engine/scene/camera.h"

namespace penumbra::viewer {

enum class PreviewMode { Exact, Sampled, SideBySide, Difference, Answers };
const char* toString(PreviewMode mode);

struct PreviewSettings {
    PreviewMode mode = PreviewMode::Exact;
    int width = 160, height = 120;  // of one image
    int passes = 16;
    int lightSamples = 16;
    double exposure = 1.0;
    ExactOptions exact;  // the exact render's tree threshold and work limit
    // A coarse pass (the viewer's, while the camera moves): one pass at a fraction of the view's
    // resolution, the full render to follow. Said of the image (PreviewImage::coarse).
    bool coarse = false;
};

struct PreviewImage {
    int width = 0, height = 0;     // SideBySide: twice the settings' width
    std::vector<uint8_t> rgba;     // top row first
    int passes = 0;                // passes accumulated in the image
    int passesPlanned = 0;         // of its render (PreviewSettings::passes)
    bool coarse = false;           // a coarse pass (PreviewSettings::coarse)
    double relativeRmsError = -1;  // sampled vs exact (when both are rendered), else -1
    // Difference mode: the |sampled - exact| luminance drawn white (the heat scale's top, a
    // quarter of the exact image's mean luminance) and that mean; 0 in the other modes.
    double differenceWhite = 0, meanExactLuminance = 0;
    std::vector<double> errorHistory;  // relativeRmsError after each pass
    double seconds = 0;                // since the job started
    bool finished = false;
    std::string error;  // a failure of the renderer
    // The linear radiance (mean of the passes, before exposure and tone mapping) of the exact and
    // the sampled image, `imageWidth` * height RGB triples each, rows from the top; empty for an
    // image the mode does not render. What the pixel inspector reads.
    int imageWidth = 0;
    std::vector<float> exactRadiance, sampledRadiance;
    // The exact image's answers (Film::answers), per pixel; empty when it is not rendered.
    std::vector<AnswerCounts> answers;
    Camera camera;                          // the camera it was rendered from
    uint64_t sceneVersion = 0;              // and the scene's version (LoadedScene::version)
    PreviewMode mode = PreviewMode::Exact;  // and the mode
};

// Whether `image` pictures a view of viewWidth x viewHeight pixels from `camera`: rendered from
// that camera for a view of that shape (the same frustum), at any resolution (a coarse pass and
// the thumbnail have fewer pixels than the view). False for no image, an image of another camera
// (the camera moved since) or of another shape (the view was resized since).
bool picturesView(const PreviewImage& image, const Camera& camera, int viewWidth, int viewHeight);

// The image's linear radiance as a film of one pass (what Save view and `screenshot
// --preview-out FILE.pfm|.exr` write): the exact image's, else the sampled one's (a mode that
// renders no exact image); nullopt before either is rendered.
std::optional<Film> radianceFilm(const PreviewImage& image);

class PreviewRunner {
  public:
    PreviewRunner() = default;
    ~PreviewRunner();  // cancels and waits for the running job
    PreviewRunner(const PreviewRunner&) = delete;
    PreviewRunner& operator=(const PreviewRunner&) = delete;

    void restart(std::shared_ptr<LoadedScene> scene, const Camera& camera,
                 const PreviewSettings& settings);
    void stop();  // cancels (non-blocking)
    // Cancels (non-blocking) and forgets the image and the effects: nothing rendered yet (a new
    // scene opens, of which the old job's results say nothing).
    void clear();
    // The newest image when it changed since the last call.
    std::optional<PreviewImage> takeUpdate();
    // Whether the current job has more to publish: started, not cancelled, its last image not
    // yet published (a job is no longer running once its finished image is out).
    bool running() const;
    EffectsSummary effects() const;
    // All three at one moment (under one lock), as the UI shows them together in a frame: an
    // image, whether more are coming and the effects never contradict each other.
    struct Snapshot {
        std::optional<PreviewImage> update;  // takeUpdate()
        bool running = false;
        EffectsSummary effects;
    };
    Snapshot take();
    // Blocks until every job has ended (headless use only, never on an interactive UI thread).
    void wait();

  private:
    struct Job;
    void run(const std::shared_ptr<Job>& job);

    tbb::task_group tasks_;
    mutable std::mutex mutex_;  // guards latest_, changed_, effects_, current_, published_
    std::shared_ptr<Job> current_;
    bool publishedLast_ = false;  // the current job published its finished image
    PreviewImage latest_;
    bool changed_ = false;
    EffectsSummary effects_;
};

}  // namespace penumbra::viewer
