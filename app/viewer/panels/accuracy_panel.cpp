#include "app/viewer/panels/accuracy_panel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace penumbra::ui {
namespace {

const ImU32 kSampled = IM_COL32(90, 160, 255, 255);
const ImU32 kExact = IM_COL32(255, 120, 60, 255);
const ImU32 kNoise = IM_COL32(160, 160, 160, 200);
const ImU32 kEqual = IM_COL32(120, 220, 120, 255);
const ImU32 kAxis = IM_COL32(200, 200, 200, 255);
const ImU32 kGrid = IM_COL32(90, 90, 90, 120);

bool positive(double t, double e) { return t > 0 && e > 0 && std::isfinite(t) && std::isfinite(e); }

}  // namespace

AccuracyPlotRange accuracyPlotRange(const AccuracyStudy& s) {
    AccuracyPlotRange r;
    double t0 = 1e300, t1 = -1e300, e0 = 1e300, e1 = -1e300;
    auto add = [&](double t, double e) {
        if (!positive(t, e)) return;
        t0 = std::min(t0, std::log10(t));
        t1 = std::max(t1, std::log10(t));
        e0 = std::min(e0, std::log10(e));
        e1 = std::max(e1, std::log10(e));
        r.valid = true;
    };
    for (const AccuracyPoint& p : s.sampled) add(p.seconds, p.rmse);
    add(s.exact.seconds, s.exact.rmse);
    add(s.equalErrorSeconds, s.exact.rmse);  // the equal-error mark stays inside the plot
    if (s.referenceNoise > 0 && r.valid) {
        e0 = std::min(e0, std::log10(s.referenceNoise));
        e1 = std::max(e1, std::log10(s.referenceNoise));
    }
    if (!r.valid) return r;
    // Whole decades around the data, at least one decade wide.
    r.logTimeMin = std::floor(t0);
    r.logTimeMax = std::max(std::ceil(t1), r.logTimeMin + 1);
    r.logErrMin = std::floor(e0);
    r.logErrMax = std::max(std::ceil(e1), r.logErrMin + 1);
    return r;
}

void AccuracyPanel::setResult(const AccuracyStudy& study) {
    study_ = study;
    range_ = accuracyPlotRange(study_);
    has_ = true;
}

void AccuracyPanel::clear() {
    study_ = AccuracyStudy{};
    range_ = AccuracyPlotRange{};
    has_ = false;
}

void AccuracyPanel::drawPlot(ImDrawList* dl, ImVec2 o, ImVec2 size) {
    const AccuracyPlotRange& r = range_;
    const float left = 60, bottom = 36, top = 10, right = 16;
    const ImVec2 a(o.x + left, o.y + top), b(o.x + size.x - right, o.y + size.y - bottom);
    if (b.x <= a.x + 10 || b.y <= a.y + 10) return;
    auto map = [&](double t, double e) {
        const double u = (std::log10(t) - r.logTimeMin) / (r.logTimeMax - r.logTimeMin);
        const double v = (std::log10(e) - r.logErrMin) / (r.logErrMax - r.logErrMin);
        return ImVec2(a.x + static_cast<float>(u) * (b.x - a.x),
                      b.y - static_cast<float>(v) * (b.y - a.y));
    };
    char text[64];
    // Decade grid and labels.
    for (int d = static_cast<int>(r.logTimeMin); d <= static_cast<int>(r.logTimeMax); ++d) {
        const ImVec2 p = map(std::pow(10.0, d), std::pow(10.0, r.logErrMin));
        dl->AddLine(ImVec2(p.x, a.y), ImVec2(p.x, b.y), kGrid);
        std::snprintf(text, sizeof text, "1e%d s", d);
        dl->AddText(ImVec2(p.x - 14, b.y + 4), kAxis, text);
    }
    for (int d = static_cast<int>(r.logErrMin); d <= static_cast<int>(r.logErrMax); ++d) {
        const ImVec2 p = map(std::pow(10.0, r.logTimeMin), std::pow(10.0, d));
        dl->AddLine(ImVec2(a.x, p.y), ImVec2(b.x, p.y), kGrid);
        std::snprintf(text, sizeof text, "1e%d", d);
        dl->AddText(ImVec2(o.x + 4, p.y - 7), kAxis, text);
    }
    dl->AddRect(a, b, kAxis);
    dl->AddText(ImVec2((a.x + b.x) / 2 - 40, b.y + 20), kAxis, "wall time (s)");
    dl->AddText(ImVec2(o.x + 4, o.y - 4), kAxis, "RMSE");

    dl->PushClipRect(a, b, true);
    // The reference's noise: below it the exact image's error cannot be resolved.
    if (study_.referenceNoise > 0) {
        const float y = map(std::pow(10.0, r.logTimeMin), study_.referenceNoise).y;
        for (float x = a.x; x < b.x; x += 10) dl->AddLine(ImVec2(x, y), ImVec2(x + 5, y), kNoise);
    }
    // The sampled curve.
    const ImVec2* prev = nullptr;
    ImVec2 last;
    for (const AccuracyPoint& p : study_.sampled) {
        if (!positive(p.seconds, p.rmse)) continue;
        const ImVec2 q = map(p.seconds, p.rmse);
        if (prev) dl->AddLine(last, q, kSampled, 2);
        dl->AddCircleFilled(q, 4, kSampled);
        std::snprintf(text, sizeof text, "%d", p.rays);
        // Right of the point, or left of it where the label would leave the plot.
        const float w = ImGui::CalcTextSize(text).x;
        dl->AddText(ImVec2(q.x + 5 + w > b.x ? q.x - 5 - w : q.x + 5, q.y - 15), kSampled, text);
        last = q;
        prev = &last;
        ++pointsDrawn_;
    }
    // The exact point.
    if (positive(study_.exact.seconds, study_.exact.rmse)) {
        const ImVec2 q = map(study_.exact.seconds, study_.exact.rmse);
        dl->AddQuadFilled(ImVec2(q.x, q.y - 7), ImVec2(q.x + 7, q.y), ImVec2(q.x, q.y + 7),
                          ImVec2(q.x - 7, q.y), kExact);
        dl->AddText(ImVec2(q.x + 8, q.y + 2), kExact, "exact");
        ++pointsDrawn_;
        // Equal error: where the sampled curve reaches the exact image's error.
        if (positive(study_.equalErrorSeconds, study_.exact.rmse)) {
            const ImVec2 e = map(study_.equalErrorSeconds, study_.exact.rmse);
            dl->AddLine(q, e, kEqual, 1.5f);
            dl->AddCircle(e, 7, kEqual, 0, 2);
        }
    }
    dl->PopClipRect();

    // Legend.
    const ImVec2 l(b.x - 170, a.y + 6);
    dl->AddRectFilled(l, ImVec2(b.x - 6, a.y + 74), IM_COL32(30, 30, 30, 220));
    dl->AddCircleFilled(ImVec2(l.x + 10, l.y + 10), 4, kSampled);
    dl->AddText(ImVec2(l.x + 20, l.y + 3), kAxis, "sampled (rays/light)");
    dl->AddCircleFilled(ImVec2(l.x + 10, l.y + 26), 4, kExact);
    dl->AddText(ImVec2(l.x + 20, l.y + 19), kAxis, "exact vs reference");
    dl->AddCircle(ImVec2(l.x + 10, l.y + 42), 5, kEqual, 0, 2);
    dl->AddText(ImVec2(l.x + 20, l.y + 35), kAxis, "equal error");
    dl->AddLine(ImVec2(l.x + 4, l.y + 58), ImVec2(l.x + 16, l.y + 58), kNoise);
    dl->AddText(ImVec2(l.x + 20, l.y + 51), kAxis, "reference noise");
}

void AccuracyPanel::draw(const char* title) {
    pointsDrawn_ = 0;
    ImGui::SetNextWindowSize(ImVec2(640, 520), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin(title)) {
        ImGui::End();
        return;
    }
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    windowRect_ = {pos.x, pos.y, size.x, size.y};
    if (!has_) {
        ImGui::TextWrapped("No measurement yet: run the accuracy study for the current scene.");
        ImGui::End();
        return;
    }
    const AccuracyStudyOptions& o = study_.options;
    ImGui::Text("%dx%d, %d spp, same primary samples for every image%s", o.width, o.height, o.spp,
                study_.complete ? "" : " (cancelled: partial)");
    ImGui::Text("exact: %.3f s (precompute %.3f s), RMSE vs reference %.3g (reference noise %.3g)",
                study_.exact.seconds, study_.exact.precomputeSeconds, study_.exact.rmse,
                study_.referenceNoise);
    if (std::isfinite(study_.equalErrorSeconds))
        ImGui::Text("sampled needs %.3f s (%.0f rays/light) for the same error: %.2fx%s",
                    study_.equalErrorSeconds, study_.equalErrorRays,
                    study_.exact.seconds > 0 ? study_.equalErrorSeconds / study_.exact.seconds : 0,
                    study_.equalErrorExtrapolated ? " (extrapolated)" : "");
    ImVec2 avail = ImGui::GetContentRegionAvail();
    avail.x = std::max(avail.x, 200.0f);
    avail.y = std::max(avail.y, 160.0f);
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("accuracy_plot", avail);
    if (range_.valid) drawPlot(ImGui::GetWindowDrawList(), origin, avail);
    if (ImGui::IsItemHovered()) {
        ImGui::BeginTooltip();
        for (const AccuracyPoint& p : study_.sampled)
            ImGui::Text("%5d rays: %.3f s, RMSE %.3g, max %.3g", p.rays, p.seconds, p.rmse,
                        p.maxError);
        ImGui::EndTooltip();
    }
    ImGui::End();
}

}  // namespace penumbra::ui
