// What the scene loaders do with data that other tools repair (docs/formats.md): repair it with a
// warning in Scene::warnings (the default), or refuse it (strict mode, the CLI's --strict, a JSON
// scene's "strict").
//
// Repairs that depend on `faces` (engine/scene/face_check.h, checkLoadedFaces): degenerate faces
// dropped, non-planar and non-convex polygons split into triangles, and each loader's own early
// checks of degenerate data (an OBJ face repeating a vertex index, STL facets whose corners
// coincide). Repairs that depend on `strict`: OBJ materials that are missing (a usemtl naming no
// material, an unreadable mtllib, a newmtl without a name) and unknown PLY header lines.
// Broken data (indices out of range, non-finite or out-of-contract coordinates, truncated files,
// numbers that do not parse, unsupported glTF versions and required extensions) is refused in
// both modes.
//
// Not a repair: `defaultLight` gives a scene with no light at all the default area light
// (engine/scene/default_light.h). Off here, so that a scene is what its file says; the commands
// and the viewer turn it on (their --no-default-light turns it off).
#pragma once

#include "engine/scene/face_check.h"

namespace penumbra {

struct LoadOptions {
    DegenerateFaces faces = DegenerateFaces::kDrop;
    bool strict = false;
    bool defaultLight = false;

    LoadOptions() = default;
    // A face policy alone (the loaders' former parameter): kReject is strict mode, every repair
    // an error; kDrop is repair mode.
    LoadOptions(DegenerateFaces f)  // NOLINT(google-explicit-constructor): the former parameter
        : faces(f), strict(f == DegenerateFaces::kReject) {}

    // Every repair an error.
    static LoadOptions strictMode() { return LoadOptions(DegenerateFaces::kReject); }
    // What the commands and the viewer load with by default: repairs, and the default light.
    static LoadOptions forCommands() {
        LoadOptions o;
        o.defaultLight = true;
        return o;
    }
};

}  // namespace penumbra
