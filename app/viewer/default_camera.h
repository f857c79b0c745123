// defaultCamera: the camera a scene opens with: its own (Scene::camera) when the file has one,
// else a fitted camera (Camera::fitting) from the direction that sees most front faces.
//
// Why: a closed room such as the Cornell box fitted from an arbitrary direction shows only the
// back of its walls; its open side is where the interesting view is. Each of 8 candidate
// directions (the four horizontal axes and diagonals, raised 20 degrees), with y up and then
// with z up, casts a 24 x 24 grid of
// rays through the BVH; a candidate scores the hits on the front side of a face. A heuristic:
// ties keep the first candidate (the traditional -z view of the Cornell box comes first).
#pragma once

#include "app/viewer/loaded_scene.h"
#include "engine/scene/camera.h"

namespace penumbra::viewer {

Camera defaultCamera(const LoadedScene& scene);

}  // namespace penumbra::viewer
