// JSON scene files (.json): compose meshes of any supported format with transforms, material
// overrides, extra polygons, area lights, point lights and a camera.
//
// {
//   "meshes": [{                         // optional, each entry:
//     "file": "bunny.obj",               //   required; relative to the JSON file's directory;
//                                        //   .obj .ply .off .stl .gltf .glb (not .json)
//     "transform": T,                    //   optional, applied first
//     "fit_into": {"min": [x, y, z], "max": [x, y, z],   // optional, applied after "transform":
//                  "align": ["center", "min", "center"]}, //   the mesh is scaled uniformly (the
//                                        //   largest scale that fits) and translated into the box;
//                                        //   "align" per axis "min", "center" (default) or "max"
//     "material": M,                     //   optional: every face gets this one material
//     "materials": {"NAME": M, ...},     //   optional: changes the given fields of the mesh's
//                                        //   own materials (by name)
//     "strict": false,                   //   optional: this mesh's repairs are errors
//                                        //   (overrides the file's "strict")
//     "drop_degenerate_faces": true      //   optional: true drops degenerate faces (and repairs
//                                        //   non-planar and non-convex ones) with a warning even
//                                        //   when strict; false refuses them even when not
//   }],
//   "strict": false,                     // optional: every mesh loads in strict mode
//   "polygons": [{"vertices": [[x, y, z], ...], "material": M}],   // optional: plain faces
//   "area_lights": [{"vertices": [[x, y, z], ...], "emission": E, "kd": C}],   // optional
//   "point_lights": [{"position": [x, y, z], "intensity": E}],        // optional
//   "moved_lights": [{"light": i, "vertices": [[x, y, z], ...]}],      // optional
//   "camera": {"eye": [x, y, z], "target": [x, y, z], "up": [0, 1, 0], "fov_y": 45}  // optional
// }
// T is an object {"scale": s | [sx, sy, sz], "rotate": {"axis": [x, y, z], "degrees": d},
// "translate": [x, y, z]} (each optional; applied in the order scale, rotate, translate; rotation
// counter-clockwise about the axis by the right-hand rule), or {"matrix": [[a, b, c, d], [e, f, g,
// h], [i, j, k, l], [0, 0, 0, 1]]} (row-major, affine, p' = M p), or an array of these applied
// first to last. A transform with a negative determinant (a mirror) reverses every face's vertex
// order so that faces stay counter-clockwise seen from the front; a singular one is an error.
// M is {"name": "...", "kd": C, "ks": C, "ke": C, "ns": n}: fields left out keep Material's
// defaults (for "material" and polygons) or the mesh's own values (for "materials").
// C and E are [r, g, b] or one number for all three; all colours non-negative, an area light's
// emission nonzero. Polygons and area lights must be planar and strictly convex, counter-clockwise
// seen from the front (an area light emits to its front only).
// The scene: faces in the order meshes (each in its file's face order), polygons, area lights;
// lights are the emissive faces in that order (so a mesh's own emissive faces, e.g. the Cornell
// box's lamp, stay lights). The camera is "camera", else the first mesh's camera (transformed),
// else none. Point lights are those of the file plus the meshes' (transformed). Materials are the
// meshes' (names made unique with a suffix "_2", "_3", ...) followed by the file's own.
// "moved_lights" places light i (the scene's numbering: its emissive faces in the order above) at
// the given vertices, one per vertex of its face in its order, after everything else is read: how
// the viewer saves a light it moved (engine/scene/light_move.h). The face must stay exactly planar
// and strictly convex (never repaired); a light whose face shares vertices gets its own.
// Repairs (engine/io/load_options.h, docs/formats.md): a mesh file loads in repair mode, its
// repairs reported as warnings ("scene.json: meshes[0]: <the mesh file's warning>"), unless the
// caller asks for strict mode (the command line's --strict: every mesh strict, whatever the file
// says) or the file does ("strict" at the top level or in the mesh entry, the entry's winning);
// "drop_degenerate_faces" then sets the face policy alone. Polygons and area lights are never
// repaired.
// Unknown keys are errors (they are usually typos). Every error is a SceneError naming the JSON
// file and the JSON path of the element: "scene.json: meshes[2].transform.scale: expected a
// number or 3 numbers"; an error inside a mesh file reads "scene.json: meshes[2]: <the mesh
// file's error>"; a JSON syntax error gives the line.
#pragma once

#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "engine/io/load_options.h"
#include "engine/scene/light_move.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_error.h"

namespace penumbra {

// Reads a JSON scene file and every mesh file it names; `options` is the caller's (strict mode
// makes every mesh strict).
Scene loadJsonScene(const std::filesystem::path& path, const LoadOptions& options = {});

// The same from memory: mesh paths are relative to `baseDirectory`; `sourceName` names the file in
// errors and becomes sourcePath.
Scene loadJsonSceneFromString(std::string_view json, const std::filesystem::path& baseDirectory,
                              std::string sourceName, const LoadOptions& options = {});

// The text of a JSON scene file, to be written at `target`, that shows the scene of `source` (a
// JSON scene or a mesh file of any supported format) from `camera`: a JSON source is kept as it is
// but for its "camera" (its mesh paths rebased onto target's directory); a mesh file becomes
// {"meshes": [{"file": ...}], "camera": ...}. Loading it gives the same scene and that camera
// (the viewer's "save view"). A scene that got the default light (`defaultLight`, from
// Scene::defaultLight) keeps it as an explicit area light, the last (as it was): loading the file
// gives the same lit scene with or without --no-default-light. Lights the viewer moved
// (`movedLights`) are written as "moved_lights" entries, replacing the source's entry for the same
// light (the default light is moved through its corners: leave it out). Throws SceneError when a
// JSON source cannot be read or parsed.
std::string jsonSceneWithCamera(const std::filesystem::path& source, const Camera& camera,
                                const std::filesystem::path& target,
                                const DefaultLight* defaultLight = nullptr,
                                std::span<const PlacedLight> movedLights = {});

}  // namespace penumbra
