#include "engine/render/effects_summary.h"

#include <algorithm>
#include <cstdio>
#include <string>

namespace penumbra {
namespace {

std::string plural(size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

// "median M us, 99th percentile P us, mean A us" of a histogram in nanoseconds.
std::string costText(const CostHistogram& ns) {
    char cost[160];
    std::snprintf(cost, sizeof cost, "median %.2f us, 99th percentile %.2f us, mean %.2f us",
                  ns.quantile(0.5) * 1e-3, ns.quantile(0.99) * 1e-3, ns.mean() * 1e-3);
    return cost;
}

}  // namespace

std::string EffectsSummary::text() const {
    std::string s;
    auto line = [&s](const std::string& l) { s += l + "\n"; };
    const bool exact = method == "exact";
    if (method.empty()) {
        line("nothing rendered yet");
    } else if (materialsAnalytic + materialsSampled == 0) {
        line("method: " + method +
             " - but no face was seen from its front (a face seen from "
             "behind is black): move the camera");
    } else if (exact) {
        line(
            "method: exact - the visible fragments of every area light from every shading point "
            "(history trees), no shadow rays");
    } else {
        line("method: " + method + " - " + std::to_string(lightSamples) +
             " stratified shadow rays per area light per shading point");
    }
    if (areaLights == 0)
        line("area lights: none - no soft shadows to compute, no history trees");
    else if (exact)
        line("area lights: " + std::to_string(areaLights) +
             " - one-sided Lambertian emitters, seen through their exactly visible fragments");
    else if (!method.empty())
        line("area lights: " + std::to_string(areaLights) +
             " - one-sided Lambertian emitters, visibility estimated by shadow rays");
    if (pointLights == 0)
        line("point lights: none");
    else
        line("point lights: " + std::to_string(pointLights) +
             " - one shadow ray each (a point light casts hard shadows: no tree needed)");
    if (exact && areaLights > 0 && components > 0) {
        char share[32];
        std::snprintf(share, sizeof share, "%.1f%%",
                      faces > 0 ? 100.0 * static_cast<double>(closedFaces) / faces : 0.0);
        line("mesh components: " + std::to_string(components) + ", " +
             std::to_string(closedComponents) + " of them closed surfaces (" + share +
             " of the faces) - a point whose pyramid holds none of a component's open edges "
             "takes it as a solid and leaves out its faces seen from behind");
    }
    if (exact && areaLights > 0) {
        line("pairs with a tree walked per point (penumbra): " + std::to_string(pairsPenumbra) +
             " - partly blocked, the tree decides per point");
        line("pairs fully visible: " + std::to_string(pairsFullyVisible) +
             " - nothing in the shaft, the whole light (clipped to the horizon), no walk");
        line("pairs fully hidden: " + std::to_string(pairsFullyHidden) +
             " - every line blocked: skipped, no light arrives");
        line("pairs back-facing: " + std::to_string(pairsBackFacing) +
             " - light and receiver face away from each other: skipped");
        if (pairsPartial > 0)
            line("  of them with a partial tree: " + std::to_string(pairsPartial) +
                 " - the build budget stopped the tree, its other " +
                 plural(deferredOccluders, "occluder is", "occluders are") +
                 " clipped from each point (still exact)");
        if (refinedPairs + refineNotWorth > 0) {
            char time[32];
            std::snprintf(time, sizeof time, "%.3f s", refineSeconds);
            line("pairs refined: " + std::to_string(refinedPairs) +
                 " - points of theirs reached the work limit, so their receiver patch was split "
                 "and " +
                 plural(refinedTrees, "sub-patch tree", "sub-patch trees") +
                 " built where those points lie (" + time + ", between passes); " +
                 std::to_string(refinedTreesUsed) +
                 " answered later points (narrower shafts, more occluders in the tree; the same "
                 "exact answer)");
            line("  sub-patches left unrefined: " + std::to_string(refineNotWorth) +
                 " - their tree would cost more to build than sampling their points in the "
                 "passes left (the parent tree's linear programs against those points' shadow "
                 "rays, both counted in rays)");
        }
        if (partialByGroupsEvaluations > 0)
            line("    of their evaluations, " + std::to_string(partialByGroupsEvaluations) +
                 " answered without the tree - at least a quarter of its deferred occluders lie "
                 "in groups of faces seen all from one side, which the direct path takes whole "
                 "(cheaper than clipping them one by one; still exact)");
        if (pairsDirect > 0)
            line("pairs without a tree: " + std::to_string(pairsDirect) + " - seen by fewer than " +
                 std::to_string(minTreeSamples) +
                 " samples, or answered by face groups (below): each point clips the faces in its "
                 "pyramid to the light directly (" +
                 std::to_string(directEvaluations) + " evaluations, exact, no precompute)");
        if (pairsGroupedNoTree > 0)
            line(
                "  of those pairs, " + std::to_string(pairsGroupedNoTree) +
                " seen often enough for a tree but left without one - their shafts hold at least " +
                std::to_string(groupedShaftMin) + " faces (" + std::to_string(groupedNoTreeFaces) +
                " in all), a quarter or more of them in groups of faces seen all from one side: "
                "a tree's build budget would defer nearly all of them, and its points would take "
                "the groups anyway (the same exact answer, no precompute)");
        if (directGroupedEvaluations > 0)
            line("  of those evaluations, " + std::to_string(directGroupedEvaluations) +
                 " took groups of faces seen all from one side whole - their shared edges cancel: "
                 "only each group's boundary enters the boundary chain (still exact)");
        if (directSolidEvaluations + directHiddenBySolidEvaluations > 0)
            line("  of those evaluations, " + std::to_string(directSolidEvaluations) +
                 " left out the faces of closed surfaces (solids) seen from behind, and " +
                 std::to_string(directHiddenBySolidEvaluations) +
                 " lay inside one - a segment that crosses a closed surface crosses it from the "
                 "front, where its boundary is out of the point's pyramid (still exact)");
        line("pairs never seen: " + std::to_string(pairsNeverSeen) +
             " - receivers (patches) no primary ray hit: not computed");
        if (sampledEvaluations > 0) {
            char share[32];
            std::snprintf(share, sizeof share, "%.2f%%", sampledPercent());
            line("points sampled: " + std::to_string(sampledEvaluations) + " of " +
                 std::to_string(exactEvaluations) + " (" + share + ") point-light evaluations, " +
                 std::to_string(sampledDirectEvaluations) +
                 " of them without a tree - their exact answer needed more than " +
                 std::to_string(exactWorkLimit) + " plane tests: " + std::to_string(lightSamples) +
                 " shadow rays each instead (not exact; --exact-work-limit 0 makes every point "
                 "exact)");
            std::string stages;
            for (size_t i = 0; i < overLimitAt.size(); ++i) {
                if (overLimitAt[i] == 0) continue;
                stages += (stages.empty() ? "" : ", ") +
                          std::string(vis::toString(static_cast<vis::WorkStage>(i))) + " " +
                          std::to_string(overLimitAt[i]);
            }
            line("  where they reached the limit: " + (stages.empty() ? "-" : stages) + "; " +
                 std::to_string(notTriedEvaluations()) +
                 " more were points of a region, or of a pixel in a later pass, whose query had "
                 "reached it (not tried)");
        }
        for (size_t path = 0; path < workAt.size(); ++path) {
            uint64_t total = 0;
            for (uint64_t w : workAt[path]) total += w;
            if (total == 0) continue;
            std::string stages;
            for (size_t i = 0; i < vis::kWorkStages; ++i) {
                if (workAt[path][i] == 0) continue;
                char share[32];
                std::snprintf(
                    share, sizeof share, " %.1f%%",
                    100.0 * static_cast<double>(workAt[path][i]) / static_cast<double>(total));
                stages += (stages.empty() ? "" : ", ") +
                          std::string(vis::toString(static_cast<vis::WorkStage>(i))) + share;
            }
            line(std::string(path == 0 ? "work walking trees: " : "work without a tree: ") +
                 std::to_string(total) + " plane tests - " + stages);
        }
        if (costs.exactNs.count() > 0)
            line("cost per exact evaluation: " + costText(costs.exactNs) + " (" +
                 std::to_string(costs.exactNs.count()) +
                 " timed: one in 8 of the evaluations answered exactly, query and shading)");
        if (costs.sampledNs.count() > 0) {
            line("  the sampled ones' shadow rays: " + costText(costs.sampledNs));
            const EvaluationCosts::TimeSplit t = costs.timeSplit();
            char split[240];
            std::snprintf(split, sizeof split,
                          "exact answers %.1f%%, queries stopped at the work limit %.1f%%, the "
                          "sampled points' shadow rays %.1f%% of about %.2f s of CPU",
                          100 * t.exact / t.total(), 100 * t.attempts / t.total(),
                          100 * t.rays / t.total(), t.total());
            line(std::string("  where their time went: ") + split +
                 " (the timed evaluations' sums, times 8: what the work limit's sampling costs "
                 "the exact render)");
        }
        if (costs.chainEvaluations > 0) {
            char per[200];
            std::snprintf(per, sizeof per,
                          "%.1f chain edges (%.1f%% of their occluders' %.1f edges), %.1f cells "
                          "and %.1f fragments",
                          static_cast<double>(costs.chainBoundaryEdges) / costs.chainEvaluations,
                          100.0 * static_cast<double>(costs.chainBoundaryEdges) /
                              static_cast<double>(std::max<uint64_t>(costs.chainOccluderEdges, 1)),
                          static_cast<double>(costs.chainOccluderEdges) / costs.chainEvaluations,
                          static_cast<double>(costs.chainCells) / costs.chainEvaluations,
                          static_cast<double>(costs.chainFragments) / costs.chainEvaluations);
            line("  of them by the boundary chain: " + std::to_string(costs.chainEvaluations) +
                 " - per evaluation " + per +
                 " (the silhouette and border edges that bound the shadow, the cells they cut "
                 "the light into, and the convex pieces of the visible region: the cells are "
                 "the chain's work, the fragments the shading's)");
        }
    }
    if (!exact && costs.sampledNs.count() > 0)
        line("cost per shading point's shadow rays: " + costText(costs.sampledNs) + " (" +
             std::to_string(costs.sampledNs.count()) + " points timed, one in 8, every light)");
    if (!method.empty()) {
        if (materialsAnalytic > 0)
            line("materials analytic: " + plural(materialsAnalytic, "material", "materials") +
                 " - diffuse: kd ke F from the form factor of the exact fragments, no samples, "
                 "no noise");
        if (materialsSampled > 0) {
            if (exact)
                line("materials sampled: " + plural(materialsSampled, "material", "materials") +
                     " - glossy (Phong lobe): " + std::to_string(glossySamples) +
                     " samples per light inside the visible fragments only, diffuse part exact");
            else
                line("materials sampled: " + plural(materialsSampled, "material", "materials") +
                     " - the whole BRDF at each shadow-ray sample");
        }
    }
    return s;
}

}  // namespace penumbra
