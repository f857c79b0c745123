// The ImGui panels of the Viewer (see viewer.h for the layout: scene, precompute, history tree
// and preview on the left; point, light plane and path on the right; help and status over the 3D
// view).
#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "app/viewer/palette.h"
#include "app/viewer/panels/tree_panel.h"
#include "app/viewer/viewer.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/render/embree_scene.h"
#include "engine/studies/accuracy_study.h"

namespace penumbra::viewer {
namespace {

constexpr ImGuiWindowFlags kPanel = ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                                    ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings;

std::string humanBytes(size_t bytes) {
    char buf[32];
    if (bytes >= (1u << 20))
        std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / (1u << 20));
    else
        std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(bytes) / (1u << 10));
    return buf;
}

ImU32 toImU32(Rgb c, int alpha = 255) { return IM_COL32(c.r, c.g, c.b, alpha); }

}  // namespace

void Viewer::place(const char* panel, float x, float y, float w, float h) {
    ImGui::SetNextWindowPos(ImVec2(x, y), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(w, h), ImGuiCond_Always);
    panelRects_[panel] = {x, y, w, h};
}

// Left column: scene, precompute, history tree, preview (the rest), top to bottom.
struct LeftColumn {
    float scene, precompute, tree, preview;  // tops
    float bottom;
    explicit LeftColumn(const Layout& l) {
        const float h = static_cast<float>(l.height);
        scene = 0;
        precompute = std::min(150.0f, 0.19f * h);
        tree = precompute + std::min(150.0f, 0.19f * h);
        preview = tree + std::min(190.0f, 0.24f * h);
        bottom = h;
    }
};

void Viewer::drawScenePanel() {
    const LeftColumn c(layout_);
    place("Scene", 0, c.scene, static_cast<float>(layout_.leftWidth), c.precompute - c.scene);
    if (ImGui::Begin("Scene", nullptr, kPanel)) {
        if (scene_) {
            ImGui::TextWrapped("%s", scene_->path.string().c_str());
            ImGui::Text("%u faces, %zu area lights, %zu trees (%s)", scene_->scene.faceCount(),
                        scene_->scene.lights.size(), scene_->store->treeCount(),
                        humanBytes(scene_->store->bytes()).c_str());
        } else {
            ImGui::TextUnformatted("No scene: pick one below or drop a scene file here.");
        }
        if (ImGui::Button("Fit (F)")) fitCamera();
        ImGui::SameLine();
        ImGui::TextUnformatted("open (or drag and drop a file):");
        if (ImGui::BeginListBox("##scenes", ImVec2(-1, -1))) {
            for (const auto& file : sceneFiles_) {
                const bool current = scene_ && scene_->path == file;
                // Named from the assets directory: "scenes/cornell_box.json".
                const std::string name =
                    file.lexically_relative(options_.assetsDirectory).generic_string();
                if (ImGui::Selectable(name.c_str(), current) && !current) openScene(file);
            }
            ImGui::EndListBox();
        }
    }
    ImGui::End();
}

void Viewer::drawPrecomputePanel() {
    const LeftColumn c(layout_);
    place("Precompute", 0, c.precompute, static_cast<float>(layout_.leftWidth),
          c.tree - c.precompute);
    if (ImGui::Begin("Precompute", nullptr, kPanel)) {
        if (precompute_) {
            const PrecomputeProgress p = precompute_->progress();
            const float fraction =
                p.total > 0 ? static_cast<float>(p.done) / static_cast<float>(p.total) : 0.0f;
            char overlay[96];
            std::snprintf(overlay, sizeof overlay, "%zu / %zu pairs, %.0f s left", p.done, p.total,
                          p.secondsLeft);
            ImGui::ProgressBar(fraction, ImVec2(-1, 0), overlay);
            const char* state = "idle";
            switch (p.state) {
                case PrecomputeProgress::State::Idle:
                    state = "idle";
                    break;
                case PrecomputeProgress::State::Running:
                    state = "running";
                    break;
                case PrecomputeProgress::State::Cancelled:
                    state = "cancelled";
                    break;
                case PrecomputeProgress::State::OverBudget:
                    state = "over budget";
                    break;
                case PrecomputeProgress::State::Failed:
                    state = "failed";
                    break;
            }
            ImGui::Text("%s: %zu pairs done, %zu nodes, %s, %.1f s", state, p.done, p.nodes,
                        humanBytes(p.bytes).c_str(), p.seconds);
            if (!p.error.empty()) ImGui::TextWrapped("error: %s", p.error.c_str());
            if (p.state == PrecomputeProgress::State::Running) {
                if (ImGui::Button("Cancel (C)")) cancelPrecompute();
            } else if (ImGui::Button("Precompute all (P)")) {
                startPrecompute();
            }
        } else if (ImGui::Button("Precompute all (P)")) {
            startPrecompute();
        }
        ImGui::TextWrapped("%s", preview_.effects().text().c_str());
    }
    ImGui::End();
}

void Viewer::drawTreePanel() {
    const LeftColumn c(layout_);
    place("History tree", 0, c.tree, static_cast<float>(layout_.leftWidth), c.preview - c.tree);
    treePanel_->draw("History tree");
}

void Viewer::drawPreviewPanel() {
    const LeftColumn c(layout_);
    place("Preview", 0, c.preview, static_cast<float>(layout_.leftWidth), c.bottom - c.preview);
    if (ImGui::Begin("Preview", nullptr, kPanel)) {
        PreviewSettings& s = options_.previewSettings;
        int mode = static_cast<int>(s.mode);
        const char* names[] = {"exact", "sampled", "side by side", "difference"};
        if (ImGui::Combo("mode (1-4)", &mode, names, 4)) {
            s.mode = static_cast<PreviewMode>(mode);
            previewDirty_ = true;
        }
        if (ImGui::SliderInt("light samples", &s.lightSamples, 1, 256)) previewDirty_ = true;
        ImGui::Text("%d / %d passes, %.1f s%s", previewImage_.passes, s.passes,
                    previewImage_.seconds, preview_.running() ? "" : " (done)");
        if (previewImage_.relativeRmsError >= 0)
            ImGui::Text("sampled vs exact: %.2f%% RMS", 100 * previewImage_.relativeRmsError);
        if (!previewImage_.error.empty())
            ImGui::TextWrapped("error: %s", previewImage_.error.c_str());
        if (previewImage_.width > 0) {
            // The whole image in the space left, aspect kept.
            const ImVec2 avail = ImGui::GetContentRegionAvail();
            const float scale =
                std::max(0.0f, std::min(avail.x / static_cast<float>(previewImage_.width),
                                        avail.y / static_cast<float>(previewImage_.height)));
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(previewTexture_)),
                         ImVec2(scale * static_cast<float>(previewImage_.width),
                                scale * static_cast<float>(previewImage_.height)));
        }
    }
    ImGui::End();
}

void Viewer::drawPointPanel() {
    const float x = static_cast<float>(layout_.width - layout_.rightWidth);
    const float w = static_cast<float>(layout_.rightWidth);
    place("Point", x, 0, w, 0.3f * static_cast<float>(layout_.height));
    if (ImGui::Begin("Point", nullptr, kPanel)) {
        if (pending_) ImGui::TextUnformatted("computing the point query...");
        if (!inspection_) {
            if (!pending_) ImGui::TextUnformatted("Click a surface point in the 3D view.");
        } else {
            const PointInspection& p = *inspection_;
            ImGui::Text("face %u  x = (%.4g, %.4g, %.4g)", p.face, p.point.x, p.point.y, p.point.z);
            ImGui::Text("normal (%.3f, %.3f, %.3f)   * = tree built by this query", p.normal.x,
                        p.normal.y, p.normal.z);
            if (ImGui::BeginTable(
                    "lights", 6,
                    ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY)) {
                ImGui::TableSetupColumn("light");
                ImGui::TableSetupColumn("visible");
                ImGui::TableSetupColumn("form factor");
                ImGui::TableSetupColumn("frags");
                ImGui::TableSetupColumn("nodes");
                ImGui::TableSetupColumn("time");
                ImGui::TableHeadersRow();
                for (size_t k = 0; k < p.lights.size(); ++k) {
                    const LightInspection& li = p.lights[k];
                    ImGui::TableNextRow();
                    ImGui::TableNextColumn();
                    char label[32];
                    std::snprintf(label, sizeof label, "%u", li.result.light);
                    if (ImGui::Selectable(label, selectedLight_ == k,
                                          ImGuiSelectableFlags_SpanAllColumns)) {
                        selectedLight_ = k;
                        updateOverlay();
                    }
                    ImGui::TableNextColumn();
                    ImGui::Text("%.2f%%", 100 * li.result.fraction);
                    ImGui::TableNextColumn();
                    ImGui::Text("%.4g", li.result.formFactor);
                    if (ImGui::IsItemHovered())
                        ImGui::SetTooltip("unoccluded: %.6g (light face %u)",
                                          li.result.unoccludedFormFactor, li.result.lightFace);
                    ImGui::TableNextColumn();
                    ImGui::Text("%zu", li.result.fragments.size());
                    ImGui::TableNextColumn();
                    ImGui::Text("%u", li.result.nodesVisited);
                    ImGui::TableNextColumn();
                    ImGui::Text("%.1f ms%s", 1e3 * li.seconds, li.treeWasBuilt ? "*" : "");
                }
                ImGui::EndTable();
            }
        }
    }
    ImGui::End();
}

void Viewer::drawLightPlanePanel() {
    const float x = static_cast<float>(layout_.width - layout_.rightWidth);
    const float w = static_cast<float>(layout_.rightWidth);
    const float y = 0.3f * static_cast<float>(layout_.height);
    place("Light plane", x, y, w, 0.3f * static_cast<float>(layout_.height));
    if (ImGui::Begin("Light plane", nullptr, kPanel)) {
        if (!inspection_ || inspection_->lights.empty() || !scene_) {
            ImGui::TextUnformatted("The selected light's visible fragments, in its plane.");
        } else {
            const LightInspection& li = inspection_->lights[selectedLight_];
            const vis::PolygonMesh& mesh = scene_->scene.mesh;
            const auto face = mesh.face(li.result.lightFace);
            ImGui::Text("light %u: %zu fragments, %.2f%% visible", li.result.light,
                        li.result.fragments.size(), 100 * li.result.fraction);
            // A frame of the light's plane: u along its first edge, v = n x u (the light seen from
            // its front, counter-clockwise stays counter-clockwise).
            const Vec3 o = mesh.vertices[face[0]];
            const Vec3 n = normalize(mesh.faceAreaNormal(li.result.lightFace));
            const Vec3 u = normalize(mesh.vertices[face[1]] - o);
            const Vec3 v = cross(n, u);
            double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
            for (uint32_t id : face) {
                const Vec3 d = mesh.vertices[id] - o;
                const double c[2] = {dot(d, u), dot(d, v)};
                for (int i = 0; i < 2; ++i) {
                    lo[i] = std::min(lo[i], c[i]);
                    hi[i] = std::max(hi[i], c[i]);
                }
            }
            const ImVec2 avail = ImGui::GetContentRegionAvail();
            const ImVec2 origin = ImGui::GetCursorScreenPos();
            const double span = std::max(hi[0] - lo[0], hi[1] - lo[1]);
            const double scale = span > 0 ? (std::min(avail.x, avail.y) - 16) / span : 1.0;
            auto toScreen = [&](const Vec3& p) {
                const Vec3 d = p - o;
                return ImVec2(origin.x + 8 + static_cast<float>((dot(d, u) - lo[0]) * scale),
                              origin.y + 8 + static_cast<float>((hi[1] - dot(d, v)) * scale));
            };
            ImDrawList* draw = ImGui::GetWindowDrawList();
            std::vector<ImVec2> pts;
            for (uint32_t id : face) pts.push_back(toScreen(mesh.vertices[id]));
            draw->AddConvexPolyFilled(pts.data(), static_cast<int>(pts.size()),
                                      IM_COL32(60, 60, 60, 255));
            for (size_t i = 0; i < li.result.fragments.size(); ++i) {
                pts.clear();
                for (const Vec3& p : li.result.fragments[i]) pts.push_back(toScreen(p));
                draw->AddConvexPolyFilled(pts.data(), static_cast<int>(pts.size()),
                                          toImU32(fragmentColour(i)));
                draw->AddPolyline(pts.data(), static_cast<int>(pts.size()),
                                  IM_COL32(20, 20, 20, 255), ImDrawFlags_Closed, 1.0f);
            }
            pts.clear();
            for (uint32_t id : face) pts.push_back(toScreen(mesh.vertices[id]));
            draw->AddPolyline(pts.data(), static_cast<int>(pts.size()),
                              IM_COL32(255, 255, 255, 255), ImDrawFlags_Closed, 1.5f);
            ImGui::Dummy(avail);
        }
    }
    ImGui::End();
}

void Viewer::drawPathPanel() {
    const float x = static_cast<float>(layout_.width - layout_.rightWidth);
    const float w = static_cast<float>(layout_.rightWidth);
    const float y = 0.6f * static_cast<float>(layout_.height);
    place("Path", x, y, w, static_cast<float>(layout_.height) - y);
    if (ImGui::Begin("Path", nullptr, kPanel)) {
        if (!inspection_ || inspection_->lights.empty()) {
            ImGui::TextUnformatted("The history-tree path of the selected light.");
        } else {
            const LightInspection& li = inspection_->lights[selectedLight_];
            ImGui::Text("light %u, tree %s: %zu nodes visited (L cycles lights)", li.result.light,
                        std::string(vis::toString(li.result.kind)).c_str(), li.steps.size());
            if (li.result.deferredOccluders > 0)
                ImGui::Text(
                    "partial tree: %u deferred occluders, %u clipped from this point "
                    "(%u clips changed a fragment)",
                    li.result.deferredOccluders, li.result.deferredActive, li.result.deferredClips);
            if (ImGui::BeginTable(
                    "path", 5,
                    ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY)) {
                ImGui::TableSetupScrollFreeze(0, 1);
                ImGui::TableSetupColumn("depth");
                ImGui::TableSetupColumn("node");
                ImGui::TableSetupColumn("edge v0 -> v1");
                ImGui::TableSetupColumn("occluder");
                ImGui::TableSetupColumn("side");
                ImGui::TableHeadersRow();
                ImGuiListClipper clipper;
                clipper.Begin(static_cast<int>(li.steps.size()));
                while (clipper.Step())
                    for (int i = clipper.DisplayStart; i < clipper.DisplayEnd; ++i) {
                        const PathStep& s = li.steps[static_cast<size_t>(i)];
                        ImGui::TableNextRow();
                        ImGui::TableNextColumn();
                        ImGui::Text("%u", s.depth);
                        ImGui::TableNextColumn();
                        ImGui::Text("%u", s.node);
                        ImGui::TableNextColumn();
                        ImGui::Text("%u -> %u", s.v0, s.v1);
                        ImGui::TableNextColumn();
                        if (s.occluderFace == PathStep::kNoOccluder)
                            ImGui::TextUnformatted("?");
                        else
                            ImGui::Text("face %u", s.occluderFace);
                        ImGui::TableNextColumn();
                        ImGui::TextUnformatted(toString(s.side));
                    }
                ImGui::EndTable();
            }
        }
    }
    ImGui::End();
}

void Viewer::drawHelpPanel() {
    const Viewport& vp = layout_.view;
    ImGui::SetNextWindowPos(
        ImVec2(static_cast<float>(vp.x + 8), static_cast<float>(vp.y + vp.height - 8)),
        ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.75f);
    if (ImGui::Begin("Help (H)", &showHelp_,
                     ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                         ImGuiWindowFlags_NoMove)) {
        ImGui::TextUnformatted(
            "left drag: orbit     right/middle drag: pan     wheel: zoom\n"
            "click: inspect point   L: next light   Esc: clear\n"
            "F: fit scene   T: tree panel   H: this help\n"
            "1-4: preview exact / sampled / side by side / difference   R: restart\n"
            "P: precompute all   C: cancel   A: accuracy vs time   Ctrl+Q: quit   drop scene: "
            "open");
    }
    ImGui::End();
}

struct Viewer::AccuracyJob {
    std::shared_ptr<LoadedScene> scene;  // kept alive while the study runs
    std::atomic<bool> cancel{false};
    std::atomic<bool> done{false};
    std::atomic<double> progress{0};
    AccuracyStudy result;  // written by the task before `done`, read after
};

void Viewer::startAccuracyStudy() {
    if (!scene_ || (accuracyJob_ && !accuracyJob_->done)) return;
    auto job = std::make_shared<AccuracyJob>();
    job->scene = scene_;
    accuracyJob_ = job;
    const Camera camera = orbit_.camera();
    // Small images: the study renders 12 sampled images and a 2 x 2048-ray reference.
    AccuracyStudyOptions options;
    options.width = options.height = 64;
    options.spp = 2;
    tasks_.run([job, camera, options] {
        try {
            job->result = runAccuracyStudy(job->scene->scene, *job->scene->bvh, *job->scene->store,
                                           camera, options, &job->cancel, &job->progress);
        } catch (const std::exception&) {
            job->result = {};  // reported as an incomplete study
        }
        job->done = true;
    });
}

void Viewer::openAccuracyStudy() {
    showAccuracy_ = true;
    startAccuracyStudy();
}

bool Viewer::accuracyStudyRunning() const { return accuracyJob_ && !accuracyJob_->done; }

void Viewer::cancelAccuracyStudy() {
    if (accuracyJob_) accuracyJob_->cancel = true;
}

void Viewer::drawAccuracyPanel() {
    if (!accuracyPanel_) accuracyPanel_ = std::make_unique<ui::AccuracyPanel>();
    const std::shared_ptr<AccuracyJob> job = accuracyJob_;
    if (job && job->done && !job->cancel) {
        accuracyPanel_->setResult(job->result);
        accuracyJob_.reset();
    }
    // First shown over the 3D view: the controls at its top left, the plot beside them.
    const Viewport& vp = layout_.view;
    const float vx = static_cast<float>(vp.x), vy = static_cast<float>(vp.y);
    ImGui::SetNextWindowPos(ImVec2(vx + 8, vy + 64), ImGuiCond_FirstUseEver);
    if (ImGui::Begin("Accuracy controls", &showAccuracy_,
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_AlwaysAutoResize)) {
        if (accuracyJob_ && !accuracyJob_->done) {
            ImGui::ProgressBar(static_cast<float>(accuracyJob_->progress.load()), ImVec2(-1, 0),
                               "measuring exact vs 1..1024 shadow rays");
            if (ImGui::Button("Cancel")) accuracyJob_->cancel = true;
        } else if (ImGui::Button("Measure this view (64x64, 2 spp)")) {
            startAccuracyStudy();
        }
    }
    ImGui::End();
    if (!accuracyPanel_->hasResult()) return;
    ImGui::SetNextWindowPos(
        ImVec2(vx + std::max(8.0f, 0.5f * (static_cast<float>(vp.width) - 640)), vy + 110),
        ImGuiCond_FirstUseEver);
    accuracyPanel_->draw("Accuracy vs time");
    const std::array<float, 4>& r = accuracyPanel_->windowRect();
    panelRects_["Accuracy vs time"] = {r[0], r[1], r[2], r[3]};
}

void Viewer::drawStatusBar() {
    const Viewport& vp = layout_.view;
    ImGui::SetNextWindowPos(ImVec2(static_cast<float>(vp.x + 8), static_cast<float>(vp.y + 8)),
                            ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.6f);
    if (ImGui::Begin("##status", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize |
                         ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing |
                         ImGuiWindowFlags_NoNav | ImGuiWindowFlags_NoInputs)) {
        ImGui::TextUnformatted(status_.c_str());
        ImGui::Text("frame %.1f ms (max %.1f ms)", 1e3 * frameStats_.lastSeconds,
                    1e3 * frameStats_.maxSeconds);
    }
    ImGui::End();
}

}  // namespace penumbra::viewer
