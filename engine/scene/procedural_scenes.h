// Procedural test scenes: the scenes of Mora & Aveneau 2005 rebuilt from boxes and triangles, a
// Cornell box, a set of small adversarial "hard cases", random triangle soups, and a similarity
// transform.
//
// Conventions shared by every scene built here:
//   - faces are planar and strictly convex (no collinear consecutive vertices, no zero area), their
//     vertices counter-clockwise seen from the front (normal by the right-hand rule);
//   - in the paper scenes and the Cornell box every face is a triangle except the floor receiver(s)
//     and the light, which are quads; the hard cases also use convex quad occluders. The floor is
//     always the first face(s), so tests can pick face 0 as the receiver;
//   - each scene has exactly one light, a quad (material "light", Ke = (15,15,15)), facing the
//     floor;
//   - faceSourceLine is all zeros; collectLights() has been called.
// Coordinates are small integers or dyadic fractions wherever a configuration depends on exact
// coincidence (touching, collinear, coplanar), so those configurations are exact in doubles.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene/scene.h"

namespace penumbra {

// Number of triangles the scene's faces triangulate into: sum over faces of (vertices - 2).
uint32_t triangleCount(const Scene& scene);

// A staircase: floor quad (face 0), 20 steps as boxes (no bottom faces), a back wall, two side
// walls, a ceiling, two posts and a slanted handrail; one quad light below the ceiling. 244
// triangles (the floor and light quads count as two each).
Scene makeStairs();

// A table with four chairs and a potted plant (leaves: small triangles) on a floor quad (face 0);
// one quad light above. 1,350 triangles.
Scene makeTable();

// Two parallel grids of bars (one of bars along x, one of bars along y, at different heights)
// between a floor of 2x2 quads (faces 0..3) and a quad light. 154 triangles.
Scene makeGrids();

// The classic Cornell box (Cornell University's measured data, y up): floor quad (face 0),
// ceiling, back, left and right walls, short and tall blocks; the light is a separate quad 0.8
// below the ceiling, facing down. Walls face the inside of the box, blocks face outward.
Scene makeCornellBox();

// Small adversarial scenes, each a floor receiver quad (face 0), a light quad (face 1) and a few
// occluders. Names: "shared_vertices", "collinear_with_light_edges", "through_light_vertices",
// "touching_light", "standing_on_receiver", "coplanar_overlap_tjunction", "slivers",
// "translated_1e5", "scaled_1e-3", "scaled_1e3", "grazing_light", "straddling_horizon".
// Exactness: "translated_1e5" and "scaled_1e3" are exact images of the base scene (all its
// coordinates are dyadic with few bits); "scaled_1e-3" is not (1e-3 is not a double): axis-aligned
// quads stay exactly planar, but exact contacts of the base scene may become near-contacts.
std::vector<std::pair<std::string, Scene>> makeHardCases();

// `triangles` random triangles (edge lengths about 0.05..0.4) between the floor quad
// [0,1]x[0,1] at z=0 (face 0, facing +z) and a light quad [0.25,0.75]^2 at z=2 (face 1, facing
// -z); triangles lie in 0.1 <= z <= 1.9. Deterministic in `seed`.
Scene makeRandomSoup(int triangles, uint64_t seed);

// Every vertex v becomes v * scale + translate (componentwise, in that order). Faces, materials
// and lights are unchanged. Exact when scale and translate keep all coordinates representable.
Scene transformed(const Scene& scene, double scale, Vec3 translate);

}  // namespace penumbra
