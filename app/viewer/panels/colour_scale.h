// The colour scales of the preview's false-colour images, drawn in the Preview panel and over the
// 3D view when it shows them: the difference heat map's bar (black, red, yellow, white from 0 to
// the luminance drawn white) with its numbers, and the answers mode's legend (each answer's colour
// with its name and share of the image's evaluations).
#pragma once

#include "app/viewer/layout.h"
#include "app/viewer/preview_runner.h"
#include "app/viewer/viewport.h"

namespace penumbra::viewer {

// In the current window: a bar as wide as the space left, the luminance difference at its ticks
// (0, a third, two thirds, all of image.differenceWhite) and what its top is.
void drawDifferenceScale(const PreviewImage& image);
// In the current window: the answers' colours, names and shares.
void drawAnswersLegend(const PreviewImage& image);

struct ColourScaleOverlay {
    // Over the bottom right of the 3D view, when it shows the difference or the answers (mode),
    // with nothing to click. Returns its rectangle (empty when not drawn).
    static PanelRect draw(const Viewport& view, PreviewMode mode, const PreviewImage& image);
};

}  // namespace penumbra::viewer
