// A point's answer as JSON: the one schema of `penumbra query` (one object per point, one line
// each, on stdout), the viewer's state (--state-out: the inspected point, the pixel under the
// mouse) and whatever else prints an answer. Keys are snake_case; doubles are printed in their
// shortest round-trip form; keys are sorted (nlohmann::json).
//
//   {"point":[x,y,z], "face":F, "source_line":N, "answered_point":[x,y,z], "lights":[L, ...]}
//   L = {"light":K, "light_face":LF, "light_area":A, "visible_area":a, "fraction":a/A,
//        "form_factor":f, "unoccluded_form_factor":u, "fragments":[[[x,y,z],...],...],
//        "outline":{"loops":[[[x,y,z],...],...], "edges":e, "form_factor":f'},
//        "nodes_visited":n, "path":[node ids], "path_sides":["+"|"-"|"both"|"in plane (+)", ...],
//        "pair":"penumbra|fully-visible|fully-hidden|back-facing"}
//
// "source_line": the line of the scene file the face came from, where the format has lines (face
// numbers are the repaired mesh's: docs/formats.md). "answered_point": the point answered when it
// is not the one given (a point a rounding behind its face's plane is answered from its front
// side, some ulps away: answeredPointOn). "outline" is the visible region's boundary, the
// fragments' union (vis::visibleOutline), and the form factor integrated over it (Lambert's
// contour integral: f to within the outline's weld, about 2^-40 of the region's extent).
// Keys that say the answer took an unusual path appear only when it did:
//   "answered_on_contact": true     x on a contact line: the contact rule answered, no walk
//   "horizon_clipped": true         x's horizon (its face's plane) cuts the light: a point of a
//                                   "fully-visible" pair (nothing in the shaft) sees the part
//                                   above it, fraction < 1
//   "deferred_occluders": n, "deferred_clipped": m   a partial tree (its build stopped at the
//                                   budget): the occluders it left, those this point's query
//                                   clipped; the answer is exact all the same
//   "pair": null                    answered without a history tree (queryPointDirect: no kind,
//                                   no path), with "face_groups" (the face groups taken whole),
//                                   "solid_groups_left_out" / "solid_faces_left_out" (the back
//                                   of a closed surface) and "hidden_by_solid": true where nonzero
//   "complete": false               a direct answer stopped by its work limit: the fragments are
//                                   incomplete (never in `query`, which has no limit)
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>

#include "engine/precompute/point_query.h"
#include "engine/scene/scene.h"

namespace penumbra {

// One light's answer (L above).
nlohmann::json lightAnswerJson(const LightAtPoint& light);

// The answer at x on `face` of `scene`: its lights as queryPoint or queryPointDirect gave them.
nlohmann::json pointAnswerJson(const Scene& scene, uint32_t face, const Vec3& x,
                               std::span<const LightAtPoint> lights);

}  // namespace penumbra
