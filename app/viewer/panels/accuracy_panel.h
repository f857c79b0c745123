// AccuracyPanel: the viewer's "Accuracy vs time" window. Draws an AccuracyStudy
// (engine/studies/accuracy_study.h) as a log-log plot of RMSE against wall time: the sampled curve
// (one point per shadow-ray count, labelled), the exact method's point, the reference's noise level
// and the equal-error marker, with a legend and a table of the figures. Only ImGui calls and
// ImDrawList primitives (ImGui 1.86): the host provides the backend.
#pragma once

#include <imgui.h>

#include <array>
#include <cstddef>

#include "engine/studies/accuracy_study.h"

namespace penumbra::ui {

// The plot's data range and mapping (for tests): log10 of time (x) and of RMSE (y).
struct AccuracyPlotRange {
    double logTimeMin = 0, logTimeMax = 1, logErrMin = 0, logErrMax = 1;
    bool valid = false;  // false when there is no positive point to plot
};
AccuracyPlotRange accuracyPlotRange(const AccuracyStudy& study);

class AccuracyPanel {
  public:
    void setResult(const AccuracyStudy& study);
    void clear();
    bool hasResult() const { return has_; }
    // Draws the window `title` (Begin/End inside).
    void draw(const char* title);
    // Points drawn in the last frame (sampled + exact), for tests.
    size_t pointsDrawn() const { return pointsDrawn_; }
    const AccuracyStudy& study() const { return study_; }
    // The window's screen rectangle (x, y, width, height) in the last frame drawn.
    const std::array<float, 4>& windowRect() const { return windowRect_; }

  private:
    void drawPlot(ImDrawList* dl, ImVec2 origin, ImVec2 size);

    AccuracyStudy study_;
    AccuracyPlotRange range_;
    bool has_ = false;
    size_t pointsDrawn_ = 0;
    std::array<float, 4> windowRect_{0, 0, 0, 0};
};

}  // namespace penumbra::ui
