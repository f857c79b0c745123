// DefaultLight: the area light a scene with no light of its own gets, so that a model without
// emissive materials does not render black with exit status 0. The commands and the viewer add it
// (LoadOptions::defaultLight; --no-default-light turns it off) and say so: one line on stderr,
// the viewer's status line and state, the render's and the precompute's summaries; a saved view
// keeps it as an explicit area light of its JSON scene.
//
// The rule, for the bounds B of the scene (diagonal D) and its up direction:
//  - up: the scene camera's up (JSON, glTF) snapped to the nearest axis, its sign kept; without a
//    camera +y, the usual convention of OBJ and glTF files (scenes have no other up: the default
//    camera tries +y then +z). Along an axis, the light's plane is one coordinate, exactly
//    outside B.
//  - a square centred over B, its side a quarter of B's larger horizontal extent (D / 4 when B has
//    none): small against the scene, so that an occluder's shadow has a penumbra and an umbra
//    (penumbra width about (occluder height) x side / height), not a uniform wash;
//  - its plane D / 2 above B's top, facing down (counter-clockwise seen from below): it touches no
//    geometry, and it lies above the default camera's eye (fitted 20 degrees up at 1.31 D from
//    B's centre, 0.45 D above it; engine/render/default_camera.h), which so sees its emitting
//    side;
//  - grey emission E with E F = 1, F the form factor of the square from the centre of B's top,
//    facing up: no point of B sees more of it, so a diffuse receiver's radiance is at most its
//    albedo and nothing clips at exposure 1.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>

#include "visibility/vec3.h"

namespace penumbra {

struct Scene;

struct DefaultLight {
    uint32_t face = 0;         // the face added: the scene's last
    uint32_t firstVertex = 0;  // its four vertices, the mesh's last
    int axis = 1;              // up is +/- this axis (0 x, 1 y, 2 z)
    int sign = 1;
    bool upFromCamera = false;         // up snapped from the scene camera's; else +y by convention
    std::array<vis::Vec3, 4> corners;  // counter-clockwise seen from below (its front)
    double side = 0;                   // the square's side
    double height = 0;                 // its plane above B's top, along up
    double emission = 0;               // grey Ke

    // "+y", "-z", ...
    std::string upName() const;
    // The one line that announces it, naming the scene file and how to turn it off.
    std::string announcement(std::string_view file) const;
};

// The material name of the default light's face.
inline constexpr std::string_view kDefaultLightMaterial = "penumbra_default_light";
// What the summaries say of a scene's lights when they are the default one.
inline constexpr std::string_view kDefaultLightNote =
    "the default light: the scene has none of its own; --no-default-light turns it off";

// True for a scene with faces and no light at all: neither area lights nor point lights (a scene
// with point lights only is lit: it keeps its own lighting).
bool needsDefaultLight(const Scene& scene);

// Adds the default light as the scene's last face (its own material, the last) and records it in
// scene.defaultLight. Requires needsDefaultLight(scene). Throws SceneError when the light would
// break the scene contract (coordinates beyond 2^59, an area doubles cannot resolve): a scene
// that close to the limits needs a light of its own.
void addDefaultLight(Scene& scene);

}  // namespace penumbra
