// The "Accuracy vs time" panel, headless: an ImGui context without a backend (display size, font
// atlas, NewFrame / draw / Render); the draw list holds the plot.
#include "app/viewer/panels/accuracy_panel.h"

#include <gtest/gtest.h>
#include <imgui.h>

#include "tools/devkit/headless_imgui.h"

namespace {

using penumbra::AccuracyPoint;
using penumbra::AccuracyStudy;

AccuracyStudy handStudy() {
    AccuracyStudy s;
    s.options.width = s.options.height = 64;
    for (int n : {1, 4, 16, 64}) {
        AccuracyPoint p;
        p.method = "sampled";
        p.rays = n;
        p.seconds = 0.01 * n;
        p.rmse = 0.1 / n;
        p.maxError = 0.5 / n;
        s.sampled.push_back(p);
    }
    s.exact.method = "exact";
    s.exact.seconds = 0.05;
    s.exact.rmse = 0.002;
    s.referenceNoise = 0.0018;
    s.equalErrorSeconds = 0.5;
    s.equalErrorRays = 50;
    s.complete = true;
    return s;
}

size_t frameVertices(penumbra::devkit::HeadlessImGui& imgui, penumbra::ui::AccuracyPanel& panel) {
    return penumbra::devkit::HeadlessImGui::vertices(
        imgui.frame([&] { panel.draw("Accuracy vs time"); }));
}

TEST(AccuracyPanel, DrawsTheCurveHeadless) {
    penumbra::devkit::HeadlessImGui imgui(800, 600);
    penumbra::ui::AccuracyPanel panel;
    const size_t empty = frameVertices(imgui, panel);  // "no measurement yet"
    EXPECT_EQ(panel.pointsDrawn(), 0u);
    panel.setResult(handStudy());
    const size_t full = frameVertices(imgui, panel);
    EXPECT_EQ(panel.pointsDrawn(), 5u);  // 4 sampled + exact
    EXPECT_GT(full, empty + 100);        // axes, points, labels, legend
}

TEST(AccuracyPanel, RangeCoversThePointsInWholeDecades) {
    const auto r = penumbra::ui::accuracyPlotRange(handStudy());
    ASSERT_TRUE(r.valid);
    EXPECT_DOUBLE_EQ(r.logTimeMin, -2);  // 0.01 s
    EXPECT_DOUBLE_EQ(r.logTimeMax, 0);   // 0.64 s
    EXPECT_DOUBLE_EQ(r.logErrMin, -3);   // 0.0015625
    EXPECT_DOUBLE_EQ(r.logErrMax, -1);   // 0.1
    EXPECT_FALSE(penumbra::ui::accuracyPlotRange(AccuracyStudy{}).valid);
    // An equal-error time beyond the sampled curve (extrapolated) widens the time axis to hold it.
    AccuracyStudy far = handStudy();
    far.equalErrorSeconds = 2;
    EXPECT_DOUBLE_EQ(penumbra::ui::accuracyPlotRange(far).logTimeMax, 1);
}

}  // namespace
