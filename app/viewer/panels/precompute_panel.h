// The Precompute panel: progress of the background precompute of every pair (PrecomputeJob), its
// start and cancel, and what the renderer simulates for this scene (EffectsSummary).
#pragma once

#include <string>

#include "app/viewer/layout.h"
#include "app/viewer/precompute_job.h"

namespace penumbra::viewer {

struct PrecomputePanel {
    enum class Action { None, Start, Cancel };
    static Action draw(const PanelRect& rect, const PrecomputeJob& job, const std::string& effects);
};

}  // namespace penumbra::viewer
