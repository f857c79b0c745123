// The Preview panel: the progressive render (exact, sampled, side by side, difference) as a
// thumbnail, its mode, passes and light samples (PreviewSettings, edited here), whether it fills
// the 3D view (ViewMode, edited here), the exact-visibility options (ExactOptions, edited here:
// the command line's option group, same meaning and defaults), passes done and error.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "app/viewer/layout.h"
#include "app/viewer/preview_runner.h"

namespace penumbra::viewer {

// What the 3D view shows: the preview's image at the view's own resolution (the rendered view, the
// default: exact, sampled, exact and sampled split at a draggable line, the difference or the
// answers, as the preview's mode says), or the rasterised scene (flat colours; also what the
// rendered view shows until its image pictures the view: before the first pass, and while the
// camera moves faster than the coarse passes follow), with the overlays on top.
enum class ViewMode { Raster, Rendered };

// The names of the command line's --view (screenshot, view): raster, or the rendered view with
// the preview's mode: rendered (exact), sampled, side (exact and sampled, split), diff, answers
// (how the exact render answered each pixel). False for any other name (nothing is changed then).
bool parseViewName(std::string_view name, ViewMode& view, PreviewMode& mode);
inline constexpr const char* kViewNames = "raster, rendered, sampled, side, diff or answers";

struct PreviewPanel {
    enum class Action { None, Restart, SaveView, Reopen };
    // Restart when `settings`, `view` or the renderer's exact options changed (the preview must
    // restart); Reopen when the build budget is applied (the store's trees follow it: the scene
    // is reopened); SaveView when its button asks to save the view under the path `saveStem`
    // (edited here). `texture` holds `image`.
    // `viewNote`: what the 3D view shows when the rendered view shows no full image (Preview::
    // viewNote; "" for none).
    static Action draw(PreviewSettings& settings, ViewMode& view, ExactOptions& exact,
                       std::array<char, 256>& saveStem, const PreviewImage& image, bool running,
                       uint32_t texture, const std::string& viewNote);
};

}  // namespace penumbra::viewer
