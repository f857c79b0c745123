#include "app/viewer/pixel_inspector.h"

#include <algorithm>
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

}  // namespace

const char* toString(PixelSource source) {
    switch (source) {
        case PixelSource::NoImage:
            return "none";
        case PixelSource::ViewPixel:
            return "view";
        case PixelSource::CoarsePixel:
            return "coarse";
        case PixelSource::OtherView:
            return "other view";
    }
    return "?";
}

const PixelReport* PixelInspector::inspect(const LoadedScene& scene, const Camera& camera,
                                           const Viewport& view, const PreviewImage& image,
                                           double px, double py) {
    if (!view.contains(px, py)) return nullptr;
    const int x = static_cast<int>(std::floor(px)) - view.x;
    const int y = static_cast<int>(std::floor(py)) - view.y;
    const bool samePixel =
        valid_ && report_.x == x && report_.y == y && scene_ == &scene && camera_ == camera;
    if (samePixel && passes_ == image.passes && imageWidth_ == image.imageWidth &&
        imageCamera_ == image.camera)
        return &report_;
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
    // The radiance follows the preview's passes (the image refines under a still mouse), read
    // where the image pictures this view: at the image's pixel that covers this one.
    const int w = image.imageWidth, h = image.height;
    report_.exact = report_.sampled = {};
    report_.answers.reset();
    report_.imageWidth = w;
    report_.imageHeight = h;
    if (w <= 0 || h <= 0) {
        report_.source = PixelSource::NoImage;
    } else if (!picturesView(image, camera, view.width, view.height)) {
        report_.source = PixelSource::OtherView;
    } else {
        const bool full = w == view.width && h == view.height;
        report_.source = full ? PixelSource::ViewPixel : PixelSource::CoarsePixel;
        report_.imageX = std::clamp(static_cast<int>((x + 0.5) * w / view.width), 0, w - 1);
        report_.imageY = std::clamp(static_cast<int>((y + 0.5) * h / view.height), 0, h - 1);
        const int ix = report_.imageX, iy = report_.imageY;
        report_.exact = radianceAt(image.exactRadiance, w, h, ix, iy);
        report_.sampled = radianceAt(image.sampledRadiance, w, h, ix, iy);
        if (image.answers.size() == static_cast<size_t>(w) * h)
            report_.answers = image.answers[static_cast<size_t>(iy) * w + ix];
    }
    valid_ = true;
    scene_ = &scene;
    camera_ = camera;
    passes_ = image.passes;
    imageWidth_ = w;
    imageCamera_ = image.camera;
    return &report_;
}

}  // namespace penumbra::viewer
