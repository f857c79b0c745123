// LightMove: moving an area light of a scene (the viewer's light controls, `screenshot
// --move-light`), and placing a light's face at given vertices (the JSON scene's "moved_lights",
// which is how a saved view keeps a moved light).
//
// A move is a scale along the world axes, then a rotation, then a translation, the first two about
// the light's centre (the mean of its vertices): p -> c + t + R (S (p - c)). It is affine, so a
// planar convex polygon stays planar and convex, and every factor of S must be positive (a zero
// factor would flatten the light into a segment, a negative one mirror it to emit backwards):
// lightMoveProblem refuses the rest, naming the field.
//
// Exact planarity by construction. The scene contract wants every face exactly planar by the exact
// orient3d sign (scene_validation.h), and a quad rotated in doubles is planar only to rounding. So
// the moved vertices are the transformed ones when those are exactly planar (a translation or a
// scale of an axis-aligned light: every rounding the same), and otherwise are rebuilt in a plane
// that doubles hold exactly: three base vertices snapped to a grid of 2^-24 of the light's largest
// coordinate, and each other vertex written as base + a (b1 - base) + b (b2 - base) with a, b
// multiples of 2^-23 (|a|, |b| <= 8). Every product and sum of that is exact in doubles, so each
// vertex lies exactly in the base plane; a vertex moves by at most about 2^-25 of the largest
// coordinate plus 2^-23 of the light's size (3e-5 on the Cornell box's lamp, 130 across at 548).
// What comes out is checked as the loader checks a face (planar, strictly convex, a light area
// doubles resolve) and refused with the reason, never repaired: a light is never split.
//
// Where the light's face shares vertices with other faces (an OBJ lamp cut out of its ceiling),
// the face gets vertices of its own (appended to the mesh), so that moving it moves no other face.
// Face and light numbers never change; what changes is the mesh's geometry, so every history tree
// and BVH of the scene before the move is stale (the caller rebuilds them; the scene hash follows
// the vertices).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "engine/scene/affine3.h"
#include "engine/scene/scene.h"

namespace penumbra {

struct LightMove {
    Vec3 translate{0, 0, 0};
    Vec3 rotateDegrees{0, 0, 0};  // about the x, then the y, then the z axis (right-hand rule)
    Vec3 scale{1, 1, 1};          // along the world axes; each factor > 0

    bool isIdentity() const;
    // The affine map of the move for a light whose centre is `centre`.
    Affine3 worldFromLight(const Vec3& centre) const;
    bool operator==(const LightMove&) const = default;
};

// Why `move` cannot be applied ("scale: factors must be positive, got 0 on y", "translate:
// non-finite"), or nullopt.
std::optional<std::string> lightMoveProblem(const LightMove& move);

// The centre of light `light` (the mean of its face's vertices).
Vec3 lightCentre(const Scene& scene, uint32_t light);

// The vertices of light `light` moved by `move`, exactly planar (above). Throws SceneError naming
// scene.sourcePath and the light for an out-of-range light, a refused move (lightMoveProblem) or
// a result the contract refuses.
std::vector<Vec3> movedLightVertices(const Scene& scene, uint32_t light, const LightMove& move);

// Places light `light`'s face at `vertices` (one per vertex of the face, in its order): gives the
// face vertices of its own when it shares any, updates scene.defaultLight's corners when it is the
// default light, and checks the face as the loader does (finite coordinates within the contract,
// exactly planar, strictly convex, a light area doubles resolve). Throws SceneError naming
// scene.sourcePath, `where` (e.g. "moved_lights[0]") and the problem; the scene is unchanged then.
void placeLight(Scene& scene, uint32_t light, std::span<const Vec3> vertices,
                const std::string& where);

// A light at the vertices it was moved to: what a saved view records ("moved_lights").
struct PlacedLight {
    uint32_t light = 0;
    std::vector<Vec3> vertices;
};

// placeLight(movedLightVertices(...)).
void moveLight(Scene& scene, uint32_t light, const LightMove& move);

}  // namespace penumbra
