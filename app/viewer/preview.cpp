#include "app/viewer/preview.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <system_error>
#include <vector>

#include "app/viewer/png_output.h"
#include "engine/io/scene_file.h"
#include "engine/render/answers.h"
#include "engine/render/renderer.h"

namespace penumbra::viewer {

Preview::Preview(const ViewerOptions& options) : options_(options) {
    glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
}

Preview::~Preview() { glDeleteTextures(1, &texture_); }

void Preview::clear() {
    runner_.clear();
    image_ = PreviewImage{};
    running_ = false;
    effects_ = EffectsSummary{};
    treeLess_ = false;
}

void Preview::poll(const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
                   const Layout& layout) {
    PreviewRunner::Snapshot now = runner_.take();
    if (now.update) upload(*now.update);
    running_ = now.running;
    effects_ = std::move(now.effects);
    sceneVersion_ = scene ? scene->version : 0;
    if (options_.preview && scene && dirty_) {
        // The full preview once the camera has rested for 200 ms; meanwhile, in the rendered
        // view, a coarse single pass at most every 100 ms, so that the view follows the camera
        // blockily without ever waiting for it. At rest, a rendered view with no image of this
        // view (a scene opened, the camera set or moved, the view resized) gets a coarse pass
        // first, which shows the shadows in a fraction of the first full pass's time, then the
        // full render.
        const auto now = std::chrono::steady_clock::now();
        const bool rendered = options_.view == ViewMode::Rendered;
        if (now - lastCameraChange_ > std::chrono::milliseconds(200)) {
            const bool coarseHere = lastCoarse_ && coarseCamera_ == camera &&
                                    coarseView_.width == layout.view.width &&
                                    coarseView_.height == layout.view.height;
            if (rendered && !coarseHere && !showsImage(camera, layout.view))
                restart(scene, camera, layout, true);
            else if (!(coarseHere && running_))  // (else: its image comes first)
                restart(scene, camera, layout);
        } else if (rendered && now - lastCoarseRestart_ > std::chrono::milliseconds(100)) {
            lastCoarseRestart_ = now;
            restart(scene, camera, layout, true);
        }
    }
}

void Preview::restartPending(const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
                             const Layout& layout) {
    if (options_.preview && dirty_) restart(scene, camera, layout);  // --no-preview: none
}

void Preview::restart(const std::shared_ptr<LoadedScene>& scene, const Camera& camera,
                      const Layout& layout, bool coarse) {
    if (!coarse) dirty_ = false;  // a coarse pass leaves the full one to come
    if (!scene) return;
    PreviewSettings s = options_.previewSettings;
    s.exact = options_.exact;
    if (treeLess_) s.exact.minTreeSamples = std::numeric_limits<uint64_t>::max();
    const Layout l = layout.width > 0 ? layout : computeLayout(1280, 800, options_.layout);
    // The rendered view: one preview pixel per view pixel, so that the view shows what
    // `penumbra render` gives for this camera at the view's size.
    constexpr double kCoarseScale = 0.125;
    const double scale = coarse                                ? kCoarseScale
                         : options_.view == ViewMode::Rendered ? 1.0
                                                               : options_.previewScale;
    s.width = std::max(8, static_cast<int>(std::lround(l.view.width * scale)));
    s.height = std::max(8, static_cast<int>(std::lround(l.view.height * scale)));
    if (coarse) s.passes = 1;
    s.coarse = coarse;
    lastCoarse_ = coarse;
    coarseCamera_ = camera;
    coarseView_ = l.view;
    runner_.restart(scene, camera, s);
    running_ = true;  // (until the next poll says otherwise)
}

void Preview::upload(const PreviewImage& image) {
    image_ = image;
    if (image.rgba.empty()) return;
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, image.rgba.data());
    glBindTexture(GL_TEXTURE_2D, 0);
}

bool Preview::showsImage(const Camera& camera, const Viewport& view) const {
    return options_.view == ViewMode::Rendered && !image_.rgba.empty() &&
           picturesView(image_, camera, view.width, view.height);
}

bool Preview::splitShown(const Camera& camera, const Viewport& view) const {
    return showsImage(camera, view) && image_.mode == PreviewMode::SideBySide;
}

std::string Preview::viewNote(const Camera& camera, const Viewport& view) const {
    if (options_.view != ViewMode::Rendered) return "";
    if (showsImage(camera, view)) {
        if (image_.sceneVersion != sceneVersion_)
            return "3D view: the image is of the light before it moved; the new one is rendering";
        if (image_.imageWidth == view.width && image_.height == view.height) return "";
        return "3D view: a coarser image (" + std::to_string(image_.imageWidth) + "x" +
               std::to_string(image_.height) + ") until the full render's first pass";
    }
    if (!options_.preview) return "3D view: flat colours (the preview is off)";
    if (!image_.error.empty()) return "3D view: flat colours (the render failed)";
    if (image_.rgba.empty()) return "3D view: flat colours until the render's first pass";
    return "3D view: flat colours while the camera moves (the image is of the view before)";
}

const ViewImage* Preview::viewImage(const Camera& camera, const Viewport& view) {
    // No image of this view yet: the rasterised scene meanwhile.
    if (!showsImage(camera, view)) return nullptr;
    viewImage_.texture = texture_;
    viewImage_.bands.clear();
    if (image_.mode == PreviewMode::SideBySide) {
        // Exact left of the split, sampled right of it: each half of the texture is one image of
        // the view's size. (The image's mode: after a switch, the last image until the new one.)
        const float t = static_cast<float>(std::clamp(options_.split, 0.0, 1.0));
        viewImage_.bands.push_back({0, t, 0, 0.5f * t});
        viewImage_.bands.push_back({t, 1, 0.5f + 0.5f * t, 1});
    } else {
        viewImage_.bands.push_back({0, 1, 0, 1});
    }
    return &viewImage_;
}

void Preview::drawSplitLine(const Camera& camera, const Viewport& vp) const {
    if (!splitShown(camera, vp)) return;
    const float x = static_cast<float>(vp.x + options_.split * vp.width);
    const float midY = static_cast<float>(vp.y) + 0.5f * static_cast<float>(vp.height);
    ImDrawList* draw = ImGui::GetBackgroundDrawList();
    draw->AddLine(ImVec2(x, static_cast<float>(vp.y)),
                  ImVec2(x, static_cast<float>(vp.y + vp.height)), IM_COL32(255, 255, 255, 200),
                  2.0f);
    const auto label = [&](float left, const char* text) {
        const ImVec2 size = ImGui::CalcTextSize(text);
        draw->AddRectFilled(ImVec2(left - 4, midY - 2),
                            ImVec2(left + size.x + 4, midY + size.y + 2), IM_COL32(0, 0, 0, 170));
        draw->AddText(ImVec2(left, midY), IM_COL32(255, 255, 255, 255), text);
    };
    label(x - 10 - ImGui::CalcTextSize("exact").x, "exact");
    label(x + 10, "sampled");
}

void Preview::drawPixelInspector(const LoadedScene* scene, const Camera& camera,
                                 const Viewport& view, bool splitDragged) {
    hover_ = nullptr;
    const ImGuiIO& io = ImGui::GetIO();
    if (options_.view != ViewMode::Rendered || !scene || io.WantCaptureMouse || splitDragged ||
        ImGui::IsMouseDragging(ImGuiMouseButton_Left) ||
        ImGui::IsMouseDragging(ImGuiMouseButton_Right))
        return;
    hover_ = pixelInspector_.inspect(*scene, camera, view, image_, io.MousePos.x, io.MousePos.y);
    if (hover_ == nullptr) return;
    const PixelReport& r = *hover_;
    ImGui::BeginTooltip();
    ImGui::Text("pixel (%d, %d)", r.x, r.y);
    // Where the numbers below come from: what the view shows under the mouse.
    switch (r.source) {
        case PixelSource::NoImage:
            ImGui::TextUnformatted(running_ ? "no rendered image yet: the first pass is rendering"
                                            : "no rendered image (the preview is off or failed)");
            break;
        case PixelSource::OtherView:
            ImGui::TextUnformatted(
                "the rendered image is of the view before it moved: a new one is rendering");
            break;
        case PixelSource::CoarsePixel:
            ImGui::Text("coarse pass: image pixel (%d, %d) of %dx%d covers this one%s", r.imageX,
                        r.imageY, r.imageWidth, r.imageHeight,
                        running_ ? "; the full render follows" : "");
            break;
        case PixelSource::ViewPixel:
            break;
    }
    const bool imaged = r.source == PixelSource::ViewPixel || r.source == PixelSource::CoarsePixel;
    auto radiance = [&](const char* name, const std::optional<Vec3>& c) {
        if (c)
            ImGui::Text("%-8s L = (%.4g, %.4g, %.4g)", name, c->x, c->y, c->z);
        else if (imaged)
            ImGui::Text("%-8s not rendered in the %s mode", name, toString(image_.mode));
    };
    radiance("exact", r.exact);
    radiance("sampled", r.sampled);
    if (r.answers) {
        std::string answered;
        for (size_t i = 0; i < kAnswers; ++i)
            if ((*r.answers)[i] > 0)
                answered += std::string(answered.empty() ? "" : ", ") +
                            toString(static_cast<Answer>(i)) + " " +
                            std::to_string((*r.answers)[i]);
        ImGui::Text("answered: %s", answered.empty() ? "no evaluation" : answered.c_str());
    }
    if (!r.hit) {
        ImGui::TextUnformatted("no surface");
    } else {
        ImGui::Text("face %u at (%.4g, %.4g, %.4g)", r.hit->face, r.hit->point.x, r.hit->point.y,
                    r.hit->point.z);
        for (const LightAtPoint& l : r.lights)
            ImGui::Text("light %u: %.2f%% visible, form factor %.4g%s", l.light, 100 * l.fraction,
                        l.formFactor, l.complete ? "" : " (over the hover budget: at least)");
        ImGui::TextUnformatted("click: inspect this point");
    }
    ImGui::EndTooltip();
}

bool Preview::save(const std::filesystem::path& stem, const LoadedScene* scene,
                   const Camera& camera, std::string& message) const {
    const PreviewImage& image = image_;
    if (!scene || image.rgba.empty()) {
        message = "save view: no rendered image yet";
        return false;
    }
    if (image.sceneVersion != scene->version) {
        message =
            "save view: the image is of the light before it moved; save once the new one "
            "is rendered";
        return false;
    }
    const std::vector<PlacedLight> moved = scene->movedLights();
    const std::optional<Film> radiance = radianceFilm(image);
    auto withExtension = [&](const char* ext) {
        std::filesystem::path p = stem;
        p += ext;
        return p;
    };
    try {
        std::error_code ec;
        if (stem.has_parent_path()) std::filesystem::create_directories(stem.parent_path(), ec);
        writeRgbaPng(withExtension(".png"), image.width, image.height, image.rgba);
        if (radiance) {
            writePfm(*radiance, withExtension(".pfm").string());
            writeExr(*radiance, withExtension(".exr").string());
        }
        writeTextFile(
            withExtension(".json"),
            jsonSceneWithCamera(scene->path, camera, withExtension(".json"),
                                scene->scene.defaultLight ? &*scene->scene.defaultLight : nullptr,
                                moved));
    } catch (const std::exception& e) {
        message = std::string("save view: ") + e.what();
        return false;
    }
    message = "saved " + withExtension(".png").string() +
              (radiance ? ", .pfm, .exr and .json (" : " and .json (") +
              std::to_string(image.imageWidth) + "x" + std::to_string(image.height) + ", " +
              std::to_string(image.passes) + " passes)";
    return true;
}

}  // namespace penumbra::viewer
