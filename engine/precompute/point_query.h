// Point queries: which face a point lies on, and what each light looks like from a point on a face
// (the exactly visible fragments of the light, their area and form factor), through the history
// tree of each (receiver, light) pair (visibility/fp_query/from_point_query.h).
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "engine/precompute/visibility_store.h"
#include "engine/scene/scene.h"
#include "visibility/answered_point.h"
#include "visibility/face_clusters.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree.h"
#include "visibility/history_tree_builder.h"
#include "visibility/visible_outline.h"

namespace penumbra {

// The result of findFaceContaining: the face, or why there is none.
struct FaceLookup {
    std::optional<uint32_t> face;      // set on success
    std::vector<uint32_t> candidates;  // every face the point is on (several when ambiguous)
    std::string error;                 // set on failure: "point (x, y, z) lies on no face", ...
    bool ok() const { return face.has_value(); }
};

// The tolerance findFaceContaining measures distances with, for a point x of the scene:
//   tol = 1e-9 * (diagonal of the scene's bounding box) + 1e-12 * |x|
// The first term absorbs the rounding of points computed from scene coordinates (e.g. a point
// written with 17 digits, or interpolated on a face); the second the rounding of x itself far from
// the origin.
double pointTolerance(const Scene& scene, const Vec3& x);

// The face x lies on. x is on face f when
//   - its distance to f's plane (through f's first vertex, with f's unit Newell normal) is <= tol,
//   - and, projected onto the coordinate plane that drops the dominant axis of f's normal, it is
//     inside f's polygon or within tol of its boundary (the 2D distance to each edge's line).
// Faces whose bounding box, grown by tol, misses x are rejected first (brute force otherwise).
// No face: an error. Several faces: when they all lie in one plane with the same orientation (every
// vertex of each within tol of the lowest-numbered one's plane, normals pointing the same way;
// e.g. a quad split into two triangles, x on the diagonal) the lowest index is chosen; otherwise
// (x on an edge where two walls meet, or on a double-sided surface) the lookup is ambiguous and
// the error lists the candidate faces.
FaceLookup findFaceContaining(const Scene& scene, const Vec3& x);

// Why x is not a point of face `face`, or nullopt when it is: off the face's plane by more than
// pointTolerance, or outside its boundary by more than that (measured as findFaceContaining
// measures), or `face` out of range. A point off the face it names is outside the contract: its
// answer would come from trees built for another place (query --face refuses it with this text).
std::optional<std::string> pointOffFace(const Scene& scene, uint32_t face, const Vec3& x);

// The point a query for x on `face` answers (visibility/answered_point.h): x itself where it lies
// on or in front of the face's plane (vis::facePlane, exact sign), else x moved to its front side
// by some ulps, with the contact rule decided at x. A point behind the plane by a rounding (one
// typed with decimals, or found within findFaceContaining's tolerance) has an exact answer of its
// own, but not one anybody asks for (slivers along the plane, seconds on a large mesh). The
// viewer's click and the renderer take the same point (engine/render/shading_point.h). Throws
// std::out_of_range for a face out of range.
vis::AnsweredPoint answeredPointOn(const Scene& scene, uint32_t face, const vis::Vec3& x);

// One light as seen from a point x on a receiver face.
struct LightAtPoint {
    uint32_t light = 0;      // light number (index into Scene::lights)
    uint32_t lightFace = 0;  // its face
    double lightArea = 0;    // area of the whole light polygon
    double visibleArea = 0;  // sum of the fragments' areas
    double fraction = 0;     // visibleArea / lightArea
    // Point-to-polygon form factor of the visible fragments, for the receiver's unit normal.
    double formFactor = 0;
    // The same without occluders: the light clipped to the receiver's front hemisphere; 0 when x
    // is not strictly in front of the light's plane.
    double unoccludedFormFactor = 0;
    std::vector<vis::Polygon3> fragments;  // disjoint convex visible parts of the light
    // Their union's boundary (vis::visibleOutline: loops in the light's plane, holes turned the
    // other way) and the form factor integrated over it, Lambert's contour integral: the
    // fragments' form factor to within the outline's weld (approximate, for the debugger: what
    // bounds the shadow, however many pieces the query cut the light into).
    vis::VisibleOutline outline;
    double outlineFormFactor = 0;
    uint32_t nodesVisited = 0;          // history-tree nodes the query visited
    std::vector<vis::TraceStep> trace;  // those nodes, depth-first, with sides
    bool answeredOnContact = false;     // x on a contact line: answered directly, no trace
    vis::PairKind kind = vis::PairKind::BackFacing;  // what the (receiver, light) pair is
    // x's horizon (the receiver's plane) cuts the light: part of it lies behind x, so even a pair
    // with nothing in its shaft leaves less than the whole light (vis::horizonClipsLight).
    bool horizonClipped = false;
    // A partial tree (vis::HistoryTree::deferred): its deferred occluders, those the query clipped
    // against from x, and the clips that changed a fragment.
    uint32_t deferredOccluders = 0, deferredActive = 0, deferredClips = 0;
    // Answered through the pair's history tree (queryPoint), or without one (queryPointDirect:
    // no kind, path or counters then; the same fragments).
    bool fromTree = true;
    // queryPointDirect with face groups: the groups of faces seen all from one side that the
    // query took whole (vis::FaceClusters: only their boundaries entered its boundary chain).
    uint32_t faceGroups = 0;
    // The groups and faces it left out as the back of a closed surface taken as a solid
    // (vis::ClosedSurfaces), and whether such a surface hid the whole light (x inside it).
    uint32_t solidGroupsLeftOut = 0, solidFacesLeftOut = 0;
    bool hiddenBySolid = false;
    // False only for a direct answer stopped by its work limit: the fragments are incomplete.
    bool complete = true;
};

// Every light (or only light `onlyLight`) of the store's scene as seen from x on face `face` (x is
// not projected onto the face; it is answered at answeredPointOn(x), the point every path
// answers for it, with the contact rule decided at x). A point behind a light's plane gets fraction
// 0 and form factors 0; so does the light's own face (kind BackFacing, no tree built). Missing
// trees are built on the calling thread (VisibilityStore::getOrBuild). Throws std::out_of_range for
// a face or light number out of range.
std::vector<LightAtPoint> queryPoint(VisibilityStore& store, uint32_t face, const Vec3& x,
                                     std::optional<uint32_t> onlyLight);

// The same answer without history trees: every face of `faces` (a hierarchy over the scene's face
// boxes, EmbreeScene::faceBoxes) that may meet the pyramid from x over the light is clipped from
// x directly (vis::FromPointQuery::runDirect), exact like the tree's walk. No tree is built or
// read, so it costs no precompute: what the viewer shows the moment a point is clicked, while the
// pair's tree is built in the background. `workLimit` bounds each light's query in plane tests
// (0 = none); a light that reaches it has complete = false and incomplete fragments. `groups`,
// when given, must have been built over `faces` (EmbreeScene::faceClusters): the groups of faces
// x sees all from one side enter whole, as in the renderer (the same answer). Throws what
// queryPoint throws.
std::vector<LightAtPoint> queryPointDirect(const Scene& scene, const vis::BoxTree& faces,
                                           uint32_t face, const Vec3& x,
                                           std::optional<uint32_t> onlyLight,
                                           uint64_t workLimit = 0,
                                           const vis::FaceClusters* groups = nullptr);

}  // namespace penumbra
