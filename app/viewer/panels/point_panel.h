// The Point panel: the inspected point (face, position, normal) and per light its exact answer
// (visible fraction, form factor, fragments, nodes visited, time); a row selects the light the
// other panels and the overlay show (Selection::selectLight).
#pragma once

#include "app/viewer/layout.h"
#include "app/viewer/selection.h"

namespace penumbra::viewer {

struct PointPanel {
    // Returns true when the selected light changed.
    static bool draw(Selection& selection);
};

}  // namespace penumbra::viewer
