// Face checking for freshly loaded scenes: every face goes through checkFace
// (engine/scene/scene_validation.h); zero-area faces are an error or, on request, dropped with a
// warning.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "engine/scene/scene.h"

namespace penumbra {

// What a loader does with a face that breaks the contract but can be repaired (FaceDefect::Kind):
// kReject is strict mode, kDrop repair mode (drop zero-area faces, split non-planar and non-convex
// ones into triangles).
enum class DegenerateFaces {
    kReject,  // strict: a SceneError naming the face
    kDrop,    // repair: dropped or split; each kind of repair reported in Scene::warnings
};

// Names face `face` (its index before anything was dropped) in messages, e.g. "mesh 0 primitive 1
// triangle 7". An empty namer gives "face N".
using FaceNamer = std::function<std::string(uint32_t face)>;

// Checks a scene as a loader produced it: validateSceneStructure, then checkFace on every face
// (in parallel for large scenes; the reported face is always the first bad one in face order).
//   - an Invalid defect: SceneError(scene.sourcePath, the face's source line,
//     "<name>: <message>"), under either policy;
//   - a Degenerate, NonPlanar or NonConvex face: the same error under kReject. Under kDrop a
//     degenerate face is removed, and a non-planar or non-convex one is replaced, in place, by the
//     triangles of PolygonTriangulation (exact, of its own vertices; each keeps the face's
//     material and source line; a polygon no projection of which is simple is an error). So the
//     faces after it are renumbered: face numbers everywhere (query --face, the visibility file)
//     refer to the repaired mesh, and faceSourceLine still gives each face's line in the file.
//     One warning per kind of repair is appended to scene.warnings:
//     "<sourcePath>: dropped N degenerate (zero-area) faces of M (first: <name>, line L: <why>)",
//     "<sourcePath>: split N non-planar faces into T triangles (first: ...)", and the same for
//     non-convex faces.
// Finally rebuilds scene.lights (Scene::collectLights). Throws SceneError "no faces" when nothing
// is left.
void checkLoadedFaces(Scene& scene, DegenerateFaces policy, const FaceNamer& name = {});

}  // namespace penumbra
