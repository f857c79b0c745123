#include "app/viewer/pixel_inspector.h"

#include <cmath>

namespace penumbra::viewer {

namespace {

std::optional<Vec3> radianceAt(const std::vector<float>& radiance, int width, int height, int x,
                               int y) {
    if (radiance.size() != static_cast<size_t>(width) * height * 3 || x < 0 || y < 0 ||
        x >= width || y >= height)
        return std::nullopt;
    const float* p = radiance.data() + (static_cast<size_t>(y) * width + x) * 3;
    return Vec3{p[0], p[1], p[2]};
}

bool sameCamera(const Camera& a, const Camera& b) {
    return a.eye == b.eye && a.target == b.target && a.up == b.up && a.fovYDegrees == b.fovYDegrees;
}

}  // namespace

const PixelReport* PixelInspector::inspect(const LoadedScene& scene, const Camera& camera,
                                           const Viewport& view, const PreviewImage& image,
                                           double px, double py) {
    if (!view.contains(px, py)) return nullptr;
    const int x = static_cast<int>(std::floor(px)) - view.x;
    const int y = static_cast<int>(std::floor(py)) - view.y;
    const bool samePixel = valid_ && report_.x == x && report_.y == y && scene_ == &scene &&
                           sameCamera(camera_, camera);
    if (samePixel && passes_ == image.passes) return &report_;
    if (!samePixel) {
        // A new pixel: its surface point and the lights' exact answers there.
        report_ = PixelReport{};
        report_.x = x;
        report_.y = y;
        report_.hit = pickSurface(scene.scene, *scene.bvh, camera, view, px, py);
        if (report_.hit)
            report_.lights = queryPointDirect(scene.scene, scene.bvh->faceBoxes(),
                                              report_.hit->face, report_.hit->point, std::nullopt,
                                              kHoverWork, &scene.bvh->faceClusters());
    }
    // The radiance follows the preview's passes (the image refines under a still mouse).
    const int h = image.height;
    report_.exact = radianceAt(image.exactRadiance, image.imageWidth, h, x, y);
    report_.sampled = radianceAt(image.sampledRadiance, image.imageWidth, h, x, y);
    report_.answers.reset();
    if (image.answers.size() == static_cast<size_t>(image.imageWidth) * h && x < image.imageWidth &&
        y < h)
        report_.answers = image.answers[static_cast<size_t>(y) * image.imageWidth + x];
    if (image.imageWidth != view.width || h != view.height) {
        report_.exact = report_.sampled = {};
        report_.answers.reset();
    }
    valid_ = true;
    scene_ = &scene;
    camera_ = camera;
    passes_ = image.passes;
    return &report_;
}

}  // namespace penumbra::viewer
