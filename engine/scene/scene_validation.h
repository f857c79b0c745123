// Scene validation: the geometric contract the visibility core relies on, checked once on load.
//
// Every face must be an exactly planar, strictly convex, non-degenerate polygon:
//   - at least 3 vertices, all indices in range, finite coordinates;
//   - no vertex index repeated, no two consecutive vertices at the same position;
//   - not all vertices collinear ("degenerate (zero area)"), decided exactly;
//   - exactly planar: every vertex in the plane of the first two and the first vertex off their
//     line, by the exact orient3d sign (no tolerance: a quad planar only to rounding is not
//     planar). Triangles are always planar. So the face's plane is the same from any three of
//     its vertices that are not collinear, whichever vertex its list starts at (face_plane.h);
//   - strictly convex: projected onto the coordinate plane that drops the dominant axis of n, every
//     turn (p[i-1], p[i], p[i+1]) has the same strict sign, decided exactly (filtered orient2d with
//     a GMP fallback). A zero turn is "collinear vertices", a turn of the other sign is a reflex
//     vertex ("non-convex"), and a polygon whose turns all agree but whose edges wind around more
//     than once (a pentagram) is self-intersecting ("non-convex").
// What breaks it is one of four kinds (FaceDefect::Kind): a zero-area face (Degenerate, which a
// loader drops in repair mode), a non-planar one (NonPlanar) or one that is planar but not strictly
// convex, or has repeated vertices (NonConvex), both split into triangles of their own vertices in
// repair mode (face_check.h, polygon_triangulation.h), and anything else (Invalid: always an
// error). Messages name faces and vertices by their 0-based index in the scene (for a scene read
// from an OBJ file the vertex's OBJ index is one more), and give the face's source line as the
// location. Scene-wide: at most 2^30 vertices and 2^30 faces (so 32-bit ids are safe), faceMaterial
// and faceSourceLine either empty or one per face, material indices in range, lights naming faces.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/scene.h"
#include "engine/scene/scene_error.h"
#include "visibility/orient2d.h"

namespace penumbra {

// The most vertices, and the most faces, a scene may have.
inline constexpr size_t kMaxSceneElements = size_t{1} << 30;

// The coordinate contract: every coordinate of a scene (vertices, point lights, the camera) is
// finite with magnitude at most 2^59 (about 5.8e17). Derived, not tried:
//   - Embree works in floats and takes a ray only when every component of its origin and direction
//     is at most FLT_LARGE = 1.844e18 (its ray validity check; beyond, it aborts): a direction is
//     the difference of two scene points, at most 2^60 < 1.844e18 in magnitude under the contract;
//   - the exact core then stays far inside the double range: an orient3d of such points is below
//     2^183, a product of two (edge_line.h) below 2^367, so no filter overflows (outside the
//     expansion arithmetic's [2^-200, 2^200] the predicates take GMP rationals, still exact);
//   - so do the face checks (cross products and Newell normals are degree 2 and 3).
// No lower bound: tiny magnitudes are exact in the core (GMP), and Embree's float rounding of them
// only moves a primary hit, as any rounding does. validateSceneStructure refuses what breaks it,
// naming the element.
inline constexpr double kMaxCoordinate = 0x1p59;

// The problem with one point under the coordinate contract ("non-finite coordinate" or "coordinate
// X beyond the supported magnitude 2^59 = 5.8e17"), or nullopt.
std::optional<std::string> coordinateProblem(const Vec3& p);

// The smallest area light doubles resolve. A light's visible fragments have rounded vertices
// (constructions: each coordinate within a few u = 2^-53 of the largest magnitude M_i it reaches
// along that axis), and a vertex within about u |y - x| of a cutting plane through the query point
// x is taken as on it (the snap rule, polygon_clip.h; |y - x| is at most the scene's size S). So a
// fragment's area carries an absolute error of order u W, with
//   W = sum over the axes i of max(M_i, S) (E_j + E_k)   (E: the light's extents on the other
//   axes),
// and the light's visible fraction one of u W / area. A light face whose area is at most
// kMinLightAreaFactor * W (2^13 u W: the fraction's error would reach about 1e-4) is refused,
// naming the face: a sliver whose area lies below what its own coordinates resolve, or a light
// some 1e12 times smaller than the scene (found by fuzzing: a light of area 6e-39 two units long
// whose clipped fragment came out 4e21 times larger than the light; a light 1e-40 across seen from
// 3e4 away, 15% too large). Harmless as an occluder (the core is exact): refused only as a light.
// (The snap width also grows as 1 / sin(theta) for cutting planes nearly parallel to the light;
// README, the one approximation.)
inline constexpr double kMinLightAreaFactor = 0x1p-40;

// W above for face f of a scene of size `sceneSize` (its bounding box's diagonal).
double lightResolutionWeight(const vis::PolygonMesh& mesh, uint32_t f, double sceneSize);
// The problem with light face `f` under that rule, or nullopt.
std::optional<std::string> lightAreaProblem(const vis::PolygonMesh& mesh, uint32_t f,
                                            double sceneSize);
// Throws SceneError naming scene.sourcePath, the face and its source line for the first light in
// scene.lights that breaks the rule (validateSceneStructure does this too; loadScene calls it
// once the loader has collected the lights).
void validateLights(const Scene& scene);

// Throws SceneError naming scene.sourcePath, the face index and the face's source line on the first
// face (in face order) that breaks the contract above. Returns normally when the scene is valid.
// Equivalent to validateSceneStructure followed by checkFace on every face.
void validateScene(const Scene& scene);

// The scene-wide part of validateScene: element limits, faceMaterial and faceSourceLine sizes,
// material indices, lights in range. No per-face geometry.
void validateSceneStructure(const Scene& scene);

// Why one face breaks the contract.
struct FaceDefect {
    enum class Kind : uint8_t {
        Degenerate,  // zero area: every distinct vertex on one line (exact), or an area that rounds
                     // to zero; dropped in repair mode
        NonPlanar,   // a vertex off the plane of three others (exact); split in repair mode
        NonConvex,   // planar, but concave, self-touching, with collinear vertices or with a
                     // vertex repeated; split in repair mode
        Invalid,     // an index out of range, a non-finite coordinate, fewer than 3 vertices
    };
    Kind kind = Kind::Invalid;
    std::string message;  // without location, e.g. "non-planar: vertex 7 lies ..."
    bool degenerate() const { return kind == Kind::Degenerate; }
    bool splittable() const { return kind == Kind::NonPlanar || kind == Kind::NonConvex; }
};

// Buffers checkFace reuses from face to face; one per thread.
struct FaceCheckScratch {
    std::vector<uint32_t> sorted;
    std::vector<Vec3> p, q;
    std::vector<vis::Point2> s;
    std::vector<int> turn;
};

// The per-face part of validateScene: nullopt when face `face` of the mesh meets the contract.
std::optional<FaceDefect> checkFace(const vis::PolygonMesh& mesh, uint32_t face,
                                    FaceCheckScratch& scratch);

}  // namespace penumbra
