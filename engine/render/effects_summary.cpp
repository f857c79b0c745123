#include "engine/render/effects_summary.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "engine/scene/default_light.h"

namespace penumbra {
namespace effects_text {

std::string plural(size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
}

// "median M us, 99th percentile P us, mean A us" of costs in nanoseconds (nearest rank; the
// subsample says so where the costs kept are one in n of those timed).
std::string costText(const CostSamples& ns) {
    const Quantiles q = ns.quantiles();
    char cost[200];
    std::snprintf(cost, sizeof cost, "median %.2f us, 99th percentile %.2f us, mean %.2f us",
                  q.median * 1e-3, q.p99 * 1e-3, ns.mean() * 1e-3);
    if (ns.stride() > 1)
        return cost + (" (median and percentile of one in " + std::to_string(ns.stride()) +
                       " of those timed)");
    return cost;
}

// The text, one line at a time.
class Lines {
  public:
    void add(const std::string& l) { text_ += l + "\n"; }
    std::string take() { return std::move(text_); }

  private:
    std::string text_;
};

// How the area lights were shaded, and the lights.
void methodAndLights(const EffectsSummary& e, Lines& out) {
    const bool exact = e.method == "exact";
    if (e.method.empty()) {
        out.add("nothing rendered yet");
    } else if (e.materialsAnalytic + e.materialsSampled == 0) {
        out.add("method: " + e.method +
                " - but no face was seen from its front (a face seen from "
                "behind is black): move the camera");
    } else if (exact) {
        out.add(
            "method: exact - the visible fragments of every area light from every shading point "
            "(history trees), no shadow rays");
    } else {
        out.add("method: " + e.method + " - " + std::to_string(e.lightSamples) +
                " stratified shadow rays per area light per shading point");
    }
    const std::string lights =
        "area lights: " + std::to_string(e.areaLights) +
        (e.defaultLight ? " (" + std::string(kDefaultLightNote) + ")" : std::string());
    if (e.areaLights == 0)
        out.add("area lights: none - no soft shadows to compute, no history trees");
    else if (exact)
        out.add(lights +
                " - one-sided Lambertian emitters, seen through their exactly visible fragments");
    else if (!e.method.empty())
        out.add(lights + " - one-sided Lambertian emitters, visibility estimated by shadow rays");
    else if (e.defaultLight)
        out.add(lights);
    for (const std::string& w : e.hiddenLights) out.add("  warning: " + w);
    if (e.pointLights == 0)
        out.add("point lights: none");
    else
        out.add("point lights: " + std::to_string(e.pointLights) +
                " - one shadow ray each (a point light casts hard shadows: no tree needed)");
}

// The mesh's components and its closed surfaces (the exact method's solids).
void components(const EffectsSummary& e, Lines& out) {
    char share[32];
    std::snprintf(share, sizeof share, "%.1f%%",
                  e.faces > 0 ? 100.0 * static_cast<double>(e.closedFaces) / e.faces : 0.0);
    out.add("mesh components: " + std::to_string(e.components) + ", " +
            std::to_string(e.closedComponents) + " of them closed surfaces (" + share +
            " of the faces) - a point whose pyramid holds none of a component's open edges "
            "takes it as a solid and leaves out its faces seen from behind");
}

// The pairs by kind, the partial trees among them and the refinement.
void treePairs(const EffectsSummary& e, Lines& out) {
    out.add("pairs with a tree walked per point (penumbra): " + std::to_string(e.pairsPenumbra) +
            " - partly blocked, the tree decides per point");
    out.add("pairs unoccluded: " + std::to_string(e.pairsFullyVisible) +
            " - nothing in the shaft: the whole light, or the part above the receiver's plane "
            "where that plane cuts it (horizon-clipped), no walk");
    out.add("pairs fully hidden: " + std::to_string(e.pairsFullyHidden) +
            " - every line blocked: skipped, no light arrives");
    out.add("pairs back-facing: " + std::to_string(e.pairsBackFacing) +
            " - light and receiver face away from each other: skipped");
    if (e.pairsPartial > 0)
        out.add("  of them with a partial tree: " + std::to_string(e.pairsPartial) +
                " - the build budget stopped the tree, its other " +
                plural(e.deferredOccluders, "occluder is", "occluders are") +
                " clipped from each point (still exact)");
    if (e.refinedPairs + e.refineNotWorth > 0) {
        char time[32];
        std::snprintf(time, sizeof time, "%.3f s", e.refineSeconds);
        out.add("pairs refined: " + std::to_string(e.refinedPairs) +
                " - points of theirs reached the work limit, so their receiver patch was split "
                "and " +
                plural(e.refinedTrees, "sub-patch tree", "sub-patch trees") +
                " built where those points lie (" + time + ", between passes); " +
                std::to_string(e.refinedTreesUsed) +
                " answered later points (narrower shafts, more occluders in the tree; the same "
                "exact answer)");
        out.add("  sub-patches left unrefined: " + std::to_string(e.refineNotWorth) +
                " - their tree would cost more to build than sampling their points in the "
                "passes left (the parent tree's linear programs against those points' shadow "
                "rays, both counted in rays)");
    }
    if (e.partialByGroupsEvaluations > 0)
        out.add("    of their evaluations, " + std::to_string(e.partialByGroupsEvaluations) +
                " answered without the tree - at least a quarter of its deferred occluders lie "
                "in groups of faces seen all from one side, which the direct path takes whole "
                "(cheaper than clipping them one by one; still exact)");
}

// The pairs without a tree and how their evaluations went.
void directPairs(const EffectsSummary& e, Lines& out) {
    if (e.pairsDirect > 0)
        out.add("pairs without a tree: " + std::to_string(e.pairsDirect) +
                " - seen by fewer than " + std::to_string(e.minTreeSamples) +
                " samples, or answered by face groups (below): each point clips the faces in its "
                "pyramid to the light directly (" +
                std::to_string(e.directEvaluations) + " evaluations, exact, no precompute)");
    if (e.pairsGroupedNoTree > 0)
        out.add("  of those pairs, " + std::to_string(e.pairsGroupedNoTree) +
                " seen often enough for a tree but left without one - their shafts hold at least " +
                std::to_string(e.groupedShaftMin) + " faces (" +
                std::to_string(e.groupedNoTreeFaces) +
                " in all), a quarter or more of them in groups of faces seen all from one side: "
                "a tree's build budget would defer nearly all of them, and its points would take "
                "the groups anyway (the same exact answer, no precompute)");
    if (e.directGroupedEvaluations > 0)
        out.add("  of those evaluations, " + std::to_string(e.directGroupedEvaluations) +
                " took groups of faces seen all from one side whole - their shared edges cancel: "
                "only each group's boundary enters the boundary chain (still exact)");
    if (e.directSolidEvaluations + e.directHiddenBySolidEvaluations > 0)
        out.add("  of those evaluations, " + std::to_string(e.directSolidEvaluations) +
                " left out the faces of closed surfaces (solids) seen from behind, and " +
                std::to_string(e.directHiddenBySolidEvaluations) +
                " lay inside one - a segment that crosses a closed surface crosses it from the "
                "front, where its boundary is out of the point's pyramid (still exact)");
}

// The points over the work limit, sampled instead, and where they reached it.
void sampledPoints(const EffectsSummary& e, Lines& out) {
    char share[32];
    std::snprintf(share, sizeof share, "%.2f%%", e.sampledPercent());
    out.add("points sampled: " + std::to_string(e.sampledEvaluations) + " of " +
            std::to_string(e.exactEvaluations) + " (" + share + ") point-light evaluations, " +
            std::to_string(e.sampledDirectEvaluations) +
            " of them without a tree - their exact answer needed more than " +
            std::to_string(e.exactWorkLimit) + " plane tests" +
            (e.lightEdgeWorkLimit != 0
                 ? ", and the light-edge path's more than " + std::to_string(e.lightEdgeWorkLimit) +
                       " or could not be taken"
                 : std::string()) +
            ": " + std::to_string(e.lightSamples) +
            " shadow rays each instead (not exact; --exact-work-limit 0 makes every point "
            "exact)");
    std::string stages;
    for (size_t i = 0; i < e.overLimitAt.size(); ++i) {
        if (e.overLimitAt[i] == 0) continue;
        stages += (stages.empty() ? "" : ", ") +
                  std::string(vis::toString(static_cast<vis::WorkStage>(i))) + " " +
                  std::to_string(e.overLimitAt[i]);
    }
    out.add("  where they reached the limit: " + (stages.empty() ? "-" : stages) + "; " +
            std::to_string(e.notTriedEvaluations()) +
            " more were points of a region, or of a pixel in a later pass, whose query had "
            "reached it (not tried)");
}

// The points the default path gave up on at the work limit that the light-edge path then
// answered, those it could not, and what its indices cost.
void lightEdgePoints(const EffectsSummary& e, Lines& out) {
    const uint64_t tried = e.lightEdgeEvaluations + e.lightEdgeNotTaken + e.lightEdgeOverLimit;
    char share[32];
    std::snprintf(share, sizeof share, "%.2f%%",
                  e.exactEvaluations == 0 ? 0.0
                                          : 100.0 * static_cast<double>(e.lightEdgeEvaluations) /
                                                static_cast<double>(e.exactEvaluations));
    out.add("light-edge path: " + std::to_string(e.lightEdgeEvaluations) + " of " +
            std::to_string(e.exactEvaluations) + " (" + share +
            ") point-light evaluations, over the work limit on the other paths, answered "
            "exactly from the light's silhouette edges near the point (--light-edge-work-limit " +
            std::to_string(e.lightEdgeWorkLimit) + " plane tests of its own); of the " +
            std::to_string(tried) + " tried, " + std::to_string(e.lightEdgeOverLimit) +
            " reached its limit and " + std::to_string(e.lightEdgeNotTaken) +
            " declined it (their edges near the cone hardly cancel, or a face cut by the "
            "light's plane meets the cone): " +
            std::to_string(e.retriedEvaluations - e.retriedOverLimit) +
            " of those answered exactly by the other paths again with its limit, " +
            std::to_string(e.retriedOverLimit) + " over it too; " +
            std::to_string(e.lightEdgeSkipped) +
            " more were sampled without trying (their pixel's attempt had failed)");
    // Why: each decline's reason, and the stage each run over its limit was in.
    std::string why;
    for (size_t i = 1; i < vis::kEdgeDeclines; ++i) {
        if (e.lightEdgeDeclinedBy[i] == 0) continue;
        why += (why.empty() ? "" : ", ") +
               std::string(vis::toString(static_cast<vis::EdgeDecline>(i))) + " " +
               std::to_string(e.lightEdgeDeclinedBy[i]);
    }
    if (!why.empty()) out.add("  declined where: " + why);
    std::string stages;
    for (size_t i = 0; i < vis::kWorkStages; ++i) {
        if (e.lightEdgeOverLimitAt[i] == 0) continue;
        stages += (stages.empty() ? "" : ", ") +
                  std::string(vis::toString(static_cast<vis::WorkStage>(i))) + " " +
                  std::to_string(e.lightEdgeOverLimitAt[i]);
    }
    if (!stages.empty()) out.add("  where it reached its limit: " + stages);
    const LightEdgeIndexStats& index = e.lightEdgeIndex;
    if (index.lights == 0) return;
    char cost[200];
    std::snprintf(cost, sizeof cost,
                  "%zu light%s, %.3f s to build (the mesh's edge table included), %.1f MB, S_L "
                  "%.1f%% of the mesh's %zu edges",
                  index.lights, index.lights == 1 ? "" : "s", index.seconds,
                  static_cast<double>(index.bytes) / 1e6,
                  100.0 * static_cast<double>(index.silhouetteEdges) /
                      static_cast<double>(std::max<size_t>(index.meshEdges * index.lights, 1)),
                  index.meshEdges);
    out.add(std::string("  its indices (built once per light, on first use): ") + cost);
}

// The queries' plane tests by stage, walking trees and without a tree.
void work(const EffectsSummary& e, Lines& out) {
    for (size_t path = 0; path < e.workAt.size(); ++path) {
        uint64_t total = 0;
        for (uint64_t w : e.workAt[path]) total += w;
        if (total == 0) continue;
        std::string stages;
        for (size_t i = 0; i < vis::kWorkStages; ++i) {
            if (e.workAt[path][i] == 0) continue;
            char share[32];
            std::snprintf(
                share, sizeof share, " %.1f%%",
                100.0 * static_cast<double>(e.workAt[path][i]) / static_cast<double>(total));
            stages += (stages.empty() ? "" : ", ") +
                      std::string(vis::toString(static_cast<vis::WorkStage>(i))) + share;
        }
        out.add(std::string(path == 0 ? "work walking trees: " : "work without a tree: ") +
                std::to_string(total) + " plane tests - " + stages);
    }
}

// What the exact method's evaluations cost, where the time went, and the boundary chain's share.
void exactCosts(const EvaluationCosts& costs, Lines& out) {
    if (costs.exactNs.count() > 0)
        out.add("cost per exact evaluation: " + costText(costs.exactNs) + " (" +
                std::to_string(costs.exactNs.count()) +
                " timed: one in 8 of the evaluations answered exactly, query and shading)");
    if (costs.sampledNs.count() > 0) {
        out.add("  the sampled ones' shadow rays: " + costText(costs.sampledNs));
        const EvaluationCosts::TimeSplit t = costs.timeSplit();
        char split[240];
        std::snprintf(split, sizeof split,
                      "exact answers %.1f%%, queries stopped at the work limit %.1f%%, the "
                      "sampled points' shadow rays %.1f%% of about %.2f s of CPU",
                      100 * t.exact / t.total(), 100 * t.attempts / t.total(),
                      100 * t.rays / t.total(), t.total());
        out.add(std::string("  where their time went: ") + split +
                " (the timed evaluations' sums, times 8: what the work limit's sampling costs "
                "the exact render)");
    }
    if (costs.lightEdgeEvaluations > 0) {
        const double n = static_cast<double>(costs.lightEdgeEvaluations);
        char per[300];
        std::snprintf(per, sizeof per,
                      "%.1f light silhouette edges examined (their weights taken; those of "
                      "the subtrees seen wholly from one side skipped), %.1f of nonzero weight, "
                      "%.1f of them in the cone (K)",
                      static_cast<double>(costs.lightEdgesExamined) / n,
                      static_cast<double>(costs.lightEdgesWeighted) / n,
                      static_cast<double>(costs.lightEdgesInCone) / n);
        out.add("  of them by the light-edge path: " + std::to_string(costs.lightEdgeEvaluations) +
                " - per evaluation " + per +
                " (no face activated: its work follows the edges examined, not the faces in "
                "the cone)");
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
        out.add("  of them by the boundary chain: " + std::to_string(costs.chainEvaluations) +
                " - per evaluation " + per +
                " (the silhouette and border edges that bound the shadow, the cells they cut "
                "the light into, and the convex pieces of the visible region: the cells are "
                "the chain's work, the fragments the shading's)");
    }
}

// The receivers' materials by how they were shaded.
void materials(const EffectsSummary& e, Lines& out) {
    if (e.materialsAnalytic > 0)
        out.add("materials analytic: " + plural(e.materialsAnalytic, "material", "materials") +
                " - diffuse: kd(x) ke F from the form factor of the exact fragments, no samples, "
                "no noise");
    if (e.materialsSampled > 0) {
        if (e.method == "exact")
            out.add("materials sampled: " + plural(e.materialsSampled, "material", "materials") +
                    " - glossy (Phong lobe): " + std::to_string(e.glossySamples) +
                    " samples per light inside the visible fragments only, diffuse part exact");
        else
            out.add("materials sampled: " + plural(e.materialsSampled, "material", "materials") +
                    " - the whole BRDF at each shadow-ray sample");
    }
}

}  // namespace effects_text

std::string EffectsSummary::text() const {
    using namespace effects_text;
    Lines out;
    const bool exact = method == "exact";
    methodAndLights(*this, out);
    if (exact && areaLights > 0) {
        if (components > 0) effects_text::components(*this, out);
        treePairs(*this, out);
        directPairs(*this, out);
        out.add("pairs never seen: " + std::to_string(pairsNeverSeen) +
                " - receivers (patches) no primary ray hit: not computed");
        if (lightEdgeEvaluations + lightEdgeNotTaken + lightEdgeOverLimit + lightEdgeSkipped > 0)
            lightEdgePoints(*this, out);
        if (sampledEvaluations > 0) sampledPoints(*this, out);
        work(*this, out);
        exactCosts(costs, out);
    }
    if (!exact && costs.sampledNs.count() > 0)
        out.add("cost per shading point's shadow rays: " + costText(costs.sampledNs) + " (" +
                std::to_string(costs.sampledNs.count()) + " points timed, one in 8, every light)");
    if (!method.empty()) effects_text::materials(*this, out);
    return out.take();
}

}  // namespace penumbra
