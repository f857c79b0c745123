// Viewer::stateJson: what the UI shows, for `--state-out` and the tests that check screenshots
// against independent queries.
#include <cmath>

#include "app/viewer/palette.h"
#include "app/viewer/viewer.h"
#include "engine/precompute/point_answer_json.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/render/answers_json.h"
#include "engine/studies/accuracy_study.h"

namespace penumbra::viewer {
namespace {

nlohmann::json vec(const Vec3& v) { return {v.x, v.y, v.z}; }

// The inspected point: its answer in the schema of `penumbra query`
// (engine/precompute/point_answer_json.h), and what the viewer adds: the face's normal, the
// selected light, whether the trees are still on their way; per light the fragments' overlay
// colours (in the fragments' order), the query's time, its tree's size and the path panel's rows.
nlohmann::json pointJson(const Selection& selection, const Scene& scene) {
    using nlohmann::json;
    if (!selection.inspection()) return nullptr;
    const PointInspection& p = *selection.inspection();
    std::vector<LightAtPoint> answers;
    for (const LightInspection& li : p.lights) answers.push_back(li.result);
    json point = pointAnswerJson(scene, p.face, p.point, answers);
    point["normal"] = vec(p.normal);
    point["selected_light"] = selection.light();
    point["trees_pending"] = p.treesPending;
    for (size_t k = 0; k < p.lights.size(); ++k) {
        const LightInspection& li = p.lights[k];
        json& light = point["lights"][k];
        json colours = json::array();
        for (size_t i = 0; i < li.result.fragments.size(); ++i) {
            const Rgb colour = fragmentColour(i);
            colours.push_back({colour.r, colour.g, colour.b});
        }
        light["fragment_colours"] = std::move(colours);
        light["seconds"] = li.seconds;
        light["tree_nodes"] = li.tree ? li.tree->nodes.size() : 0;
        json steps = json::array();
        for (const PathStep& st : li.steps)
            steps.push_back(
                {{"node", st.node},
                 {"depth", st.depth},
                 {"v0", st.v0},
                 {"v1", st.v1},
                 {"occluder_face",
                  st.occluderFace == PathStep::kNoOccluder ? json(nullptr) : json(st.occluderFace)},
                 {"side", vis::toString(st.side)}});
        light["path_steps"] = std::move(steps);
    }
    return point;
}

// The "Accuracy vs time" window: shown, running, and the study it plots.
nlohmann::json accuracyJson(const ui::AccuracyPanel& panel, bool shown, bool running) {
    using nlohmann::json;
    json accuracy = {{"shown", shown}, {"running", running}};
    if (panel.hasResult()) {
        const AccuracyStudy& st = panel.study();
        auto point = [](const AccuracyPoint& p) {
            return json{{"rays", p.rays},
                        {"seconds", p.seconds},
                        {"rmse", p.rmse},
                        {"maxError", p.maxError},
                        {"precomputeSeconds", p.precomputeSeconds}};
        };
        json sampled = json::array();
        for (const AccuracyPoint& p : st.sampled) sampled.push_back(point(p));
        auto finiteOrNull = [](double v) { return std::isfinite(v) ? json(v) : json(nullptr); };
        accuracy["study"] = {{"width", st.options.width},
                             {"height", st.options.height},
                             {"spp", st.options.spp},
                             {"complete", st.complete},
                             {"sampled", sampled},
                             {"exact", point(st.exact)},
                             {"referenceNoise", st.referenceNoise},
                             {"meanRadiance", st.meanRadiance},
                             {"equalErrorSeconds", finiteOrNull(st.equalErrorSeconds)},
                             {"equalErrorRays", finiteOrNull(st.equalErrorRays)},
                             {"equalErrorExtrapolated", st.equalErrorExtrapolated},
                             {"pointsDrawn", panel.pointsDrawn()}};
    } else {
        accuracy["study"] = nullptr;
    }
    return accuracy;
}

}  // namespace

nlohmann::json Viewer::stateJson() const {
    using nlohmann::json;
    json s;
    s["scene"] = scene_ ? scene_->path.string() : "";
    s["sceneWarnings"] = scene_ ? scene_->scene.warnings : std::vector<std::string>{};
    s["status"] = status_;
    // The light added because the scene has none (engine/scene/default_light.h), or null.
    if (scene_ && scene_->scene.defaultLight) {
        const DefaultLight& d = *scene_->scene.defaultLight;
        json corners = json::array();
        for (const Vec3& c : d.corners) corners.push_back(vec(c));
        s["defaultLight"] = {{"face", d.face},     {"light", scene_->scene.lights.size() - 1},
                             {"corners", corners}, {"side", d.side},
                             {"height", d.height}, {"emission", d.emission},
                             {"up", d.upName()},   {"upFromCamera", d.upFromCamera}};
    } else {
        s["defaultLight"] = nullptr;
    }
    // The area lights as the scene has them now, with the viewer's moves (engine/scene/
    // light_move.h) and what a move left: the scene's version, the trees in its store, the trees
    // the moves dropped and whether their pairs are still being rebuilt.
    json lights = json::array();
    if (scene_)
        for (uint32_t i = 0; i < scene_->scene.lights.size(); ++i) {
            const uint32_t face = scene_->scene.lights[i];
            json vertices = json::array();
            for (uint32_t v : scene_->scene.mesh.faces[face])
                vertices.push_back(vec(scene_->scene.mesh.vertices[v]));
            const LightMove m = scene_->lightMove(i);
            lights.push_back({{"light", i},
                              {"face", face},
                              {"vertices", vertices},
                              {"moved", !m.isIdentity()},
                              {"translate", vec(m.translate)},
                              {"rotateDegrees", vec(m.rotateDegrees)},
                              {"scale", vec(m.scale)}});
        }
    s["lights"] = lights;
    s["lightMoves"] = {{"sceneVersion", scene_ ? scene_->version : 0},
                       {"treesInStore", scene_ ? scene_->store->treeCount() : 0},
                       {"treesDropped", lightStatus_.invalidated},
                       {"treesKept", lightStatus_.kept},
                       {"treesNotKeptBecause", scene_ ? scene_->kept.noneBecause : ""},
                       {"building", lightJob_.busy()},
                       {"rebuilding", lightRebuild_},
                       {"previewTreeLess", preview_.treeLess()},
                       {"refused", lightStatus_.refused},
                       {"windowShown", lightPanel_.visible()}};
    s["size"] = {layout_.width, layout_.height};
    s["viewport"] = {{"x", layout_.view.x},
                     {"y", layout_.view.y},
                     {"width", layout_.view.width},
                     {"height", layout_.view.height}};
    const Camera& c = orbit_.camera();
    s["camera"] = {
        {"eye", vec(c.eye)}, {"target", vec(c.target)}, {"up", vec(c.up)}, {"fovY", c.fovYDegrees}};
    // Which optional windows are open (the docked panels are always there).
    s["panels"] = {{"help", helpPanel_.visible()},
                   {"tree", showTree_},
                   {"preview", options_.preview},
                   {"accuracy", accuracy_.shown()}};
    json rects = json::object();
    for (const auto& [name, r] : panelRects_) rects[name] = {r[0], r[1], r[2], r[3]};
    rects["3D view"] = {layout_.view.x, layout_.view.y, layout_.view.width, layout_.view.height};
    s["panelRects"] = rects;
    // The user's arrangement (panel_arrangement.h) and the columns' widths, as the settings file
    // keeps them; how far each window's widest item reaches past its edge (panels/panel_fit.h).
    s["layout"] = arrangement_.toJson();
    s["layout"]["columns"] = {options_.layout.leftWidth, options_.layout.rightWidth};
    s["layout"]["menuBarHeight"] = options_.layout.top;
    s["panelOverflow"] = panelOverflow_;
    s["settings"] = {{"file", options_.settingsFile.string()}, {"warning", settingsWarning_}};
    // What each panel said in the last frame (PanelText: Dear ImGui's log of it).
    s["panelText"] = panelText_.texts();
    s["inspectionPending"] = selection_.pending();
    s["point"] = scene_ ? pointJson(selection_, scene_->scene) : nullptr;
    // What the 3D view shows: "raster", or "rendered" (the preview's image at the view's size, in
    // the preview's mode; side by side split at `split`).
    s["view"] = {{"mode", options_.view == ViewMode::Rendered ? "rendered" : "raster"},
                 {"showsImage", preview_.showsImage(orbit_.camera(), layout_.view)},
                 {"split", options_.split}};
    // The pixel inspector's report for the pixel under the mouse (rendered view only).
    if (preview_.hover() != nullptr) {
        const PixelReport& r = *preview_.hover();
        auto radiance = [&](const std::optional<Vec3>& c) { return c ? vec(*c) : json(nullptr); };
        json lights = json::array();
        for (const LightAtPoint& l : r.lights) lights.push_back(lightAnswerJson(l));
        s["pixel"] = {
            {"x", r.x},
            {"y", r.y},
            {"source", toString(r.source)},
            {"exact", radiance(r.exact)},
            {"sampled", radiance(r.sampled)},
            {"answers", r.answers ? answerTotalsJson(std::span(&*r.answers, 1)) : json(nullptr)},
            {"face", r.hit ? json(r.hit->face) : json(nullptr)},
            {"point", r.hit ? vec(r.hit->point) : json(nullptr)},
            {"lights", lights}};
    }
    // The settings that shape the answer, as the command line names them.
    s["exact"] = {{"maxLpSolves", options_.exact.maxLpSolves},
                  {"minTreeSamples", options_.exact.minTreeSamples},
                  {"groupedShaftMin", options_.exact.groupedShaftMin},
                  {"exactWorkLimit", options_.exact.exactWorkLimit},
                  {"lightEdgeWorkLimit", options_.exact.lightEdgeWorkLimit},
                  {"chainMinOccluders", options_.exact.chainMinOccluders},
                  {"refineLevels", options_.exact.refineLevels},
                  {"passes", options_.previewSettings.passes},
                  {"lightSamples", options_.previewSettings.lightSamples}};
    const PreviewImage& image = preview_.image();
    // "mode": the preview's setting; "imageMode": of the image shown (the last one until the new
    // mode's first pass); "simulates": whose effects the Precompute panel lists ("exact",
    // "sampled"; "" before any render).
    s["preview"] = {{"mode", toString(options_.previewSettings.mode)},
                    {"imageMode", toString(image.mode)},
                    {"running", preview_.running()},
                    {"coarse", image.coarse},
                    {"sceneVersion", image.sceneVersion},
                    {"simulates", preview_.effects().method},
                    {"passes", image.passes},
                    {"width", image.width},
                    {"height", image.height},
                    {"finished", image.finished},
                    {"relativeRmsError", image.relativeRmsError},
                    {"errorHistory", image.errorHistory},
                    {"answers", answerTotalsJson(image.answers)},
                    {"error", image.error}};
    s["frames"] = {{"count", frameStats_.frames},
                   {"maxSeconds", frameStats_.maxSeconds},
                   {"meanSeconds",
                    frameStats_.frames > 0 ? frameStats_.sumSeconds / frameStats_.frames : 0.0}};
    s["accuracy"] = accuracyJson(accuracy_.plot(), accuracy_.shown(), accuracy_.running());
    if (visibility_.attached() || !visibility_.state().empty())
        s["visibility"] = {{"file", visibility_.file().string()},
                           {"state", visibility_.state()},
                           {"status", visibility_.status()},
                           {"treesLoaded", visibility_.treesLoaded()},
                           {"treesWritten", visibility_.treesWritten()},
                           {"treesInStore", scene_ ? scene_->store->treeCount() : 0}};
    if (precomputeNow_) {
        const PrecomputeProgress& p = *precomputeNow_;
        s["precompute"] = {
            {"done", p.done},       {"total", p.total},
            {"seconds", p.seconds}, {"nodes", p.nodes},
            {"bytes", p.bytes},     {"running", p.state == PrecomputeProgress::State::Running}};
    }
    return s;
}

}  // namespace penumbra::viewer
