#include "app/viewer/preview_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "app/viewer/palette.h"
#include "engine/io/image_io.h"
#include "engine/render/renderer.h"

namespace penumbra::viewer {

struct PreviewRunner::Job {
    std::shared_ptr<LoadedScene> scene;
    Camera camera;
    PreviewSettings settings;
    std::atomic<bool> cancel{false};
    std::atomic<bool> ended{false};
};

namespace {

double luminance(const Vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

void putPixel(PreviewImage& img, int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    uint8_t* p = img.rgba.data() + (static_cast<size_t>(y) * img.width + x) * 4;
    p[0] = r;
    p[1] = g;
    p[2] = b;
    p[3] = 255;
}

// An RGB image of the film's size (rows from the top) into the preview at column offsetX.
void putRgb(PreviewImage& img, const std::vector<uint8_t>& rgb, const Film& film, int offsetX) {
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const uint8_t* p = rgb.data() + (static_cast<size_t>(y) * film.width + x) * 3;
            putPixel(img, offsetX + x, y, p[0], p[1], p[2]);
        }
}

// The film tone mapped as `penumbra render` writes its PNG (engine/io/image_io.h), so that the
// rendered view shows the same pixels.
void putFilm(PreviewImage& img, const Film& film, int offsetX, double exposure) {
    putRgb(img, toSrgb8(film, exposure), film, offsetX);
}

// The film's mean radiance as RGB floats, rows from the top.
void putRadiance(std::vector<float>& out, const Film& film) {
    out.resize(static_cast<size_t>(film.width) * film.height * 3);
    size_t i = 0;
    for (int y = 0; y < film.height; ++y)
        for (int x = 0; x < film.width; ++x) {
            const Vec3 c = film.mean(x, y);
            out[i++] = static_cast<float>(c.x);
            out[i++] = static_cast<float>(c.y);
            out[i++] = static_cast<float>(c.z);
        }
}

// RMS of the luminance difference relative to the exact image's mean luminance.
double relativeRms(const Film& exact, const Film& sampled) {
    double sumSq = 0, sumExact = 0;
    const size_t n = static_cast<size_t>(exact.width) * exact.height;
    for (int y = 0; y < exact.height; ++y)
        for (int x = 0; x < exact.width; ++x) {
            const double e = luminance(exact.mean(x, y)), s = luminance(sampled.mean(x, y));
            sumSq += (s - e) * (s - e);
            sumExact += e;
        }
    const double mean = sumExact / std::max<size_t>(n, 1);
    return mean > 0 ? std::sqrt(sumSq / std::max<size_t>(n, 1)) / mean : 0.0;
}

}  // namespace

bool picturesView(const PreviewImage& image, const Camera& camera, int viewWidth, int viewHeight) {
    const int w = image.imageWidth, h = image.height;
    if (w <= 0 || h <= 0 || viewWidth <= 0 || viewHeight <= 0 || !(image.camera == camera))
        return false;
    // Rendered for a view of W x H at scale k: w = round(W k), h = round(H k), so that
    // |w H - h W| <= (W + H) / 2 exactly when the shapes agree (to the rounding of w and h).
    const double skew =
        std::fabs(static_cast<double>(w) * viewHeight - static_cast<double>(h) * viewWidth);
    return skew <= 0.5 * (viewWidth + viewHeight);
}

std::optional<Film> radianceFilm(const PreviewImage& image) {
    const std::vector<float>& radiance =
        !image.exactRadiance.empty() ? image.exactRadiance : image.sampledRadiance;
    if (radiance.empty()) return std::nullopt;
    Film film;
    film.reset(image.imageWidth, image.height);
    film.passes = 1;
    for (size_t i = 0; i < film.sum.size(); ++i)
        film.sum[i] = Vec3{radiance[3 * i], radiance[3 * i + 1], radiance[3 * i + 2]};
    return film;
}

const char* toString(PreviewMode mode) {
    switch (mode) {
        case PreviewMode::Exact:
            return "exact";
        case PreviewMode::Sampled:
            return "sampled";
        case PreviewMode::SideBySide:
            return "side by side";
        case PreviewMode::Difference:
            return "difference";
        case PreviewMode::Answers:
            return "answers";
    }
    return "?";
}

PreviewRunner::~PreviewRunner() {
    stop();
    tasks_.wait();
}

void PreviewRunner::restart(std::shared_ptr<LoadedScene> scene, const Camera& camera,
                            const PreviewSettings& settings) {
    auto job = std::make_shared<Job>();
    job->scene = std::move(scene);
    job->camera = camera;
    job->settings = settings;
    {
        const std::lock_guard lock(mutex_);
        if (current_) current_->cancel = true;
        current_ = job;
        publishedLast_ = false;
        latest_ = PreviewImage{};
        changed_ = false;
    }
    tasks_.run([this, job] { run(job); });
}

void PreviewRunner::stop() {
    const std::lock_guard lock(mutex_);
    if (current_) current_->cancel = true;
}

void PreviewRunner::clear() {
    const std::lock_guard lock(mutex_);
    if (current_) current_->cancel = true;
    current_.reset();  // the old job publishes nothing more
    latest_ = PreviewImage{};
    changed_ = false;
    effects_ = EffectsSummary{};
}

bool PreviewRunner::running() const {
    const std::lock_guard lock(mutex_);
    return current_ && !current_->ended && !current_->cancel && !publishedLast_;
}

PreviewRunner::Snapshot PreviewRunner::take() {
    const std::lock_guard lock(mutex_);
    Snapshot s;
    if (changed_) s.update = latest_;
    changed_ = false;
    s.running = current_ && !current_->ended && !current_->cancel && !publishedLast_;
    s.effects = effects_;
    return s;
}

std::optional<PreviewImage> PreviewRunner::takeUpdate() {
    const std::lock_guard lock(mutex_);
    if (!changed_) return std::nullopt;
    changed_ = false;
    return latest_;
}

EffectsSummary PreviewRunner::effects() const {
    const std::lock_guard lock(mutex_);
    return effects_;
}

void PreviewRunner::wait() { tasks_.wait(); }

void PreviewRunner::run(const std::shared_ptr<Job>& job) {
    struct EndMark {
        Job& job;
        ~EndMark() { job.ended = true; }
    } endMark{*job};
    if (job->cancel) return;
    const auto start = std::chrono::steady_clock::now();
    const PreviewSettings& s = job->settings;
    const bool wantExact = s.mode != PreviewMode::Sampled;
    const bool wantSampled = s.mode != PreviewMode::Exact && s.mode != PreviewMode::Answers;
    PreviewImage image;
    image.width = s.mode == PreviewMode::SideBySide ? 2 * s.width : s.width;
    image.height = s.height;
    image.camera = job->camera;
    image.sceneVersion = job->scene->version;
    image.mode = s.mode;
    image.passesPlanned = s.passes;
    image.coarse = s.coarse;
    image.rgba.assign(static_cast<size_t>(image.width) * image.height * 4, 0);
    auto publish = [&](bool finished) {
        image.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        image.finished = finished;
        const std::lock_guard lock(mutex_);
        if (current_ != job) return;
        latest_ = image;
        changed_ = true;
        publishedLast_ = finished;
    };
    LoadedScene& scene = *job->scene;
    try {
        ProgressiveRenderer renderer(scene.scene, *scene.bvh, *scene.store);
        RenderSettings exactSettings;
        exactSettings.width = s.width;
        exactSettings.height = s.height;
        exactSettings.spp = s.passes;
        exactSettings.method = DirectMethod::Exact;
        exactSettings.recordAnswers = true;  // (the answers mode, the pixel inspector)
        s.exact.applyTo(exactSettings);
        RenderSettings sampledSettings = exactSettings;
        sampledSettings.method = DirectMethod::Sampled;
        sampledSettings.lightSamples = s.lightSamples;
        Film exact, sampled;
        exact.reset(s.width, s.height);
        sampled.reset(s.width, s.height);
        if (wantExact) renderer.prepare(job->camera, exactSettings, &job->cancel);
        // What the render simulates, after its first pass: the exact image's (the sampled image
        // beside it in the side-by-side and difference modes is its shadow rays alone), so taken
        // before a sampled pass makes the renderer's summary the sampled one's. Computed outside
        // the lock: the UI thread takes it every frame.
        const auto takeEffects = [&] {
            EffectsSummary effects = renderer.effects();
            const std::lock_guard lock(mutex_);
            if (current_ == job) effects_ = effects;
        };
        for (int pass = 0; pass < s.passes && !job->cancel; ++pass) {
            if (wantExact && !renderer.renderPass(job->camera, exactSettings, exact, &job->cancel))
                return;
            if (pass == 0 && wantExact) takeEffects();
            if (wantSampled &&
                !renderer.renderPass(job->camera, sampledSettings, sampled, &job->cancel))
                return;
            if (pass == 0 && !wantExact) takeEffects();
            switch (s.mode) {
                case PreviewMode::Exact:
                    putFilm(image, exact, 0, s.exposure);
                    break;
                case PreviewMode::Sampled:
                    putFilm(image, sampled, 0, s.exposure);
                    break;
                case PreviewMode::SideBySide:
                    putFilm(image, exact, 0, s.exposure);
                    putFilm(image, sampled, s.width, s.exposure);
                    break;
                case PreviewMode::Difference: {
                    // Heat scale: an error of 25% of the mean exact luminance is white.
                    double meanExact = 0;
                    for (int y = 0; y < s.height; ++y)
                        for (int x = 0; x < s.width; ++x) meanExact += luminance(exact.mean(x, y));
                    meanExact /= std::max(1, s.width * s.height);
                    image.differenceWhite = meanExact > 0 ? 0.25 * meanExact : 1.0;
                    image.meanExactLuminance = meanExact;
                    for (int y = 0; y < s.height; ++y)
                        for (int x = 0; x < s.width; ++x) {
                            const Rgb c = heatColour(std::fabs(luminance(sampled.mean(x, y)) -
                                                               luminance(exact.mean(x, y))) /
                                                     image.differenceWhite);
                            putPixel(image, x, y, c.r, c.g, c.b);
                        }
                    break;
                }
                case PreviewMode::Answers:  // as `penumbra render --out-answers` writes them
                    putRgb(image, answersToRgb8(exact), exact, 0);
                    break;
            }
            image.passes = pass + 1;
            image.imageWidth = s.width;
            if (wantExact) {
                putRadiance(image.exactRadiance, exact);
                image.answers = exact.answers;
            }
            if (wantSampled) putRadiance(image.sampledRadiance, sampled);
            if (wantExact && wantSampled) {
                image.relativeRmsError = relativeRms(exact, sampled);
                image.errorHistory.push_back(image.relativeRmsError);
            }
            publish(pass + 1 == s.passes);
        }
    } catch (const std::exception& e) {
        image.error = e.what();
        publish(true);
    }
}

}  // namespace penumbra::viewer
