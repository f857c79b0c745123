// Shading: the material model and the direct-light estimators of the renderer.
//
// BRDF (scene.h's Material): f(wi, wo) = kd / pi + ks (ns + 2) / (2 pi) max(0, r . wi)^ns with
// r = reflect(wo) about the normal: Lambert plus the energy-normalised Phong lobe.
// Area lights are one-sided Lambertian emitters of radiance ke: a point y on light L sends
// radiance ke towards x when x is strictly in front of L's plane. A receiving point sees only
// its face's open front half-space.
//
// The direct radiance leaving x towards wo from one area light is
//   L(x, wo) = integral over the visible part of L of f(wi, wo) ke cos(theta_x) cos(theta_y) / r^2
//   dA.
// The estimators:
//   exact:   the visible fragments of L from x (FPQuery on the pair's history tree). The diffuse
//            part is kd(x) ke F, F the form factor of the fragments, kd(x) the albedo at x (a
//            texture's value there): closed form, no samples (exact up to floating-point
//            rounding). The glossy part is estimated with stratified
//            area-uniform samples inside the fragments only: no shadow rays, since every point
//            of a fragment is visible (unbiased, noisy only where the lobe varies over them).
//   sampled: stratified area-uniform samples over the whole light, each with one Embree shadow
//            ray (EmbreeScene::occluded, ignoring the receiver and light faces), the full BRDF
//            (unbiased up to the shadow rays' float precision and their 1e-4 end pull-in).
//   point lights: one shadow ray each, I cos(theta_x) / r^2 f (exact up to the float ray).
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <unordered_set>
#include <vector>

#include "engine/precompute/visibility_store.h"
#include "engine/render/answers.h"
#include "engine/render/effects_summary.h"
#include "engine/render/visible_fraction.h"
#include "engine/scene/random.h"
#include "engine/scene/scene.h"
#include "visibility/answered_point.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/light_edge_index.h"
#include "visibility/mesh_edges.h"
#include "visibility/pair_occluders.h"

namespace penumbra {

class EmbreeScene;

inline Vec3 mul(const Vec3& a, const Vec3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

// The Phong lobe's scalar factor (ns + 2) / (2 pi) max(0, r . wi)^ns (times ks gives f_s). n, wo,
// wi unit; wo and wi point away from the surface.
double phongLobe(double ns, const Vec3& n, const Vec3& wo, const Vec3& wi);
// The whole BRDF f(wi, wo) per channel, with diffuse albedo kd (the material's at the point:
// SurfacePoint::kd).
Vec3 brdf(const Material& m, const Vec3& kd, const Vec3& n, const Vec3& wo, const Vec3& wi);

// samples = a * b with a the largest divisor of samples not above its square root: the grid
// of stratified samples (EmbreeScene::sampledFraction uses the same rule).
void stratifiedGrid(int samples, int& a, int& b);

// Area-uniform points on a union of convex polygons, each split into its fan triangles. The unit
// square maps onto the union: u picks a triangle by its share of the area and the sqrt-warped
// distance from its first vertex, v the position across it; equal-area cells of the square map
// to equal-area pieces, so stratification survives.
class TriangleSampler {
  public:
    void clear();
    void addPolygon(std::span<const Vec3> polygon);
    double area() const { return total_; }
    bool empty() const { return tris_.empty(); }
    Vec3 sample(double u, double v) const;

  private:
    struct Tri {
        Vec3 a, b, c;
        double area;
    };
    std::vector<Tri> tris_;
    double total_ = 0;
};

// One area light, prepared once per scene.
struct AreaLight {
    uint32_t face = 0;
    Vec3 ke;
    Vec3 normal;                // unit, towards the front (the side it lights)
    Vec3 origin;                // a vertex, for the approximate plane test of the sampled estimator
    vis::FacePlane plane;       // exact plane test (as FPQuery does it)
    std::vector<Vec3> polygon;  // its vertices
    TriangleSampler sampler;
};

// A shading point: x on face `face` (on its plane), unit front normal n, unit direction wo
// towards the viewer (in n's hemisphere).
struct SurfacePoint {
    uint32_t face = 0;
    // x: the point answered, on the face's closed front side; input: the point it stands for
    // (the projected hit), where the exact queries decide the contact rule (shadingPoint).
    Vec3 x, input, n, wo;
    const Material* material = nullptr;
    // The diffuse albedo at x (Scene::kdAt: material->kd, times its texture there), what every
    // estimator's diffuse term uses.
    Vec3 kd;
    vis::AnsweredPoint answered() const { return {x, input}; }
};

// Whether the renderer answers the points of `record`'s pair without its tree, by the direct
// path with face groups (FromPointQuery::runDirect): a partial tree at least a quarter of whose
// deferred occluders lie in face groups (PairRecord::deferredGrouped). There the tree's walk
// saves little (it holds a few hundred of the pair's occluders, and defers tens to hundreds of
// thousands) while the groups spare activating the deferred faces one by one. Measured, exact
// renders at 128x128, 4 spp, CPU seconds of shading, tree / groups: dragon 34.5 / 12.9, motorbike
// 282 / 111, bunny 1.24 / 1.13; the table's partial trees (leaves: 0% grouped) keep their tree,
// where the groups would cost more (0.67 / 0.82). The same exact answer either way.
bool answeredByGroups(const PairRecord& record);
// The same decision before building the tree, from the pair's shaft: at least minFaces faces
// (a tree's build budget inserts some hundreds of occluders and defers the rest: measured on the
// bunny, motorbike and dragon, every pair with 800 or more candidates came out partial with over
// 95% of them deferred), at least a quarter of them in face groups. Such a pair gets no tree: its
// points take the direct path with the groups, as its partial tree's would (the same exact
// answer), and the precompute is spared (RenderSettings::groupedShaftMin). 0 = never.
bool groupsWillAnswer(const VisibilityStore::ShaftCount& shaft, size_t minFaces);

// A point sampled over the work limit that a tree's walk answers (ExactScratch::overLimitTrees).
struct OverLimitPoint {
    PairKey key;
    Vec3 x;
    uint64_t cell = 0;  // (pixel, light), as ExactScratch::overLimitNow
};

// Per-thread (per-tile) state of the exact estimator: the last tree used per light (neighbouring
// pixels hit the same receiver patch, so most lookups skip the store), the keys the tile needed,
// and scratch for the fragments. For a pair with nothing in its shaft the fragment is the light
// clipped to the receiver's front half-space, whatever x: it is cached per light for the last
// receiver face (the same polygon FPQuery would return, without walking or allocating per point),
// with whether that plane cut anything (horizon-clipped) or left the whole light (fully visible).
struct ExactScratch {
    // The key of the next point's first light (the first that is not its own face), when the
    // caller looked it up already (the renderer groups a tile's points by it): exactAreaLights
    // takes it instead of a second PatchLayout::keyAt.
    std::optional<PairKey> pointKey;
    std::vector<PairKey> lastKey;             // per light
    std::vector<const PairRecord*> lastTree;  // per light (nullptr: none yet)
    std::vector<uint32_t> clippedFace;        // per light: the receiver of clippedLight
    std::vector<vis::Polygon3> clippedLight;  // per light
    // Per light: whether that receiver's plane cut clippedLight from the light (its horizon).
    std::vector<uint8_t> clippedByHorizon;
    std::vector<char> lastDirect;  // per light: lastKey is a direct pair
    std::unordered_set<PairKey, PairKeyHash> used;
    TriangleSampler fragments;
    vis::FromPointQuery query;     // FPQuery workspace: no allocation per point after warm-up
    ExactEvaluations evaluations;  // see exactAreaLights
    // False: a pair the store holds no tree for is evaluated point by point, without a tree
    // (FromPointQuery::runDirect), instead of building one: the renderer's choice once prepare()
    // has built the trees its image samples often enough.
    bool buildMissing = true;
    std::unordered_set<PairKey, PairKeyHash> usedDirect;  // the pairs evaluated that way

    // The region the next points lie in (optional): corners spanning a box that holds them, all on
    // one receiver patch (so one tree per light). FPQuery then skips the plane tests of the nodes
    // that send the whole region one way (vis::RegionDecisions). The caller sets the corners and
    // a new regionId (never 0) for each group of points; empty corners = no region.
    std::vector<Vec3> regionCorners;
    uint64_t regionId = 0;
    std::vector<vis::RegionDecisions> regions;  // per light
    std::vector<uint64_t> regionOf;             // per light: the regionId of its decisions
    // Per light: the regionId in which a tree's walk reached the work limit. The later points of
    // that region (in the caller's order) are sampled without trying: their neighbours' answer is
    // as complex, and the attempt would be wasted work. Not for a pair without a tree, whose
    // neighbouring points differ more (on a finely tessellated mesh each samples other faces of
    // the surface): the pixel rule below suffices there. Measured at 256x256, 16 spp, with the
    // rule on those pairs and without: dragon 44.0% -> 38.1% of the evaluations sampled and 3%
    // less rendering CPU, bunny 14.7% -> 12.9% (2% less), motorbike 61.8% -> 55.4% (the same
    // CPU); on the table's trees it still saves 9%.
    std::vector<uint64_t> regionOverLimit;
    // Across passes: the (pixel, light) cells whose query reached the work limit in an earlier
    // pass of the film (the renderer's, read-only during a pass; null = none), each pixel's
    // index times the light count plus the light's index. The later points of such a pixel are
    // sampled for that light without trying: a jittered sample of the same pixel (on a finely
    // tessellated mesh, mostly another face of the same surface) is as complex, and the attempt
    // would be wasted work. Measured, dragon 256x256, 16 spp: the attempts that reached the limit
    // cost 60 us each, more than the 128 rays that then answer them; this rule made the render 4.6
    // -> 3.1 s wall and sampled 43.7% of the evaluations instead of 39.2%. `pixel` is the index of
    // the pixel of the next point; the cells whose query reached the limit in this pass go to
    // overLimitNow (the renderer adds them after the pass).
    const std::unordered_set<uint64_t>* overLimitBefore = nullptr;
    uint64_t pixel = 0;
    // This pass's answer (answers.h) per (pixel, light) cell, indexed as overLimitNow's cells
    // (kNoAnswer where none); null = not recorded. One byte a cell: a pixel has one point per
    // pass, and it one evaluation per light.
    static constexpr uint8_t kNoAnswer = 0xFF;
    uint8_t* answers = nullptr;
    void note(uint64_t cell, Answer a) {
        if (answers != nullptr) answers[cell] = static_cast<uint8_t>(a);
    }
    // This pass's LightSeen per cell (visible_fraction.h), indexed as `answers` (kNoAnswer where
    // none: not counted); null = not recorded.
    uint8_t* seen = nullptr;
    void noteSeen(uint64_t cell, LightSeen s) {
        if (seen != nullptr) seen[cell] = static_cast<uint8_t>(s);
    }
    std::vector<uint64_t> overLimitNow;
    // The light-edge path, tried where the paths above gave up at the work limit (tried or
    // skipped) before the point is sampled: its own work limit (0 = never tried: sampled at
    // once), and the cells of the film's earlier passes where it reached that limit too, or
    // could not be taken (the renderer's, read-only during a pass; null = none): their later
    // points are sampled without trying it. This pass's such cells go to edgeFailedNow.
    uint64_t lightEdgeWorkLimit = 0;
    const std::unordered_set<uint64_t>* edgeFailedBefore = nullptr;
    std::vector<uint64_t> edgeFailedNow;
    // The same for the cells where the light-edge path declined (it would not pay there, or
    // cannot be taken): their later points take the default path with its limit at once.
    const std::unordered_set<uint64_t>* edgeDeclinedBefore = nullptr;
    std::vector<uint64_t> edgeDeclinedNow;
    // The points sampled over the work limit (tried or skipped) that a tree's walk answers,
    // with the tree's key: where the renderer refines (RenderSettings::refineLevels).
    std::vector<OverLimitPoint> overLimitTrees;
    // Whether to time the next evaluation (EvaluationCosts): one in kTimedEvery, in this
    // scratch's order. Reading the clock twice per evaluation cost the Cornell box's exact render
    // 4.7% of its time (its median evaluation takes 0.17 us); a systematic sample keeps the
    // distribution and spares the hot path.
    static constexpr uint32_t kTimedEvery = EvaluationCosts::kTimedEvery;
    bool timeNext() { return timingTick_++ % kTimedEvery == 0; }

  private:
    uint32_t timingTick_ = 0;
};

class DirectLighting {
  public:
    // scene and bvh must outlive this object; store may be null (then exact() may not be called).
    DirectLighting(const Scene& scene, const EmbreeScene& bvh, VisibilityStore* store);
    ~DirectLighting();
    DirectLighting(const DirectLighting&) = delete;
    DirectLighting& operator=(const DirectLighting&) = delete;

    const std::vector<AreaLight>& areaLights() const { return lights_; }

    // The reflected radiance at p from every area light, by the exact fragments. glossySamples
    // samples per light for the Phong lobe (unused for diffuse materials). A partial tree's
    // deferred occluders are clipped by the query itself. A query that reaches
    // scratch.query's work limit (FromPointQuery::setWorkLimit) has no exact answer there, and
    // neither do the later points of the same region after a tree's walk reached it
    // (ExactScratch::regionOverLimit) and of the same pixel in later passes
    // (ExactScratch::overLimitBefore): those take the light-edge path with its own limit
    // (ExactScratch::lightEdgeWorkLimit; the same exact answer, counted in
    // scratch.evaluations.lightEdges), or where it declines (it would not pay there, or cannot
    // be taken) the default path again with that limit (.retried); where that limit is
    // reached, that light is estimated with `fallbackSamples` stratified shadow rays, counted in
    // scratch.evaluations.sampled (.all counts every point-light pair that needed a query).
    Vec3 exactAreaLights(const SurfacePoint& p, int glossySamples, int fallbackSamples,
                         SplitMix64& rng, ExactScratch& scratch) const;
    // The light-edge index of every light built so far (built on a light's first point that
    // the default path gave up on: lightEdges()), for the effects summary.
    LightEdgeIndexStats lightEdgeStats() const;
    // The lights (indices into the scene's lights) whose light-edge index is built, and the
    // build of one: what the other ranks' shading built is built on rank 0 too, so that its
    // effects summary counts it (the cluster's render).
    std::vector<uint32_t> lightEdgesBuilt() const;
    void buildLightEdges(size_t k) const { lightEdges(k); }
    // The same with `samples` stratified shadow rays per light.
    Vec3 sampledAreaLights(const SurfacePoint& p, int samples, SplitMix64& rng) const;
    // Every point light, one shadow ray each.
    Vec3 pointLights(const SurfacePoint& p) const;

  private:
    // exactAreaLights for the light lights_[k], in steps: the pair's tree (cached per light in
    // scratch), the skip of a cell or region known to be over the work limit, then the answer by
    // the direct path, the fully visible pair's clipped light or the tree's walk; over the limit,
    // shadow rays (overLimit); an exact answer counted by exactDone.
    struct Evaluation;
    Vec3 exactAreaLight(const SurfacePoint& p, size_t k, int glossySamples, int fallbackSamples,
                        SplitMix64& rng, ExactScratch& scratch) const;
    const PairRecord* pairRecord(const PairKey& key, size_t k, ExactScratch& scratch) const;
    bool knownOverLimit(size_t k, uint64_t cell, ExactScratch& scratch) const;
    // The default path gave up on the point (its query reached the work limit: tried; or its
    // region's or pixel's had: not tried): the light-edge path, then shadow rays.
    Vec3 gaveUp(Evaluation& e, bool tried) const;
    // The light-edge path's answer, or nothing where it reached its limit or declined (then the
    // default path is tried again with its limit: gaveUp).
    std::optional<Vec3> lightEdgeAnswer(Evaluation& e) const;
    // A query reached the work limit: the default path gives up (gaveUp), or its retry with the
    // light-edge path's limit did too (the point is sampled).
    Vec3 limitReached(Evaluation& e) const;
    Vec3 overLimit(Evaluation& e, bool tried, vis::WorkStage stage) const;
    // Light k's light-edge index, built once on first use (thread-safe: the first caller builds
    // it, the others wait), with the mesh's edge table before the first one.
    const vis::LightEdgeIndex& lightEdges(size_t k) const;
    void exactDone(Evaluation& e, Answer path, size_t fragments) const;
    // The light clipped to the receiver's front half-space (cached per light for the last
    // receiver face in scratch), with whether the receiver's plane cut it.
    const vis::Polygon3& clippedLight(size_t k, uint32_t face, ExactScratch& scratch) const;
    // What an exact answer's fragments saw of the light (ExactScratch::seen), when recorded.
    void noteSeen(Evaluation& e, const vis::FragmentList& list) const;
    Vec3 directAnswer(Evaluation& e) const;
    Vec3 fullyVisibleAnswer(Evaluation& e) const;
    Vec3 treeWalkAnswer(Evaluation& e) const;
    // Shading from the visible fragments of one light (those of `list`, then `fragments`).
    Vec3 shadeFragments(const SurfacePoint& p, const AreaLight& light,
                        const vis::FragmentList& list, std::span<const vis::Polygon3> fragments,
                        int glossySamples, SplitMix64& rng, ExactScratch& scratch) const;
    Vec3 sampledAreaLight(const AreaLight& light, const SurfacePoint& p, int samples,
                          SplitMix64& rng) const;

    const Scene& scene_;
    const EmbreeScene& bvh_;
    VisibilityStore* store_;
    std::vector<AreaLight> lights_;
    // The light-edge indices, one slot per light (a once flag each: not movable), and the mesh's
    // edge table they are built from (once, by the first light's build).
    struct LightEdgeSlot;
    struct MeshEdgesSlot;
    std::unique_ptr<LightEdgeSlot[]> lightEdges_;
    std::unique_ptr<MeshEdgesSlot> meshEdges_;
};

}  // namespace penumbra
