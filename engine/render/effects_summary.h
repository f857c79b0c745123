// EffectsSummary: what a scene calls for and what the renderer simulates for it (the third promise
// of the product: simulate only the effects a scene calls for, and say so).
// Filled by the renderer and the precompute, printed by the commands, shown by the viewer.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/render/cost_samples.h"
#include "visibility/fp_query/edge_decline.h"
#include "visibility/fp_query/work_budget.h"

namespace penumbra {

// What the renderer's evaluations cost, summed over threads and passes (ExactEvaluations and
// EffectsSummary hold it alike).
struct EvaluationCosts {
    // One evaluation in kTimedEvery is timed (ExactScratch::timeNext).
    static constexpr uint32_t kTimedEvery = 8;
    // Of one evaluation in kTimedEvery: per evaluation answered exactly, its time
    // in nanoseconds (the query and the shading of its fragments); per sampled one, the time of
    // its shadow rays alone (the exact method's points over the work limit, per light; the
    // sampled method's points, all lights). Their medians and percentiles are exact order
    // statistics of the timed ones (CostSamples: of one in stride() of them past its capacity).
    CostSamples exactNs, sampledNs;
    // Per timed evaluation whose query reached the work limit (the exact method's), the time
    // the query ran before it stopped: spent before the shadow rays, and lost.
    CostSamples attemptNs;
    // The exact evaluations the boundary chain answered (vis::FromPointQuery::ChainCounts: it cut
    // L into cells), their occluders' edges (each use by a face; a face group taken whole counts
    // its boundary only), the chain edges left of them, the cells those cut L into and the
    // fragments they kept (the cells seen), summed. The cells are what the chain's work follows
    // (each is cut, then labelled); the fragments are what shading pays for.
    uint64_t chainEvaluations = 0, chainOccluderEdges = 0, chainBoundaryEdges = 0, chainCells = 0,
             chainFragments = 0;
    // Of the exact evaluations, those the light-edge path answered (vis::FromPointQuery::
    // runLightEdges, after the default path gave up at the work limit): the S_L edges its
    // hierarchy found near x's cone (each one's weight taken), those of nonzero weight, and
    // those of them that meet the cone over L (K: the silhouette and border edges that can bound
    // this point's shadow), summed.
    uint64_t lightEdgeEvaluations = 0, lightEdgesExamined = 0, lightEdgesWeighted = 0,
             lightEdgesInCone = 0;
    // Where the exact method's evaluations that needed a query spent their time, estimated from
    // the timed ones (their sums times kTimedEvery), in CPU seconds: the exact answers, the
    // queries that stopped at the work limit, and the sampled points' shadow rays.
    struct TimeSplit {
        double exact = 0, attempts = 0, rays = 0;
        double total() const { return exact + attempts + rays; }
    };
    TimeSplit timeSplit() const {
        const double scale = kTimedEvery * 1e-9;
        return {exactNs.sum() * scale, attemptNs.sum() * scale, sampledNs.sum() * scale};
    }
    EvaluationCosts& operator+=(const EvaluationCosts& o) {
        exactNs += o.exactNs;
        sampledNs += o.sampledNs;
        attemptNs += o.attemptNs;
        chainEvaluations += o.chainEvaluations;
        chainOccluderEdges += o.chainOccluderEdges;
        chainBoundaryEdges += o.chainBoundaryEdges;
        chainCells += o.chainCells;
        chainFragments += o.chainFragments;
        lightEdgeEvaluations += o.lightEdgeEvaluations;
        lightEdgesExamined += o.lightEdgesExamined;
        lightEdgesWeighted += o.lightEdgesWeighted;
        lightEdgesInCone += o.lightEdgesInCone;
        return *this;
    }
};

// What the light-edge indices cost (DirectLighting::lightEdgeStats): the lights whose index was
// built, the seconds the builds took (the mesh's edge table included), the memory they hold, and
// S_L's edges (summed over those lights) against the mesh's edges (per light).
struct LightEdgeIndexStats {
    size_t lights = 0;
    double seconds = 0;
    size_t bytes = 0;
    size_t silhouetteEdges = 0, meshEdges = 0;
};

// The exact method's (point, light) evaluations that needed a query (counted per renderer
// thread, summed into EffectsSummary): all of them, those over the work limit (sampled instead),
// and those of pairs without a tree (evaluated directly).
struct ExactEvaluations {
    // Every evaluation that needed a query, those sampled (over the work limit), those of pairs
    // without a tree (direct), the sampled ones among them, and the direct ones that took face
    // groups whole (vis::FaceClusters: only their boundaries entered the boundary chain).
    uint64_t all = 0, sampled = 0, direct = 0, sampledDirect = 0, directGrouped = 0;
    // The direct ones that left out faces of closed surfaces seen from behind, and those that
    // such a surface hid whole (x inside it; vis::ClosedSurfaces).
    uint64_t directSolid = 0, directHiddenBySolid = 0;
    // The evaluations of partial trees answered by the direct path with face groups instead of
    // the tree (answeredByGroups, shading.h).
    uint64_t partialByGroups = 0;
    // The evaluations the default path gave up on (over the work limit, tried or skipped) that
    // tried the light-edge path: answered by it (exact), declined (it would not pay there, a
    // face cut by the light's plane may meet x's cone, or x behind its receiver's plane; or it
    // declined the pixel's earlier point), or over its own limit; and those that did not try
    // it, their pixel's earlier attempt (or retry) having spent its limit.
    uint64_t lightEdges = 0, lightEdgesNotTaken = 0, lightEdgesOverLimit = 0, lightEdgesSkipped = 0;
    // Of those it declined at the point itself, why (vis::EdgeDecline), and of those over its
    // limit, the stage its run was in (vis::WorkStage).
    std::array<uint64_t, vis::kEdgeDeclines> lightEdgesDeclinedBy{};
    std::array<uint64_t, vis::kWorkStages> lightEdgesOverLimitAt{};
    // Of those it declined (not taken), the ones that took the default path again with its
    // limit, and those of them that reached that limit too (sampled).
    uint64_t retried = 0, retriedOverLimit = 0;
    // Of the sampled ones, those whose query reached the limit, by the stage it was in
    // (vis::WorkStage); the others were not tried, their region's (or their pixel's, in an
    // earlier pass) query having reached it.
    std::array<uint64_t, vis::kWorkStages> overLimitAt{};
    // The queries' work in plane tests (vis::FromPointQuery::stageWork), by the stage it was
    // spent in: [0] the tree pairs', [1] the direct ones' (those over the limit included).
    std::array<std::array<uint64_t, vis::kWorkStages>, 2> workAt{};
    EvaluationCosts costs;
    ExactEvaluations& operator+=(const ExactEvaluations& o) {
        costs += o.costs;
        all += o.all;
        sampled += o.sampled;
        direct += o.direct;
        sampledDirect += o.sampledDirect;
        directGrouped += o.directGrouped;
        directSolid += o.directSolid;
        directHiddenBySolid += o.directHiddenBySolid;
        partialByGroups += o.partialByGroups;
        lightEdges += o.lightEdges;
        lightEdgesNotTaken += o.lightEdgesNotTaken;
        lightEdgesOverLimit += o.lightEdgesOverLimit;
        lightEdgesSkipped += o.lightEdgesSkipped;
        for (size_t i = 0; i < vis::kEdgeDeclines; ++i)
            lightEdgesDeclinedBy[i] += o.lightEdgesDeclinedBy[i];
        for (size_t i = 0; i < vis::kWorkStages; ++i)
            lightEdgesOverLimitAt[i] += o.lightEdgesOverLimitAt[i];
        retried += o.retried;
        retriedOverLimit += o.retriedOverLimit;
        for (size_t i = 0; i < overLimitAt.size(); ++i) overLimitAt[i] += o.overLimitAt[i];
        for (size_t p = 0; p < workAt.size(); ++p)
            for (size_t i = 0; i < vis::kWorkStages; ++i) workAt[p][i] += o.workAt[p][i];
        return *this;
    }
};

struct EffectsSummary {
    // (receiver patch, light) pairs by what they call for; only penumbra pairs get a tree.
    size_t pairsBackFacing = 0, pairsFullyVisible = 0, pairsFullyHidden = 0, pairsPenumbra = 0;
    size_t pairsNeverSeen = 0;  // pairs of receivers no primary ray hit: not computed
    // Of the penumbra pairs, those with a partial tree (the build budget stopped it: the
    // occluders it left, deferredOccluders in all, are clipped from each shading point, exact).
    size_t pairsPartial = 0, deferredOccluders = 0;
    // Query-driven refinement (RenderSettings::refineLevels): the pairs whose patch was split
    // because points reached the work limit, the sub-patch trees built for them, those the
    // images used (not counted among the pairs above), and the seconds it took.
    size_t refinedPairs = 0, refinedTrees = 0, refinedTreesUsed = 0;
    // Sub-patches with sampled points left without a tree: building it would have cost more
    // than sampling them in the passes left.
    size_t refineNotWorth = 0;
    double refineSeconds = 0;
    // The evaluations of partial trees answered without the tree, by the direct path with face
    // groups (most of their deferred occluders lie in groups: answeredByGroups, shading.h).
    uint64_t partialByGroupsEvaluations = 0;
    // (shading point, light) evaluations of the exact method, and those whose exact answer needed
    // more than exactWorkLimit plane tests: sampled with lightSamples shadow rays (not exact).
    uint64_t exactEvaluations = 0, sampledEvaluations = 0, exactWorkLimit = 0;
    // Of the sampled evaluations, those of pairs without a tree (the others walked a tree).
    uint64_t sampledDirectEvaluations = 0;
    // The evaluations over the work limit that the light-edge path then answered exactly, those
    // it could not take, those over its own limit (lightEdgeWorkLimit; 0 = never tried), and
    // those sampled without trying it (ExactEvaluations); the light-edge indices it built.
    uint64_t lightEdgeEvaluations = 0, lightEdgeNotTaken = 0, lightEdgeOverLimit = 0,
             lightEdgeSkipped = 0, lightEdgeWorkLimit = 0;
    // Of those it could not take, why (indexed by vis::EdgeDecline; the rest were declined by
    // their pixel's earlier point), and of those over its limit, the stage it was in
    // (vis::WorkStage) (ExactEvaluations::lightEdgesDeclinedBy, lightEdgesOverLimitAt).
    std::array<uint64_t, vis::kEdgeDeclines> lightEdgeDeclinedBy{};
    std::array<uint64_t, vis::kWorkStages> lightEdgeOverLimitAt{};
    // Of those it could not take or that would not pay there, the ones that took the default
    // path again with its limit (ExactEvaluations::retried), and those over that limit too.
    uint64_t retriedEvaluations = 0, retriedOverLimit = 0;
    LightEdgeIndexStats lightEdgeIndex;
    // Of the sampled evaluations, those whose query reached the limit, by the stage it was in
    // (the rest were points of a region, or of a pixel in a later pass, whose query had reached
    // it: not tried).
    std::array<uint64_t, vis::kWorkStages> overLimitAt{};
    // The exact queries' work in plane tests by stage: [0] walking trees, [1] without a tree
    // (ExactEvaluations::workAt).
    std::array<std::array<uint64_t, vis::kWorkStages>, 2> workAt{};
    // The cost of each evaluation and the boundary chain's evaluations (ExactEvaluations::costs).
    EvaluationCosts costs;
    // Of the sampled evaluations, those not tried (a point of a region, or of a pixel in a later
    // pass, whose query had reached the limit): the ones no stage of overLimitAt counts.
    uint64_t notTriedEvaluations() const {
        return sampledEvaluations - std::min(triedEvaluations(), sampledEvaluations);
    }
    // Of the sampled evaluations, those whose query reached the limit (every stage of
    // overLimitAt).
    uint64_t triedEvaluations() const {
        uint64_t tried = 0;
        for (uint64_t n : overLimitAt) tried += n;
        return tried;
    }
    // sampledEvaluations as a percentage of exactEvaluations (0 when there were none).
    double sampledPercent() const {
        return exactEvaluations == 0 ? 0.0
                                     : 100.0 * static_cast<double>(sampledEvaluations) /
                                           static_cast<double>(exactEvaluations);
    }
    // Pairs seen by fewer than minTreeSamples primary samples: no tree, each point evaluated
    // directly (exact), and those evaluations.
    size_t pairsDirect = 0;
    uint64_t directEvaluations = 0, minTreeSamples = 0;
    // Of those pairs, the ones seen often enough for a tree but left without one because their
    // shaft holds at least groupedShaftMin faces, a quarter of them in face groups (their partial
    // tree would be answered by the groups: RenderSettings::groupedShaftMin), and the faces in
    // those shafts.
    size_t pairsGroupedNoTree = 0;
    uint64_t groupedNoTreeFaces = 0, groupedShaftMin = 0;
    // Of those evaluations, the ones that took groups of faces seen all one way whole
    // (vis::FaceClusters).
    uint64_t directGroupedEvaluations = 0;
    // Of those evaluations, the ones that left out faces of closed surfaces seen from behind, and
    // the ones such a surface hid whole; the mesh's closed components and their faces
    // (vis::ClosedSurfaces).
    uint64_t directSolidEvaluations = 0, directHiddenBySolidEvaluations = 0;
    size_t closedComponents = 0, components = 0, closedFaces = 0, faces = 0;
    // Materials of the receivers by how they are shaded.
    size_t materialsAnalytic = 0;  // diffuse: form factor of the exact fragments, no samples
    size_t materialsSampled = 0;   // glossy: samples inside the visible fragments only
    size_t areaLights = 0;
    bool defaultLight = false;  // the one area light is the default light (Scene::defaultLight)
    // The exact method's lights none of whose pairs the image used is lit (each back-facing or
    // hidden, some hidden; a pair without a tree counts as lit: its kind is not known): one
    // warning each
    // (engine/scene/light_checks.h), which `render` also prints on stderr.
    std::vector<std::string> hiddenLights;
    size_t pointLights = 0;  // one shadow ray each
    // How the area lights were shaded: "exact", "sampled" or "reference" (empty: nothing
    // rendered yet), with the sample counts that apply.
    std::string method;
    int lightSamples = 0;   // sampled / reference: shadow rays per light per shading point
    int glossySamples = 0;  // exact: samples per light inside the fragments, glossy materials
    // Multi-line human-readable text (what, how many, why).
    std::string text() const;
};

}  // namespace penumbra
