#include "engine/render/shading.h"

#include <oneapi/tbb/collaborative_call_once.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>

#include "engine/raytrace/embree_scene.h"
#include "engine/render/shading_point.h"
#include "engine/scene/tbb_loops.h"
#include "visibility/face_plane.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/polygon_clip.h"

namespace penumbra {

double phongLobe(double ns, const Vec3& n, const Vec3& wo, const Vec3& wi) {
    const Vec3 r = 2 * dot(n, wo) * n - wo;  // mirror direction of wo
    const double c = dot(r, wi);
    if (!(c > 0)) return 0;
    return (ns + 2) / (2 * std::numbers::pi) * std::pow(c, ns);
}

Vec3 brdf(const Material& m, const Vec3& kd, const Vec3& n, const Vec3& wo, const Vec3& wi) {
    Vec3 f = kd * (1 / std::numbers::pi);
    if (m.isGlossy()) f += m.ks * phongLobe(m.ns, n, wo, wi);
    return f;
}

void stratifiedGrid(int samples, int& a, int& b) {
    a = static_cast<int>(std::sqrt(static_cast<double>(samples)));
    while (a > 1 && a * a > samples) --a;  // guard sqrt rounding
    while ((a + 1) * (a + 1) <= samples) ++a;
    while (a > 1 && samples % a != 0) --a;
    a = std::max(a, 1);
    b = samples / a;
}

void TriangleSampler::clear() {
    tris_.clear();
    total_ = 0;
}

void TriangleSampler::addPolygon(std::span<const Vec3> polygon) {
    for (size_t i = 1; i + 1 < polygon.size(); ++i) {
        const Vec3 a = polygon[0], b = polygon[i], c = polygon[i + 1];
        const double area = 0.5 * length(cross(b - a, c - a));
        if (!(area > 0)) continue;
        tris_.push_back({a, b, c, area});
        total_ += area;
    }
}

Vec3 TriangleSampler::sample(double u, double v) const {
    double target = u * total_;
    size_t t = 0;
    while (t + 1 < tris_.size() && target >= tris_[t].area) {
        target -= tris_[t].area;
        ++t;
    }
    const Tri& tri = tris_[t];
    const double s = std::sqrt(std::clamp(target / tri.area, 0.0, 1.0));
    return tri.a + (tri.b - tri.a) * (s * (1 - v)) + (tri.c - tri.a) * (s * v);
}

namespace {
using Clock = std::chrono::steady_clock;
// answeredByGroups' share: at least one in kGroupedShare of the faces in groups.
constexpr size_t kGroupedShare = 4;
}  // namespace

bool answeredByGroups(const PairRecord& record) {
    const vis::HistoryTree& tree = record.tree;
    return tree.kind == vis::PairKind::Penumbra && tree.partial() &&
           kGroupedShare * record.deferredGrouped >= tree.deferred.size();
}

bool groupsWillAnswer(const VisibilityStore::ShaftCount& shaft, size_t minFaces) {
    return minFaces > 0 && shaft.faces >= minFaces && shaft.grouped > 0 &&
           kGroupedShare * shaft.grouped >= shaft.faces;
}

// One light's light-edge index, built on first use (DirectLighting::lightEdges); `built` is set
// (release) once it is, for lightEdgeStats to read it from another thread.
//
// Built in parallel (tbbLoops) under a collaborative once flag: the threads that need the index
// while it is built join its loops instead of waiting idle.
struct DirectLighting::LightEdgeSlot {
    tbb::collaborative_once_flag once;
    vis::LightEdgeIndex index;
    double seconds = 0;
    std::atomic<bool> built{false};
};

struct DirectLighting::MeshEdgesSlot {
    tbb::collaborative_once_flag once;
    vis::MeshEdges edges;
    double seconds = 0;
};

DirectLighting::~DirectLighting() = default;

DirectLighting::DirectLighting(const Scene& scene, const EmbreeScene& bvh, VisibilityStore* store)
    : scene_(scene),
      bvh_(bvh),
      store_(store),
      lightEdges_(std::make_unique<LightEdgeSlot[]>(scene.lights.size())),
      meshEdges_(std::make_unique<MeshEdgesSlot>()) {
    for (uint32_t face : scene.lights) {
        AreaLight light;
        light.face = face;
        light.ke = scene.material(face).ke;
        light.normal = normalize(scene.mesh.faceAreaNormal(face));
        light.origin = scene.mesh.vertices[scene.mesh.faces[face][0]];
        light.plane = vis::facePlane(scene.mesh, face);
        for (uint32_t v : scene.mesh.faces[face]) light.polygon.push_back(scene.mesh.vertices[v]);
        light.sampler.addPolygon(light.polygon);
        lights_.push_back(std::move(light));
    }
}

// One (point, light) evaluation of exactAreaLights: what its steps share.
struct DirectLighting::Evaluation {
    const SurfacePoint& p;
    size_t k;  // the light's index
    const AreaLight& light;
    PairKey key;
    const PairRecord* record;  // null: the pair has no tree (evaluated directly)
    uint64_t cell;             // this pixel's cell for this light (ExactScratch::overLimitBefore)
    // Timed (ExactScratch::timeNext; only the evaluations that need a query), since evalStart.
    bool timed;
    Clock::time_point evalStart;
    int glossySamples, fallbackSamples;
    SplitMix64& rng;
    ExactScratch& scratch;
    // The default path again, with the light-edge path's limit, after that path declined
    // (DirectLighting::gaveUp): its stage when it first gave up, if it ran.
    bool retry = false, tried = false;
    vis::WorkStage firstStage = vis::WorkStage::Walk;
};

namespace {

// The query's work by stage, on the tree pairs' (0) or the direct ones' (1) account.
void countWork(ExactScratch& scratch, size_t path) {
    const auto& work = scratch.query.stageWork();
    for (size_t i = 0; i < work.size(); ++i) scratch.evaluations.workAt[path][i] += work[i];
}

}  // namespace

Vec3 DirectLighting::exactAreaLights(const SurfacePoint& p, int glossySamples, int fallbackSamples,
                                     SplitMix64& rng, ExactScratch& scratch) const {
    if (scratch.lastTree.size() != lights_.size()) {
        scratch.lastKey.assign(lights_.size(), PairKey{});
        scratch.lastTree.assign(lights_.size(), nullptr);
        scratch.clippedFace.assign(lights_.size(), EmbreeScene::kNoFace);
        scratch.lastDirect.assign(lights_.size(), 0);
        scratch.clippedLight.assign(lights_.size(), vis::Polygon3{});
        scratch.clippedByHorizon.assign(lights_.size(), 0);
    }
    // Starting from +0, adding the +0 of a light that gives nothing changes no bit.
    Vec3 out{};
    for (size_t k = 0; k < lights_.size(); ++k) {
        if (lights_[k].face == p.face) continue;  // a light does not light itself
        out += exactAreaLight(p, k, glossySamples, fallbackSamples, rng, scratch);
    }
    return out;
}

Vec3 DirectLighting::exactAreaLight(const SurfacePoint& p, size_t k, int glossySamples,
                                    int fallbackSamples, SplitMix64& rng,
                                    ExactScratch& scratch) const {
    const AreaLight& light = lights_[k];
    const PairKey key = scratch.pointKey && scratch.pointKey->receiver == p.face &&
                                scratch.pointKey->lightFace == light.face
                            ? *scratch.pointKey
                            : store_->layout().keyAt(p.face, p.x, light.face);
    const PairRecord* record = pairRecord(key, k, scratch);
    // The evaluations that need a query: a pair without a tree, or a tree to walk.
    const bool queried = record == nullptr || record->tree.kind == vis::PairKind::Penumbra;
    if (queried) {
        ++scratch.evaluations.all;
        if (record == nullptr) ++scratch.evaluations.direct;
    }
    const uint64_t cell = scratch.pixel * lights_.size() + k;
    const bool timed = queried && scratch.timeNext();
    Evaluation e{p,
                 k,
                 light,
                 key,
                 record,
                 cell,
                 timed,
                 timed ? Clock::now() : Clock::time_point{},
                 glossySamples,
                 fallbackSamples,
                 rng,
                 scratch};
    if (queried && knownOverLimit(k, cell, scratch)) return gaveUp(e, false);
    // A partial tree whose deferred occluders lie mostly in face groups: its points are
    // answered without it (the same exact answer; see answeredByGroups).
    if (record == nullptr || answeredByGroups(*record)) return directAnswer(e);
    const vis::PairKind kind = record->tree.kind;
    if (kind == vis::PairKind::BackFacing || kind == vis::PairKind::FullyHidden) {
        scratch.note(cell, Answer::NoLight);
        // A fully hidden pair's points see none of the light (where it rises above their
        // horizon); a back-facing one's see no light to be hidden.
        if (kind == vis::PairKind::FullyHidden && scratch.seen != nullptr &&
            e.light.plane.side(p.x) == vis::Sign::Positive &&
            clippedLight(k, p.face, scratch).size() >= 3)
            scratch.noteSeen(cell, LightSeen::None);
        return {};
    }
    return kind == vis::PairKind::FullyVisible ? fullyVisibleAnswer(e) : treeWalkAnswer(e);
}

const PairRecord* DirectLighting::pairRecord(const PairKey& key, size_t k,
                                             ExactScratch& scratch) const {
    const PairRecord* record = scratch.lastTree[k];
    if ((record == nullptr && !scratch.lastDirect[k]) || scratch.lastKey[k] != key) {
        // Without a tree and not to be built: evaluated point by point (buildMissing).
        record = store_->find(key);
        const bool direct = record == nullptr && !scratch.buildMissing;
        if (record == nullptr && !direct) record = &store_->getOrBuild(key);
        scratch.lastKey[k] = key;
        scratch.lastTree[k] = record;
        scratch.lastDirect[k] = direct;
        scratch.used.insert(key);
        if (direct) scratch.usedDirect.insert(key);
    }
    return record;
}

bool DirectLighting::knownOverLimit(size_t k, uint64_t cell, ExactScratch& scratch) const {
    if (!scratch.regionCorners.empty()) {
        if (scratch.regions.size() != lights_.size()) {
            scratch.regions.assign(lights_.size(), vis::RegionDecisions{});
            scratch.regionOf.assign(lights_.size(), 0);
            scratch.regionOverLimit.assign(lights_.size(), 0);
        }
        if (scratch.regionOverLimit[k] == scratch.regionId) return true;
    }
    return scratch.overLimitBefore != nullptr &&
           scratch.overLimitBefore->find(cell) != scratch.overLimitBefore->end();
}

Vec3 DirectLighting::gaveUp(Evaluation& e, bool tried) const {
    ExactScratch& scratch = e.scratch;
    // What the default path's giving up decides, whatever answers the point now: the later
    // points of its region and pixel skip that path, and a tree's walk over the limit is where
    // the renderer refines.
    const vis::WorkStage stage = scratch.query.limitStage();
    if (!scratch.regionCorners.empty() && e.record != nullptr)
        scratch.regionOverLimit[e.k] = scratch.regionId;
    if (tried) scratch.overLimitNow.push_back(e.cell);
    if (e.record != nullptr && e.record->tree.kind == vis::PairKind::Penumbra &&
        !answeredByGroups(*e.record))
        scratch.overLimitTrees.push_back({e.key, e.p.x, e.cell});
    if (scratch.lightEdgeWorkLimit != 0) {
        auto in = [&](const std::unordered_set<uint64_t>* cells) {
            return cells != nullptr && cells->find(e.cell) != cells->end();
        };
        const bool declinedBefore = in(scratch.edgeDeclinedBefore);
        if (in(scratch.edgeFailedBefore)) {
            ++scratch.evaluations.lightEdgesSkipped;
        } else if (const std::optional<Vec3> v =
                       declinedBefore ? std::nullopt : lightEdgeAnswer(e)) {
            return *v;
        } else if (declinedBefore || !scratch.query.limitReached()) {
            // (Declined here, or by the pixel's earlier attempt: counted as declined.)
            scratch.evaluations.lightEdgesNotTaken += declinedBefore;
            // Declined (it would not pay, or cannot be taken here): the default path again,
            // with the light-edge path's limit; over that too, the point is sampled.
            ++scratch.evaluations.retried;
            vis::FromPointQuery& query = scratch.query;
            const uint64_t limit = query.workLimit();
            query.setWorkLimit(scratch.lightEdgeWorkLimit);
            e.retry = true;
            e.firstStage = stage;
            e.tried = tried;
            const Vec3 v = e.record == nullptr || answeredByGroups(*e.record) ? directAnswer(e)
                                                                              : treeWalkAnswer(e);
            query.setWorkLimit(limit);
            return v;
        }
    }
    return overLimit(e, tried, stage);
}

Vec3 DirectLighting::limitReached(Evaluation& e) const {
    if (!e.retry) return gaveUp(e, true);
    ++e.scratch.evaluations.retriedOverLimit;
    e.scratch.edgeFailedNow.push_back(e.cell);
    return overLimit(e, e.tried, e.firstStage);
}

std::optional<Vec3> DirectLighting::lightEdgeAnswer(Evaluation& e) const {
    ExactScratch& scratch = e.scratch;
    vis::FromPointQuery& query = scratch.query;
    const uint64_t limit = query.workLimit();
    query.setWorkLimit(scratch.lightEdgeWorkLimit);
    const vis::FragmentList* list = query.runLightEdges(
        scene_.mesh, e.p.face, e.light.face, e.p.answered(), bvh_.faceBoxes(), lightEdges(e.k));
    query.setWorkLimit(limit);
    countWork(scratch, 1);
    if (list == nullptr || query.limitReached()) {
        // (Over its limit the pixel's later points skip it; declined, they retry the default
        // path: gaveUp.)
        if (list == nullptr) {
            ++scratch.evaluations.lightEdgesNotTaken;
            ++scratch.evaluations
                  .lightEdgesDeclinedBy[static_cast<size_t>(query.lightEdgeDecline())];
            scratch.edgeDeclinedNow.push_back(e.cell);
        } else {
            ++scratch.evaluations.lightEdgesOverLimit;
            ++scratch.evaluations.lightEdgesOverLimitAt[static_cast<size_t>(query.limitStage())];
            scratch.edgeFailedNow.push_back(e.cell);
        }
        return std::nullopt;
    }
    ++scratch.evaluations.lightEdges;
    const Vec3 v = shadeFragments(e.p, e.light, *list, {}, e.glossySamples, e.rng, scratch);
    noteSeen(e, *list);
    exactDone(e, Answer::LightEdges, list->size());
    return v;
}

const vis::LightEdgeIndex& DirectLighting::lightEdges(size_t k) const {
    LightEdgeSlot& slot = lightEdges_[k];
    tbb::collaborative_call_once(slot.once, [&] {
        const vis::ParallelLoops loops = tbbLoops();
        MeshEdgesSlot& table = *meshEdges_;
        tbb::collaborative_call_once(table.once, [&] {
            const auto t0 = Clock::now();
            table.edges = vis::MeshEdges(scene_.mesh, loops);
            table.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        });
        const auto t0 = Clock::now();
        slot.index = vis::LightEdgeIndex(scene_.mesh, table.edges, lights_[k].face, loops);
        slot.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
        slot.built.store(true, std::memory_order_release);
    });
    return slot.index;
}

std::vector<uint32_t> DirectLighting::lightEdgesBuilt() const {
    std::vector<uint32_t> built;
    for (size_t k = 0; k < lights_.size(); ++k)
        if (lightEdges_[k].built.load(std::memory_order_acquire))
            built.push_back(static_cast<uint32_t>(k));
    return built;
}

LightEdgeIndexStats DirectLighting::lightEdgeStats() const {
    LightEdgeIndexStats out;
    for (size_t k = 0; k < lights_.size(); ++k) {
        const LightEdgeSlot& slot = lightEdges_[k];
        if (!slot.built.load(std::memory_order_acquire)) continue;
        ++out.lights;
        out.seconds += slot.seconds;
        out.bytes += slot.index.bytes();
        out.silhouetteEdges += slot.index.size();
    }
    if (out.lights > 0) {  // (the edge table was built before the first index)
        out.seconds += meshEdges_->seconds;
        out.meshEdges = meshEdges_->edges.size();
    }
    return out;
}

Vec3 DirectLighting::overLimit(Evaluation& e, bool tried, vis::WorkStage stage) const {
    ExactScratch& scratch = e.scratch;
    ++scratch.evaluations.sampled;
    scratch.note(e.cell, Answer::Sampled);
    if (tried) ++scratch.evaluations.overLimitAt[static_cast<size_t>(stage)];
    if (e.record == nullptr) ++scratch.evaluations.sampledDirect;
    if (e.timed && tried) scratch.evaluations.costs.attemptNs.addSince(e.evalStart);
    if (!e.timed) return sampledAreaLight(e.light, e.p, e.fallbackSamples, e.rng);
    const auto raysStart = Clock::now();
    const Vec3 v = sampledAreaLight(e.light, e.p, e.fallbackSamples, e.rng);
    scratch.evaluations.costs.sampledNs.addSince(raysStart);
    return v;
}

void DirectLighting::exactDone(Evaluation& e, Answer path, size_t fragments) const {
    ExactScratch& scratch = e.scratch;
    if (e.timed) scratch.evaluations.costs.exactNs.addSince(e.evalStart);
    const vis::FromPointQuery::ChainCounts& chain = scratch.query.chainCounts();
    const bool noLight = scratch.query.work() == 0 && fragments == 0;
    scratch.note(e.cell, path == Answer::LightEdges ? path
                         : chain.cells != 0         ? Answer::Chain
                         : noLight                  ? Answer::NoLight
                                                    : path);
    if (path == Answer::LightEdges) {
        ++scratch.evaluations.costs.lightEdgeEvaluations;
        scratch.evaluations.costs.lightEdgesExamined += chain.lightEdgesExamined;
        scratch.evaluations.costs.lightEdgesWeighted += chain.boundaryEdges;
        scratch.evaluations.costs.lightEdgesInCone += chain.chainInCone;
    }
    if (chain.cells == 0) return;
    ++scratch.evaluations.costs.chainEvaluations;
    scratch.evaluations.costs.chainOccluderEdges += chain.occluderEdges;
    scratch.evaluations.costs.chainBoundaryEdges += chain.boundaryEdges;
    scratch.evaluations.costs.chainCells += chain.cells;
    scratch.evaluations.costs.chainFragments += fragments;
}

const vis::Polygon3& DirectLighting::clippedLight(size_t k, uint32_t face,
                                                  ExactScratch& scratch) const {
    if (scratch.clippedFace[k] != face) {
        const vis::FacePlane receiver = vis::facePlane(scene_.mesh, face);
        const vis::OrientedPlane horizon{receiver.a, receiver.b, receiver.c};
        scratch.clippedLight[k] = vis::clipConvexPositive(lights_[k].polygon, horizon);
        scratch.clippedByHorizon[k] = vis::anyVertexBehind(lights_[k].polygon, horizon);
        scratch.clippedFace[k] = face;
    }
    return scratch.clippedLight[k];
}

void DirectLighting::noteSeen(Evaluation& e, const vis::FragmentList& list) const {
    ExactScratch& scratch = e.scratch;
    if (scratch.seen == nullptr) return;
    // The pair's first signs left no light (exactDone's "no light"): no fraction to count.
    if (scratch.query.work() == 0 && list.empty()) return;
    const vis::Polygon3& light = clippedLight(e.k, e.p.face, scratch);
    const double unoccluded = light.size() < 3 ? 0 : vis::formFactor(e.p.x, e.p.n, light);
    if (!(unoccluded > 0)) return;  // nothing of the light above x's horizon
    double visible = 0;
    for (size_t i = 0; i < list.size(); ++i) visible += vis::formFactor(e.p.x, e.p.n, list[i]);
    scratch.noteSeen(e.cell, lightSeen(!list.empty(), visible, unoccluded));
}

Vec3 DirectLighting::directAnswer(Evaluation& e) const {
    ExactScratch& scratch = e.scratch;
    // The faces in the pyramid from x, clipped from x.
    const vis::FragmentList& list =
        scratch.query.runDirect(scene_.mesh, e.p.face, e.light.face, e.p.answered(),
                                bvh_.faceBoxes(), &bvh_.faceClusters());
    if (e.retry) {
        // (Counted on the first try.)
    } else if (e.record == nullptr) {
        const vis::FromPointQuery& q = scratch.query;
        scratch.evaluations.directGrouped += q.clustersUsed() > 0;
        scratch.evaluations.directSolid += q.solidGroupsLeftOut() + q.solidFacesLeftOut() > 0;
        scratch.evaluations.directHiddenBySolid += q.hiddenBySolid();
    } else {
        ++scratch.evaluations.partialByGroups;
    }
    countWork(scratch, 1);
    if (scratch.query.limitReached()) return limitReached(e);
    const Vec3 v = shadeFragments(e.p, e.light, list, {}, e.glossySamples, e.rng, scratch);
    noteSeen(e, list);
    exactDone(e, Answer::Direct, list.size());
    return v;
}

Vec3 DirectLighting::fullyVisibleAnswer(Evaluation& e) const {
    ExactScratch& scratch = e.scratch;
    const size_t k = e.k;
    // What FPQuery returns for a fully visible pair, cached per receiver face.
    if (e.light.plane.side(e.p.x) != vis::Sign::Positive) {
        scratch.note(e.cell, Answer::NoLight);
        return {};
    }
    if (clippedLight(k, e.p.face, scratch).size() < 3) {
        scratch.note(e.cell, Answer::NoLight);
        return {};
    }
    scratch.note(e.cell,
                 scratch.clippedByHorizon[k] ? Answer::HorizonClipped : Answer::FullyVisible);
    scratch.noteSeen(e.cell, LightSeen::Whole);
    static const vis::FragmentList kNone;  // immutable: shared by every thread
    return shadeFragments(e.p, e.light, kNone,
                          std::span<const vis::Polygon3>(&scratch.clippedLight[k], 1),
                          e.glossySamples, e.rng, scratch);
}

Vec3 DirectLighting::treeWalkAnswer(Evaluation& e) const {
    ExactScratch& scratch = e.scratch;
    vis::RegionDecisions* region = nullptr;
    if (!scratch.regionCorners.empty()) {
        region = &scratch.regions[e.k];
        if (scratch.regionOf[e.k] != scratch.regionId || region->tree() != &e.record->tree) {
            region->reset(scene_.mesh, e.record->tree, scratch.regionCorners);
            scratch.regionOf[e.k] = scratch.regionId;
        }
    }
    const vis::FragmentList& list =
        scratch.query.run(scene_.mesh, e.record->tree, e.p.answered(), nullptr, region);
    countWork(scratch, 0);
    if (scratch.query.limitReached()) return limitReached(e);
    noteSeen(e, list);
    if (list.empty()) {
        exactDone(e, Answer::TreeWalk, 0);
        return {};
    }
    const Vec3 v = shadeFragments(e.p, e.light, list, {}, e.glossySamples, e.rng, scratch);
    exactDone(e, Answer::TreeWalk, list.size());
    return v;
}

Vec3 DirectLighting::shadeFragments(const SurfacePoint& p, const AreaLight& light,
                                    const vis::FragmentList& list,
                                    std::span<const vis::Polygon3> fragments, int glossySamples,
                                    SplitMix64& rng, ExactScratch& scratch) const {
    const Material& m = *p.material;
    const bool glossy = m.isGlossy() && glossySamples > 0;
    // Diffuse: irradiance pi ke F times kd / pi. Exact up to rounding.
    double formFactor = 0;
    for (size_t i = 0; i < list.size(); ++i) formFactor += vis::formFactor(p.x, p.n, list[i]);
    for (const vis::Polygon3& fragment : fragments)
        formFactor += vis::formFactor(p.x, p.n, fragment);
    Vec3 out = mul(p.kd, light.ke) * formFactor;
    if (!glossy) return out;
    // Glossy: stratified area samples inside the visible fragments only (no shadow rays).
    TriangleSampler& sampler = scratch.fragments;
    sampler.clear();
    for (size_t i = 0; i < list.size(); ++i) sampler.addPolygon(list[i]);
    for (const vis::Polygon3& fragment : fragments) sampler.addPolygon(fragment);
    if (sampler.empty()) return out;
    int a = 1, b = 1;
    stratifiedGrid(glossySamples, a, b);
    double sum = 0;
    for (int i = 0; i < b; ++i) {
        for (int j = 0; j < a; ++j) {
            const double u = (i + rng.uniform()) / b;
            const double v = (j + rng.uniform()) / a;
            const Vec3 d = sampler.sample(u, v) - p.x;
            const double r2 = dot(d, d);
            if (!(r2 > 0)) continue;
            const Vec3 wi = d / std::sqrt(r2);
            const double cosX = dot(p.n, wi), cosY = -dot(light.normal, wi);
            if (!(cosX > 0) || !(cosY > 0)) continue;
            sum += phongLobe(m.ns, p.n, p.wo, wi) * cosX * cosY / r2;
        }
    }
    return out + mul(m.ks, light.ke) * (sum * sampler.area() / glossySamples);
}

Vec3 DirectLighting::sampledAreaLight(const AreaLight& light, const SurfacePoint& p, int samples,
                                      SplitMix64& rng) const {
    if (light.face == p.face || light.sampler.empty() || samples < 1) return {};
    // The light emits only to its front.
    if (!(dot(p.x - light.origin, light.normal) > 0)) return {};
    const Material& m = *p.material;
    int a = 1, b = 1;
    stratifiedGrid(samples, a, b);
    Vec3 sum{};
    for (int i = 0; i < b; ++i) {
        for (int j = 0; j < a; ++j) {
            const double u = (i + rng.uniform()) / b;
            const double v = (j + rng.uniform()) / a;
            const Vec3 y = light.sampler.sample(u, v);
            const Vec3 d = y - p.x;
            const double r2 = dot(d, d);
            if (!(r2 > 0)) continue;
            const Vec3 wi = d / std::sqrt(r2);
            const double cosX = dot(p.n, wi), cosY = -dot(light.normal, wi);
            // x sees only its face's open front half-space.
            if (!(cosX > 0) || !(cosY > 0)) continue;
            if (bvh_.occluded(p.x, y, p.face, light.face)) continue;
            sum += brdf(m, p.kd, p.n, p.wo, wi) * (cosX * cosY / r2);
        }
    }
    return mul(sum, light.ke) * (light.sampler.area() / samples);
}

Vec3 DirectLighting::sampledAreaLights(const SurfacePoint& p, int samples, SplitMix64& rng) const {
    Vec3 out{};
    for (const AreaLight& light : lights_) out += sampledAreaLight(light, p, samples, rng);
    return out;
}

Vec3 DirectLighting::pointLights(const SurfacePoint& p) const {
    Vec3 out{};
    for (const PointLight& light : scene_.pointLights) {
        const Vec3 d = light.position - p.x;
        const double r2 = dot(d, d);
        if (!(r2 > 0)) continue;
        const Vec3 wi = d / std::sqrt(r2);
        const double cosX = dot(p.n, wi);
        if (!(cosX > 0)) continue;
        if (bvh_.occluded(p.x, light.position, p.face, EmbreeScene::kNoFace)) continue;
        out += mul(brdf(*p.material, p.kd, p.n, p.wo, wi), light.intensity) * (cosX / r2);
    }
    return out;
}

}  // namespace penumbra
