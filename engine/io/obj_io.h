// Wavefront OBJ + MTL reading and writing for penumbra::Scene (our own reader; no third-party
// loader).
//
// What is read:
//   v x y z [w | r g b | w r g b]  positions (only x y z used; all numbers must be finite)
//   vt u [v [w]]     texture coordinates (w unused), kept as (u, 1 - v): the scene's v runs down
//                    the image (engine/scene/texture.h)
//   f a b c ...      faces; each vertex `v`, `v/vt`, `v//vn` or `v/vt/vn`, indices 1-based or
//                    negative (relative: -1 is the last vertex or vt so far); v and vt are
//                    checked like each other (a positive one against the whole file), vn must be
//                    a nonzero integer; a face whose every corner names a vt gets those
//                    coordinates (Scene::faceUv), another none
//   usemtl NAME      material of the faces that follow
//   mtllib FILE...   MTL libraries, relative to the OBJ's directory (the whole rest of the line
//                    if that names a file, else whitespace-separated names)
//   ignored: vn vp o g s l p mg lod bevel c_interp d_interp usemap maplib shadow_obj trace_obj
//   csh, comments (`#` to the end of the line), blank lines
//   errors: free-form geometry (cstype, curv, surf, ...), `call`, any unknown statement, binary
//   data (control bytes other than tab/VT/FF)
// Lines end in LF, CRLF or CR; a UTF-8 byte-order mark is skipped; a line ending in `\` (and
// without a `#` comment) continues on the next one, the backslash read as a space.
// MTL: newmtl NAME, Kd, Ks, Ke (1 or 3 non-negative numbers), Ns (one non-negative number), map_Kd
// [options] FILE (Material::kdMap: FILE, the rest of the line, relative to the MTL's directory,
// decoded by engine/io/texture_io.h; -o and -s offset and scale the coordinates, -clamp on clamps
// them, the format's other options are skipped with their arguments); key case is ignored; every
// other key is ignored. A material defined twice is an error. writeObj writes no texture.
//
// Missing materials are repaired (LoadOptions, engine/io/load_options.h), each kind with one
// warning line in Scene::warnings, and are errors in strict mode:
//   - a usemtl naming no material (no mtllib, or a name the libraries do not define): its faces
//     get a default diffuse material (Material's defaults, not emissive) named as the usemtl
//     names it, appended after the libraries' materials ("model.obj: usemtl 'Default' on line 12
//     names no material (no mtllib): 340 faces use a default diffuse material");
//   - an mtllib whose library cannot be read: skipped ("model.obj:2: mtllib: cannot read material
//     library ...; its materials are missing"); its usemtl names are then unknown, as above;
//   - a newmtl without a name: that material and its statements are ignored (the warning names
//     the MTL file and the line);
//   - a map_Kd that cannot be used (its file missing or not an image, an unknown option): the
//     material keeps its Kd alone ("dir/m.mtl:7: map_Kd 'wood.png' (dir/wood.png) of material
//     'table': cannot read file: No such file or directory: the material uses its Kd alone");
//   - faces of a material with a map_Kd that have no vt: they use its Kd alone.
// A repeated vertex index in a face is a degenerate face: dropped with the others under
// DegenerateFaces::kDrop, an error under kReject.
//
// The scene: faces numbered from 0 in file order, faceSourceLine the 1-based OBJ line of each face,
// faceMaterial the index into `materials` (MTL definition order) or -1 before any usemtl, lights
// the faces whose material has a nonzero Ke (Scene::collectLights). The result is validated
// (checkLoadedFaces, engine/scene/face_check.h): faces must be planar, strictly convex and
// non-degenerate; under DegenerateFaces::kDrop (the default) zero-area faces are dropped and other
// polygons repaired with a warning instead (face numbers then refer to the repaired mesh).
//
// Every problem is a SceneError "file:line: message"; a face problem says "face N: ...". An empty
// file, or one without faces, is the error "no faces".
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "engine/io/load_options.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_error.h"

namespace penumbra {

// Reads the OBJ file and its MTL libraries, validates the scene, sets sourcePath to objPath.
// `options`: repair (the default) or strict mode, engine/io/load_options.h.
Scene loadObj(const std::filesystem::path& objPath, const LoadOptions& options = {});

// The same from memory: `mtlText` is the text of every MTL library the OBJ names (read once, even
// if several mtllib names appear). sourceName is the OBJ name used in errors and sourcePath; MTL
// errors name the library as the OBJ names it, relative to sourceName's directory.
Scene loadObjFromString(std::string_view objText, std::string_view mtlText, std::string sourceName,
                        const LoadOptions& options = {});

// Writes the scene (validated first) as objPath and a sibling MTL file with the same stem and the
// extension .mtl; both start with the comment "# penumbra scene v1". Positions are printed with 17
// significant digits (%.17g, locale-independent) so that reading them back gives the same doubles.
// Faces keep their order; a face without a material (-1) that follows faces with one is written
// with an extra material named "penumbra_default" (made unique) holding Material's defaults.
// Each file is written atomically: to a temporary file in the same directory, then renamed over
// the target. On failure the temporary is removed and a SceneError thrown.
void writeObj(const Scene& scene, const std::filesystem::path& objPath);

}  // namespace penumbra
