// Picking: the surface point under a pixel, by casting the camera ray through the pixel centre
// into the Embree BVH (EmbreeScene::intersect). The hit (float precision in Embree) becomes the
// point the renderer's direct query takes there (shadingPoint: projected onto the face's plane in
// double, then onto its closed front side), so that the from-point query, which answers a click
// without trees, gets a point on the face.
#pragma once

#include <optional>

#include "app/viewer/gl/scene_renderer.h"
#include "engine/render/embree_scene.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

struct PickedPoint {
    uint32_t face = 0;
    Vec3 point;
};

// (px, py): framebuffer pixel (top-left origin); nullopt outside the viewport or on a miss.
std::optional<PickedPoint> pickSurface(const Scene& scene, const EmbreeScene& bvh,
                                       const Camera& camera, const Viewport& viewport, double px,
                                       double py);

}  // namespace penumbra::viewer
