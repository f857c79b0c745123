// OverlayGeometry: the debug drawing for an inspected point, in world space: the point marker and
// its normal, each light's visible fragments (filled in the palette's colours, their edges dark,
// the region's boundary in kOutlineColour), and the occluder edges of the history-tree path of
// the selected light.
#pragma once

#include <optional>
#include <vector>

#include "app/viewer/palette.h"
#include "engine/precompute/point_inspection.h"

namespace penumbra::viewer {

struct OverlayGeometry {
    // Interleaved x y z r g b a per vertex.
    std::vector<float> fragmentTriangles;  // depth-tested, pulled forward onto the light
    std::vector<float> lines;              // depth-tested (fragment edges, region outline)
    std::vector<float> linesOnTop;         // drawn over everything (marker, normal, path edges)
    bool empty() const { return fragmentTriangles.empty() && lines.empty() && linesOnTop.empty(); }
};

// `sceneSize` (the scene's bounding-box diagonal) scales the marker and the normal.
// selectedLight: the light whose path edges are shown (all lights when empty).
OverlayGeometry buildOverlay(const PointInspection& inspection, double sceneSize,
                             std::optional<size_t> selectedLight);

}  // namespace penumbra::viewer
