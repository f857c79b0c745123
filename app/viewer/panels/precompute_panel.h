// The Precompute panel: progress of the background precompute of every pair (PrecomputeJob), its
// start and cancel, and what the renderer simulates for this scene (EffectsSummary of the
// preview's render; before any render of the scene, its lights as the scene holds them).
#pragma once

#include "app/viewer/layout.h"
#include "app/viewer/precompute_job.h"
#include "engine/render/effects_summary.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

struct PrecomputePanel {
    enum class Action { None, Start, Cancel };
    // `effects`: of the open scene's last render (EffectsSummary::method empty: nothing rendered
    // yet); `scene`: the open scene (nullptr: none).
    static Action draw(const PanelRect& rect, const PrecomputeJob& job,
                       const EffectsSummary& effects, const Scene* scene);
};

}  // namespace penumbra::viewer
