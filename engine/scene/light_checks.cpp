#include "engine/scene/light_checks.h"

#include <tbb/parallel_for.h>

#include <cstdint>

#include "visibility/face_plane.h"

namespace penumbra {

std::string lightName(const Scene& scene, size_t light) {
    const uint32_t face = scene.lights[light];
    std::string s = "light " + std::to_string(light) + " (face " + std::to_string(face);
    const Material& m = scene.material(face);
    if (!m.name.empty()) s += ", material '" + m.name + "'";
    const int32_t line = face < scene.faceSourceLine.size() ? scene.faceSourceLine[face] : 0;
    if (line > 0) s += ", line " + std::to_string(line);
    return s + ")";
}

std::vector<size_t> lightsFacingAway(const Scene& scene) {
    // The vertices of faces (a file may hold vertices no face uses).
    std::vector<char> used(scene.mesh.vertices.size(), 0);
    for (const auto& face : scene.mesh.faces)
        for (uint32_t v : face) used[v] = 1;
    std::vector<uint32_t> vertices;
    for (uint32_t v = 0; v < used.size(); ++v)
        if (used[v]) vertices.push_back(v);
    std::vector<char> away(scene.lights.size(), 0);
    if (scene.faceCount() <= scene.lights.size()) {
        // Possibly nothing but lights: is there a receiver at all?
        std::vector<char> isLight(scene.faceCount(), 0);
        for (uint32_t f : scene.lights) isLight[f] = 1;
        bool receiver = false;
        for (uint32_t f = 0; f < scene.faceCount() && !receiver; ++f) receiver = !isLight[f];
        if (!receiver) return {};
    }
    tbb::parallel_for(size_t{0}, scene.lights.size(), [&](size_t k) {
        const uint32_t light = scene.lights[k];
        if (scene.mesh.faces[light].size() < 3) return;
        const vis::PlaneOrient plane = vis::facePlane(scene.mesh, light).orient();
        // The light's own vertices lie on its plane (faces are exactly planar): Zero, not front.
        for (uint32_t v : vertices)
            if (plane.sign(scene.mesh.vertices[v]) == vis::Sign::Positive) return;
        away[k] = 1;
    });
    std::vector<size_t> out;
    for (size_t k = 0; k < away.size(); ++k)
        if (away[k]) out.push_back(k);
    return out;
}

std::optional<std::string> lightsFacingAwayWarning(const Scene& scene) {
    const std::vector<size_t> away = lightsFacingAway(scene);
    if (away.empty()) return std::nullopt;
    std::string s = scene.sourcePath + ": ";
    if (away.size() == 1)
        s += lightName(scene, away[0]) + ": its normal points away from every other face";
    else
        s += std::to_string(away.size()) +
             " lights have normals pointing away from every other face, the first " +
             lightName(scene, away[0]);
    return s +
           ": flipped winding? (a light emits only to the side its vertices turn "
           "counter-clockwise, and no face lies there: it lights nothing)";
}

std::string hiddenLightWarning(const Scene& scene, size_t light, size_t backFacing, size_t hidden,
                               std::string_view receivers) {
    const bool isDefault = scene.defaultLight && scene.lights[light] == scene.defaultLight->face;
    return scene.sourcePath + ": " + lightName(scene, light) +
           (isDefault ? ", the default light," : "") + " is hidden from " + std::string(receivers) +
           ": of its " + std::to_string(backFacing + hidden) + " (receiver patch, light) pairs " +
           std::to_string(backFacing) + " are back-facing and " + std::to_string(hidden) +
           " hidden, so it lights nothing" +
           (isDefault ? " (it hangs over the scene and something covers all of it, as a closed "
                        "room's ceiling does: give the scene a light of its own)"
                      : " (enclosed by geometry, or facing only the backs of faces: flipped "
                        "winding?)");
}

}  // namespace penumbra
