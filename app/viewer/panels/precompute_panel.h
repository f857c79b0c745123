// The Precompute panel: progress of the background precompute of every pair (PrecomputeJob), its
// start and cancel, the visibility file's Load and Save (visibility_link.h), and below it what the
// preview's render simulates for this scene, under a line that names the image (EffectsSummary of
// the preview's exact image, or of its sampled one in the sampled mode; before any render of the
// scene, its lights as the scene holds them).
#pragma once

#include <optional>
#include <string>

#include "app/viewer/layout.h"
#include "app/viewer/visibility_link.h"
#include "engine/precompute/precompute_scheduler.h"
#include "engine/render/effects_summary.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

struct PrecomputePanel {
    enum class Action { None, Start, Cancel, LoadFile, SaveFile };
    // `progress`: the precompute's, as the frame found it (none: never started); `effects`: of the
    // open scene's last render (EffectsSummary::method empty: nothing rendered yet); `scene`: the
    // open scene (nullptr: none); `visibility`: the visibility file, if any.
    static Action draw(const std::optional<PrecomputeProgress>& progress,
                       const EffectsSummary& effects, const Scene* scene,
                       const VisibilityLink& visibility);
    // "done: 1378 of 1378 pairs, 5120 nodes, 1.2 MiB, 3.4 s" (running, cancelled, over budget,
    // failed; idle before any batch): the panel's line, and the status line's when a batch ends.
    static std::string progressLine(const PrecomputeProgress& progress);
};

}  // namespace penumbra::viewer
