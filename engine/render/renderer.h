// ProgressiveRenderer: the CPU ray tracer with exact soft shadows.
//
// One pass = one jittered primary sample per pixel, rendered in tiles on oneTBB. Passes accumulate
// in a Film; a pass can be cancelled (the partial pass is discarded, the film keeps whole passes).
// Direct illumination only (emitted + one bounce from the area and point lights).
//   Exact:     the visible fragments of each area light from the shading point (FPQuery through the
//              VisibilityStore). Diffuse: L = kd * Le * F with F the point-to-polygon form factor
//              of the fragments (irradiance pi Le F, times kd / pi): analytic, no samples.
//              Glossy: samples drawn only inside the visible fragments.
//   Sampled:   N stratified shadow rays per light per shading point (Embree), the paper's baseline.
//   Reference: the same as Sampled with many rays (referenceSamples).
// Conventions (engine/render/shading.h has the BRDF and the estimators):
//   - A receiver sees only its face's front hemisphere and a light emits only to its front: a
//     primary ray that hits a face from behind (or edge-on) returns black, emission included.
//   - Embree's hit point is computed in float and lies a hair off the face's plane; it is
//     projected onto the plane (through the face's first vertex, unit Newell normal) before
//     shading, since the from-point query takes x on the face. The projection is itself rounded:
//     x is on the plane up to an ulp or so, which moves a shadow boundary by as much.
//   - Point lights: one shadow ray each (EmbreeScene::occluded), in every method.
//   - Random numbers are counter-based (engine/scene/random.h): the image does not depend on the
//     thread schedule, and the same settings give the same film.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <span>
#include <string>
#include <unordered_set>
#include <vector>

#include "engine/precompute/visibility_store.h"
#include "engine/render/answers.h"
#include "engine/render/effects_summary.h"
#include "engine/render/pass_findings.h"
#include "engine/render/tile_schedule.h"
#include "engine/render/visible_fraction.h"
#include "engine/scene/camera.h"
#include "engine/scene/scene.h"
#include "visibility/fp_query/from_point_query.h"

namespace penumbra {

class EmbreeScene;
class DirectLighting;
struct OverLimitPoint;

enum class DirectMethod { Exact, Sampled, Reference };
const char* toString(DirectMethod m);

struct RenderSettings {
    int width = 512;
    int height = 512;
    int spp = 16;  // primary samples per pixel (= passes)
    DirectMethod method = DirectMethod::Exact;
    int lightSamples = 128;       // shadow rays per light per shading point (Sampled)
    int referenceSamples = 1024;  // (Reference)
    uint64_t seed = 1;            // the pixel sampling pattern; the same seed gives the same jitter
    // The light sampling (shadow-ray positions, glossy samples inside the fragments): separate from
    // `seed` so that the pixel pattern can stay fixed while the light samples change.
    uint64_t lightSeed = 1;
    int glossySamples = 16;  // Exact, glossy materials: samples per light inside the fragments
    // Exact: the work one from-point query may do on the tree and direct paths, in plane tests
    // (vis::FromPointQuery::setWorkLimit); a point whose exact answer needs more (hundreds of
    // fragments behind a plant's leaves) takes the light-edge path (lightEdgeWorkLimit below, the
    // same answer), and is shaded with lightSamples shadow rays only where that fails too (the
    // effects summary counts it). 0 = no limit: every point exact on the first paths, whatever it
    // costs - not more exact than the default, and slower where the light-edge path is cheaper
    // (the motorbike: 37.8 s of CPU against 17.1 s, the same image). 256 or 4096 instead of 1024
    // changed no scene's time beyond the machine's noise (the motorbike: 0.985x at 256, paired).
    uint64_t exactWorkLimit = 1024;
    // Exact, with a work limit: a point the paths above gave up on at exactWorkLimit (and the
    // later points of its region and pixel, which skip them) takes the light-edge path
    // (vis::FromPointQuery::runLightEdges: the boundary chain from the light's silhouette edges
    // near the point's cone, no face activated; the same exact answer) with this many plane
    // tests of its own before it is sampled; a pixel whose attempt reached it, or could not take
    // the path (a face cut by the light's plane near its cone), is sampled in the later passes
    // without trying. Easy points never pay for it. 0 = never tried (sampled at once).
    uint64_t lightEdgeWorkLimit = 4194304;
    // Exact: a point clipped against at least this many occluders (a partial tree's deferred
    // ones, or the direct path's) is evaluated by their boundary chain when most of their edges
    // cancel (vis::FromPointQuery::ChainOptions; the same answer). 0 = never.
    uint32_t chainMinOccluders = vis::FromPointQuery::ChainOptions{}.minOccluders;
    // Exact: a (receiver patch, light) pair that the image's primary samples (all passes) hit
    // fewer times than this gets no history tree; its points are evaluated directly
    // (vis::FromPointQuery::runDirect: the faces in each point's pyramid to the light, clipped
    // from the point; exact, no precompute). On a finely tessellated mesh most receivers are seen
    // by a few samples each, and a tree would cost more than all of their queries. 0 = a tree for
    // every pair. Only prepare() decides this (a pass alone, without prepare, builds what it
    // needs); it counts the samples of the first two passes.
    uint64_t minTreeSamples = 64;
    // Exact, with minTreeSamples > 0: a pair seen often enough for a tree, whose shaft holds at
    // least this many faces with a quarter of them in face groups, gets no tree either: its
    // partial tree would be answered by the direct path with the groups (groupsWillAnswer,
    // shading.h), so building it would be wasted. 0 = build them.
    uint32_t groupedShaftMin = 1024;
    // Exact, with a work limit: query-driven refinement. After each pass, a tree whose points
    // reached the work limit has its receiver patch split (PatchLayout::refine) and the
    // trees of the sub-patches those points lie in built, so that the later passes walk a tree
    // for a smaller region (narrower shaft, more of its occluders inserted) where the image
    // found the exact answer expensive; nothing is built where it did not, nor where the build
    // would cost more than sampling those points in the passes left. Up to this many levels
    // below a patch (at most PatchLayout::kMaxRefineLevels); 0 = never. The same answer.
    int refineLevels = PatchLayout::kMaxRefineLevels;
    // A sub-patch tree is built where its estimated cost is at most this many times that of the
    // sampling it replaces (1: break-even; tests raise it to refine wherever the limit was hit).
    double refineCostShare = 1;
    // Exact: keep per pixel how its evaluations were answered (Film::answers, answers.h): a byte
    // per (pixel, light) per pass and six counts per pixel in the film, so off unless asked for.
    bool recordAnswers = false;
    // Exact: keep per pixel how many of its evaluations saw none, part or all of their light
    // (Film::seen, visible_fraction.h): the penumbra pixels of the image. A byte per (pixel,
    // light) per pass and three counts per pixel, and a form factor more per queried evaluation.
    bool recordVisibleFraction = false;
};

// Linear radiance, accumulated over passes. A pass adds one jittered sample per pixel; the jitter
// of pixel (x, y) in pass p depends only on (RenderSettings::seed, p, x, y).
struct Film {
    int width = 0, height = 0;
    int passes = 0;
    std::vector<Vec3> sum;  // width * height, row-major from the top-left
    // Exact method with RenderSettings::recordAnswers: per pixel, how many of its evaluations (all
    // passes, all area lights) took each answer (answers.h); else empty.
    std::vector<AnswerCounts> answers;
    // Exact method with RenderSettings::recordVisibleFraction: per pixel, how many of its
    // evaluations (all passes, all area lights) saw none, part or all of their light; else empty.
    std::vector<SeenCounts> seen;
    void reset(int w, int h);
    Vec3 mean(int x, int y) const;  // sum / passes (0 when no pass)
};

struct RenderTimes {
    // Seconds building the history trees the image needs: prepare's, and the refinement's after
    // the passes (`refine`, part of it).
    double precompute = 0;
    double refine = 0;
    double primary = 0;  // tracing primary rays (summed over threads, then scaled to wall time)
    double shading = 0;  // direct illumination
    double total = 0;    // wall time
    // Process CPU time (all threads, user + system) of the precompute and of the whole render:
    // on a loaded machine wall times mislead, CPU times still compare methods.
    double precomputeCpu = 0;  // the refinement's included
    double totalCpu = 0;
};

// Where the trees an image needs are built and the tiles of its passes shaded besides this
// process: the other ranks of an MPI job (engine/cluster/cluster_render.h). The renderer calls it
// from the thread that called render(), which must then only coordinate (the shading of this
// process's own tiles runs on other threads meanwhile). Each call either succeeds or throws (a
// rank lost, a failed build: the render is over).
class RenderCluster {
  public:
    virtual ~RenderCluster() = default;
    // Builds the trees of `keys` (none in the store yet) across the processes: each ends up in
    // this store and in every other process's. False when cancelled.
    virtual bool buildTrees(const std::vector<PairKey>& keys) = 0;
    // The store's layout was refined at `keys` (refineWhere), before any of their sub-patch
    // trees is built: every process refines its layout the same way.
    virtual void refined(const std::vector<PairKey>& keys) = 0;
    // Shades pass `pass` of a width x height image: hands tiles of `schedule` (most expensive
    // first) to the other processes while `shadeHere` runs on this process's threads, taking tiles
    // from the same schedule; a remote tile's pixels go into `image` (row-major, the whole image),
    // its cost into the schedule, and what the remote tiles found into `found`. Cancelled
    // (`cancel`, read about every millisecond), it sets `stopHere`, which `shadeHere` reads before
    // each tile, waits for `shadeHere` and returns false.
    virtual bool shadePass(int pass, int width, int height, const PassCells& cells,
                           TileSchedule& schedule, std::vector<Vec3>& image,
                           const std::function<void()>& shadeHere, std::atomic<bool>& stopHere,
                           PassFindings& found, const std::atomic<bool>* cancel) = 0;
};

class ProgressiveRenderer {
  public:
    // All three must outlive the renderer. The store is used only by DirectMethod::Exact.
    ProgressiveRenderer(const Scene& scene, const EmbreeScene& bvh, VisibilityStore& store);

    // The trees the image needs (for Exact), built in parallel before shading: the (receiver
    // patch, light) pairs hit by the primary rays often enough (RenderSettings::minTreeSamples,
    // counted on the first two passes; every pass is traced when it is 0). Returns seconds spent.
    // Cancellable; returns early when cancelled.
    double prepare(const Camera& camera, const RenderSettings& settings,
                   const std::atomic<bool>* cancel = nullptr);
    // Adds one pass (pass index = film.passes) to the film. Returns false when cancelled (the film
    // is unchanged). A film of another size than settings' is reset first. The cancel flag is
    // read before each tile. Throws std::invalid_argument for settings out of range (sizes,
    // spp or sample counts < 1).
    bool renderPass(const Camera& camera, const RenderSettings& settings, Film& film,
                    const std::atomic<bool>* cancel = nullptr);
    // prepare + settings.spp passes.
    Film render(const Camera& camera, const RenderSettings& settings, RenderTimes* times = nullptr,
                const std::atomic<bool>* cancel = nullptr);

    // Builds the trees and shades the passes across the processes of `cluster` too (null: this
    // process alone, the default). The image and the effects summary are the same either way.
    void setCluster(RenderCluster* cluster) { cluster_ = cluster; }
    // The other processes' side of RenderCluster::shadePass: shades `tiles` of pass `pass` (the
    // film's earlier passes' cells in `cells`) on this process's threads; `pixels` gets each
    // tile's pixels in turn (its rows top to bottom), `costNs` each tile's thread time, `found`
    // what they found. The store must hold the trees rank 0's does (and its layout the same
    // refinements). `cancel` is read before each tile (what is left unshaded is then garbage).
    void shadeTiles(const Camera& camera, const RenderSettings& settings, int pass,
                    const PassCells& cells, std::span<const int> tiles, std::vector<Vec3>& pixels,
                    std::vector<int64_t>& costNs, PassFindings& found,
                    const std::atomic<bool>* cancel = nullptr);

    // What was simulated and why (pairs by kind, materials analytic or sampled, point lights), for
    // the images rendered since construction or the last resetEffects().
    EffectsSummary effects() const;
    void resetEffects();

    ~ProgressiveRenderer();
    ProgressiveRenderer(const ProgressiveRenderer&) = delete;
    ProgressiveRenderer& operator=(const ProgressiveRenderer&) = delete;

  private:
    struct PassTimes;
    bool renderPassTimed(const Camera& camera, const RenderSettings& settings, Film& film,
                         const std::atomic<bool>* cancel, PassTimes* times);
    // Query-driven refinement after a pass (RenderSettings::refineLevels): the trees whose
    // walks from `points` (this pass's points sampled over the work limit) would have answered
    // are refined, and the sub-patches holding those points built where the build costs less
    // than sampling them would in the `passesLeft` passes to come (a cost model in shadow rays:
    // deterministic). The cells of the points whose sub-patch got a tree leave overLimitCells_
    // (the others stay skipped). Returns false when cancelled (what was built stays).
    bool refineWhere(const std::vector<OverLimitPoint>& points, const RenderSettings& settings,
                     int passesLeft, const std::atomic<bool>* cancel);
    void recordUse(const std::vector<PairKey>& keys, const std::vector<uint32_t>& faces,
                   const RenderSettings& settings, const ExactEvaluations& evaluations = {},
                   const std::vector<PairKey>& directKeys = {});

    const Scene& scene_;
    const EmbreeScene& bvh_;
    VisibilityStore& store_;
    std::unique_ptr<DirectLighting> lighting_;
    std::vector<Vec3> faceNormal_;      // unit, per face
    std::vector<Vec3> faceOrigin_;      // first vertex, per face
    std::vector<uint8_t> passAnswers_;  // renderPass's, kept for its capacity
    std::vector<uint8_t> passSeen_;     // (the same for what each evaluation saw)

    // What the images used (effects()); guarded by mutex_.
    mutable std::mutex mutex_;
    std::set<PairKey> usedKeys_;
    std::vector<char> faceSeen_;
    bool rendered_ = false;
    DirectMethod method_ = DirectMethod::Exact;
    int lightSamples_ = 0, glossySamples_ = 0;
    uint64_t exactWorkLimit_ = 0, lightEdgeWorkLimit_ = 0;
    // Exact method: (point, light) evaluations, and those over the work limit (sampled).
    ExactEvaluations evaluations_;
    uint64_t minTreeSamples_ = 0;
    std::set<PairKey> directUsed_;
    // The pairs prepare() left without a tree because the groups answer them (groupedShaftMin),
    // with the faces in their shafts.
    std::set<PairKey> groupedNoTree_;
    uint64_t groupedNoTreeFaces_ = 0;
    uint32_t groupedShaftMin_ = 0;
    // Query-driven refinement so far (refineWhere): the trees with sub-patch trees built below
    // them, those sub-patch trees, the sub-patches left without one (not worth it), and the
    // wall time it took.
    std::set<PairKey> refinedParents_;
    size_t refinedTrees_ = 0;
    std::set<PairKey> refineNotWorth_;
    double refineSeconds_ = 0;
    // The (pixel, light) cells of the film being accumulated whose exact query reached the work
    // limit (ExactScratch::overLimitBefore), the limit they were for and the store's tree count
    // then (cleared when either changes): written between passes, read by a pass's tiles.
    std::unordered_set<uint64_t> overLimitCells_;
    // Of them, those whose light-edge attempt reached its own limit or could not be taken
    // (ExactScratch::edgeFailedBefore): sampled without trying it. Cleared with them.
    std::unordered_set<uint64_t> edgeFailedCells_;
    // And those where it declined (ExactScratch::edgeDeclinedBefore): the default path with its
    // limit at once.
    std::unordered_set<uint64_t> edgeDeclinedCells_;
    uint64_t overLimitCellsLimit_ = 0, overLimitCellsEdgeLimit_ = 0;
    size_t overLimitCellsTrees_ = 0;
    // The from-point query workspaces, one per worker thread, kept across passes and films
    // (QueryPool in renderer.cpp): a fresh one sizes its per-mesh tables (the face hierarchy's
    // node stamps: 2 MB on the 871k dragon) on its first point.
    struct QueryPool;
    std::unique_ptr<QueryPool> queries_;
    // The order of a pass's tiles, from the last whole pass's costs (tile_schedule.h).
    TileSchedule schedule_;
    // Set by prepare() with minTreeSamples > 0: the passes evaluate the pairs without a tree
    // point by point instead of building them (written by prepare, read by the passes, never at
    // the same time).
    bool directMissing_ = false;
    RenderCluster* cluster_ = nullptr;
};

// Output (engine/io/image_io.cpp). PFM: linear float, little-endian, bottom-to-top rows as the
// format requires. OpenEXR: linear 32-bit float RGB, the same values as the PFM
// (engine/io/exr_io.h). PNG: exposure then sRGB tone mapping. All written atomically (temp file +
// rename); failures throw std::runtime_error naming the file and the reason.
void writePfm(const Film& film, const std::string& path);
void writeExr(const Film& film, const std::string& path);
void writePng(const Film& film, const std::string& path, double exposure = 1.0);

}  // namespace penumbra
