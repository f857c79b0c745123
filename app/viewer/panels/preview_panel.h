// The Preview panel: the progressive render (exact, sampled, side by side, difference) as a
// thumbnail, its mode and light samples (PreviewSettings, edited here), passes and error.
#pragma once

#include <cstdint>

#include "app/viewer/layout.h"
#include "app/viewer/preview_runner.h"

namespace penumbra::viewer {

struct PreviewPanel {
    // Returns true when `settings` changed (the preview must restart). `texture` holds `image`.
    static bool draw(const PanelRect& rect, PreviewSettings& settings, const PreviewImage& image,
                     bool running, uint32_t texture);
};

}  // namespace penumbra::viewer
