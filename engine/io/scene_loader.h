// loadScene: reads a scene file of any supported format, chosen by extension (case-insensitive):
//   .obj          engine/io/obj_io.h      (own reader: MTL materials, Ke area lights, usemtl per
//   face) .ply .off .stl engine/io/openmesh_io.h (OpenMesh; geometry only, default material) .gltf
//   .glb    engine/io/gltf_io.h     (tinygltf; PBR materials, emissive lights, node
//                                       transforms, camera)
//   .json         engine/io/scene_file.h  (composition of the above, with lights and a camera)
// Every face is validated (engine/scene/scene_validation.h via engine/scene/face_check.h); problems
// are SceneErrors naming the file and the element. What other tools repair (degenerate faces,
// non-planar and non-convex polygons, missing OBJ materials, unknown PLY header lines) is repaired
// by default with one warning line per kind and file in Scene::warnings, and refused in strict
// mode (engine/io/load_options.h; docs/formats.md lists both).
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "engine/io/load_options.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_error.h"

namespace penumbra {

// The supported extensions, lower case with the dot, separated by ", ": for messages.
std::string supportedSceneExtensions();

// True when loadScene can read files with this extension ("." included, any case).
bool isSupportedSceneExtension(std::string_view extension);

// Reads the file as loadScenePart does, then what concerns the whole scene: the default light when
// `options.defaultLight` and the scene has no light (engine/scene/default_light.h), and a warning
// for lights that face away from every other face (engine/scene/light_checks.h).
// Reads the file in repair mode (the default) or strict mode; a JSON scene file takes `options`
// for its meshes unless it says otherwise ("strict", "drop_degenerate_faces":
// engine/io/scene_file.h). Throws SceneError; an unknown extension is the SceneError
// "unknown scene format '.xyz' (supported: ...)".
Scene loadScene(const std::filesystem::path& path, const LoadOptions& options = {});

// The file alone, as one part of a scene (a JSON scene's meshes are read this way): its format's
// reader and the lights' area check, no default light and no scene-wide light warnings.
Scene loadScenePart(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace penumbra
