#include "engine/precompute/point_answer_json.h"

#include <string>
#include <vector>

namespace penumbra {
namespace {

nlohmann::json toJson(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

// Polygons (fragments, or an outline's loops) as arrays of points.
nlohmann::json toJson(const std::vector<vis::Polygon3>& polygons) {
    nlohmann::json out = nlohmann::json::array();
    for (const vis::Polygon3& polygon : polygons) {
        nlohmann::json points = nlohmann::json::array();
        for (const Vec3& v : polygon) points.push_back(toJson(v));
        out.push_back(std::move(points));
    }
    return out;
}

}  // namespace

nlohmann::json lightAnswerJson(const LightAtPoint& l) {
    nlohmann::json j;
    j["light"] = l.light;
    j["light_face"] = l.lightFace;
    j["light_area"] = l.lightArea;
    j["visible_area"] = l.visibleArea;
    j["fraction"] = l.fraction;
    j["form_factor"] = l.formFactor;
    j["unoccluded_form_factor"] = l.unoccludedFormFactor;
    j["fragments"] = toJson(l.fragments);
    j["outline"] = {{"loops", toJson(l.outline.loops)},
                    {"edges", l.outline.edges()},
                    {"form_factor", l.outlineFormFactor}};
    j["nodes_visited"] = l.nodesVisited;
    nlohmann::json path = nlohmann::json::array(), sides = nlohmann::json::array();
    for (const vis::TraceStep& s : l.trace) {
        path.push_back(s.node);
        sides.push_back(vis::toString(s.side));
    }
    j["path"] = std::move(path);
    j["path_sides"] = std::move(sides);
    if (l.answeredOnContact) j["answered_on_contact"] = true;
    j["pair"] = l.fromTree ? nlohmann::json(std::string(vis::toString(l.kind))) : nullptr;
    // The pair's kind says what its shaft holds; a fully-visible pair whose light x's horizon
    // cuts still shows x only the part above it.
    if (l.horizonClipped) j["horizon_clipped"] = true;
    if (l.deferredOccluders > 0) {
        // A partial tree: the budget stopped the build; the query clipped the rest from x.
        j["deferred_occluders"] = l.deferredOccluders;
        j["deferred_clipped"] = l.deferredActive;
    }
    if (l.faceGroups > 0) j["face_groups"] = l.faceGroups;
    if (l.solidGroupsLeftOut > 0) j["solid_groups_left_out"] = l.solidGroupsLeftOut;
    if (l.solidFacesLeftOut > 0) j["solid_faces_left_out"] = l.solidFacesLeftOut;
    if (l.hiddenBySolid) j["hidden_by_solid"] = true;
    if (!l.complete) j["complete"] = false;
    return j;
}

nlohmann::json pointAnswerJson(const Scene& scene, uint32_t face, const Vec3& x,
                               std::span<const LightAtPoint> lights) {
    nlohmann::json out;
    out["point"] = toJson(x);
    out["face"] = face;
    // Face numbers are the repaired mesh's (a split face's triangles, a dropped face's absence):
    // the line of the scene file the face came from, where the format has lines.
    const int32_t line = face < scene.faceSourceLine.size() ? scene.faceSourceLine[face] : 0;
    if (line > 0) out["source_line"] = line;
    // A point behind its face's plane by a rounding is answered from its front side: the point
    // answered, some ulps away; the contact rule is decided at the point given.
    const Vec3 answered = answeredPointOn(scene, face, x).at;
    if (answered != x) out["answered_point"] = toJson(answered);
    nlohmann::json lightsJson = nlohmann::json::array();
    for (const LightAtPoint& l : lights) lightsJson.push_back(lightAnswerJson(l));
    out["lights"] = std::move(lightsJson);
    return out;
}

}  // namespace penumbra
