// defaultCamera: the one rule for the camera a scene is seen from when none is given (`render`,
// `bench`, `view`, `screenshot`): the scene's own (Scene::camera) when the file has one, else a
// fitted camera (Camera::fitting) from the direction that sees most front faces.
//
// Why: a closed room such as the Cornell box fitted from an arbitrary direction shows only the
// back of its walls; its open side is where the interesting view is. Each of 8 candidate
// directions (the four horizontal axes and diagonals, raised 20 degrees), with y up and then
// with z up, casts a 24 x 24 grid of rays through the BVH; a candidate scores the hits on the
// front side of a face. A heuristic: ties keep the first candidate (the traditional -z view of the
// Cornell box comes first). With `up` given, only that up direction is tried (and the scene's own
// camera gets it).
//
// A light emits from its front only and its back renders black: a candidate whose rays reach the
// back of a light first (the eye strictly behind the light's plane, exact; the grid's rays, and
// rays to the light's centroid and corners for a light small in the image) is taken only when no
// other shows anything. When the best candidate sees one, the best of the others is taken, else
// of the same directions raised only 5 degrees (an eye below a light that hangs over the
// scene); only when none of them shows anything without a light's back is the best
// kept. The candidates are fitted to the file's geometry (Scene::fileBounds): the default light
// hangs D / 2 over it, above the eye (engine/scene/default_light.h).
#pragma once

#include <optional>

#include "engine/raytrace/embree_scene.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"

namespace penumbra {

Camera defaultCamera(const Scene& scene, const EmbreeScene& bvh,
                     std::optional<Vec3> up = std::nullopt);

}  // namespace penumbra
