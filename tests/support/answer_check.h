// The fuzz harnesses' contract for a scene that loads (tests/fuzz/fuzz_scene.cpp), shared with the
// regression test that replays their findings (tests/engine/fuzz_regressions_test.cpp): every
// vertex inside the coordinate contract, and the first pair's exact answer sound. The history tree
// of (face 0 or 1, the first light) is built with a small budget and the from-point query at the
// receiver's centroid must give fragments of finite, non-negative total area no larger than the
// light's, up to the rounding of their constructed vertices: 16 u W per fragment
// (engine/scene/scene_validation.h: W, and the rule that refuses lights too thin for it, which the
// first light must also keep).
#pragma once

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "engine/scene/scene.h"
#include "engine/scene/scene_validation.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"

namespace penumbra::test {

inline std::optional<std::string> answerProblem(const Scene& scene) {
    for (const Vec3& v : scene.mesh.vertices)
        if (coordinateProblem(v)) return "a loaded vertex breaks the coordinate contract";
    if (scene.lights.empty() || scene.faceCount() < 2 || scene.faceCount() > 64) return {};
    const uint32_t light = scene.lights[0];
    // Below that area the fraction would be noise (the allowance below exceeds the light).
    if (const auto thin = lightAreaProblem(scene.mesh, light, scene.mesh.bounds().diagonal()))
        return "a loaded light breaks the light-area rule: " + *thin;
    const uint32_t receiver = light == 0 ? 1 : 0;
    vis::BuildOptions options;
    options.maxLpSolves = 200;
    const vis::HistoryTree tree = vis::buildHistoryTree(scene.mesh, receiver, light, options);
    Vec3 x{};
    for (uint32_t v : scene.mesh.faces[receiver]) x += scene.mesh.vertices[v];
    x = x / static_cast<double>(scene.mesh.faces[receiver].size());
    vis::FromPointQuery query;
    const vis::FragmentList& fragments = query.run(scene.mesh, tree, x);
    double area = 0;
    for (size_t i = 0; i < fragments.size(); ++i) area += vis::polygonArea(fragments[i]);
    const double lightArea = scene.mesh.faceArea(light);
    const double rounding =
        16 * 0x1p-53 * lightResolutionWeight(scene.mesh, light, scene.mesh.bounds().diagonal()) *
        static_cast<double>(fragments.size() + 1);
    if (!std::isfinite(area) || area < 0 || area > lightArea + rounding) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "visible area %.17g of a light of area %.17g (rounding allowance %.3g)", area,
                      lightArea, rounding);
        return std::string(buf);
    }
    return {};
}

}  // namespace penumbra::test
