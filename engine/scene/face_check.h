// Face checking for freshly loaded scenes: every face goes through checkFace
// (engine/scene/scene_validation.h); zero-area faces are an error or, on request, dropped with a
// warning.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "engine/scene/scene.h"

namespace penumbra {

// What a loader does with a degenerate (zero-area) face, see FaceDefect::degenerate.
enum class DegenerateFaces {
    kReject,  // a SceneError naming the face (the default everywhere)
    kDrop,    // removed; the count is reported in Scene::warnings
};

// Names face `face` (its index before anything was dropped) in messages, e.g. "mesh 0 primitive 1
// triangle 7". An empty namer gives "face N".
using FaceNamer = std::function<std::string(uint32_t face)>;

// Checks a scene as a loader produced it: validateSceneStructure, then checkFace on every face
// (in parallel for large scenes; the reported face is always the first bad one in face order).
//   - a non-degenerate defect: SceneError(scene.sourcePath, the face's source line,
//     "<name>: <message>");
//   - a degenerate face: the same error under kReject; under kDrop the face is removed (with its
//     faceMaterial and faceSourceLine entries; vertices are kept) and one warning
//     "<sourcePath>: dropped N degenerate (zero-area) faces of M (first: <name>: <message>)" is
//     appended to scene.warnings.
// Finally rebuilds scene.lights (Scene::collectLights). Throws SceneError "no faces" when nothing
// is left.
void checkLoadedFaces(Scene& scene, DegenerateFaces policy, const FaceNamer& name = {});

}  // namespace penumbra
