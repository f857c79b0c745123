// The Light plane panel: the selected light polygon seen from its front, in its own plane, with
// the fragments visible from the inspected point filled in their overlay colours.
#pragma once

#include "app/viewer/layout.h"
#include "app/viewer/selection.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::viewer {

struct LightPlanePanel {
    static void draw(const Selection& selection, const vis::PolygonMesh* mesh);
};

}  // namespace penumbra::viewer
