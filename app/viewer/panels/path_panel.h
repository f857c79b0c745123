// The Path panel: the history-tree path the selected light's query walked, one row per visited
// node (depth, node, the node's occluder edge and face, and the side the light polygon went to).
#pragma once

#include "app/viewer/layout.h"
#include "app/viewer/selection.h"

namespace penumbra::viewer {

struct PathPanel {
    static void draw(const Selection& selection);
};

}  // namespace penumbra::viewer
