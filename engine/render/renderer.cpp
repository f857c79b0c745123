#include "engine/render/renderer.h"

#include <sys/resource.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

#include "engine/raytrace/embree_scene.h"
#include "engine/render/cpu_time.h"
#include "engine/render/shading.h"
#include "engine/render/shading_point.h"
#include "engine/render/tile_schedule.h"
#include "engine/scene/light_checks.h"
#include "engine/scene/random.h"
#include "visibility/face_plane.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;

// The exact method shades a tile in cells of kRegionCell x kRegionCell pixels: the points of one
// receiver patch in one cell share the region decisions of the from-point query. A tile is one
// cell (engine/render/tile_schedule.h).
constexpr int kRegionCell = 8;
constexpr int kTileSize = TileSchedule::kTileSize;
static_assert(kTileSize % kRegionCell == 0 &&
              (kTileSize / kRegionCell) * (kTileSize / kRegionCell) <= 256);

// The distinct corners of a box (1, 2, 4 or 8 of them: a flat box has fewer).
void boxCorners(const vis::Bounds3& box, std::vector<Vec3>& out) {
    out.clear();
    const double xs[2] = {box.lo.x, box.hi.x}, ys[2] = {box.lo.y, box.hi.y},
                 zs[2] = {box.lo.z, box.hi.z};
    const int nx = box.lo.x == box.hi.x ? 1 : 2, ny = box.lo.y == box.hi.y ? 1 : 2,
              nz = box.lo.z == box.hi.z ? 1 : 2;
    for (int i = 0; i < nx; ++i)
        for (int j = 0; j < ny; ++j)
            for (int k = 0; k < nz; ++k) out.push_back({xs[i], ys[j], zs[k]});
}
// Tags that keep the light streams apart from the pixel streams when the two seeds are equal.
constexpr uint64_t kPixelStream = 0x50495845ull, kLightStream = 0x4C494748ull;

double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

void validate(const RenderSettings& s) {
    auto require = [](bool ok, const std::string& what) {
        if (!ok) throw std::invalid_argument("render settings: " + what);
    };
    require(s.width >= 1 && s.height >= 1, "image size " + std::to_string(s.width) + "x" +
                                               std::to_string(s.height) + " (both must be >= 1)");
    require(s.width <= 65536 && s.height <= 65536, "image size above 65536 pixels per side");
    require(s.spp >= 1, "spp " + std::to_string(s.spp) + " (must be >= 1)");
    require(s.lightSamples >= 1,
            "light samples " + std::to_string(s.lightSamples) + " (must be >= 1)");
    require(s.referenceSamples >= 1,
            "reference samples " + std::to_string(s.referenceSamples) + " (must be >= 1)");
    require(s.glossySamples >= 1,
            "glossy samples " + std::to_string(s.glossySamples) + " (must be >= 1)");
    require(s.refineCostShare >= 0 && std::isfinite(s.refineCostShare),
            "refine cost share " + std::to_string(s.refineCostShare) + " (must be finite, >= 0)");
    require(s.refineLevels >= 0 && s.refineLevels <= PatchLayout::kMaxRefineLevels,
            "refine levels " + std::to_string(s.refineLevels) + " (must be 0.." +
                std::to_string(PatchLayout::kMaxRefineLevels) + ")");
}

// Query-driven refinement's cost model (refineWhere), in shadow rays, measured on the table scene
// (2-core EPYC): a linear program of a tree's build costs about 5 us, a shadow ray about 0.1 us
// (128 rays: 6-13 us), a tree about 0.1 ms besides its programs. Counts, not seconds: what is
// refined, and so the image, is the same on every run and machine.
constexpr double kRefineRaysPerLpSolve = 50, kRefineRaysPerTree = 1000;

Tile tileAt(int index, const RenderSettings& s) {
    return TileSchedule::tileAt(index, s.width, s.height);
}

int tileCount(const RenderSettings& s) { return TileSchedule::tileCount(s.width, s.height); }

// The primary ray of pixel (x, y) in pass `pass`: a uniform jitter inside the pixel drawn from
// the stream (seed, pass, pixel).
Ray primaryRay(const CameraRays& rays, const RenderSettings& s, int pass, int x, int y) {
    SplitMix64 rng = SplitMix64::forIndices(
        {kPixelStream, s.seed, static_cast<uint64_t>(pass),
         static_cast<uint64_t>(y) * static_cast<uint64_t>(s.width) + static_cast<uint64_t>(x)});
    const double u = rng.uniform(), v = rng.uniform();
    return rays(x + u, y + v);
}

// The plane of the face the last point lay on (vis::facePlane), formed again only when the face
// changes: consecutive pixels mostly share a face, and a table of every face's plane would cost
// 120 bytes a face (100 MB on the dragon).
class LastFacePlane {
  public:
    explicit LastFacePlane(const vis::PolygonMesh& mesh) : mesh_(mesh) {}
    const vis::PlaneOrient& of(uint32_t face) {
        if (face != face_) {
            plane_ = vis::facePlane(mesh_, face).orient();
            face_ = face;
        }
        return plane_;
    }

  private:
    const vis::PolygonMesh& mesh_;
    uint32_t face_ = UINT32_MAX;
    vis::PlaneOrient plane_;
};

// What every tile of one pass reads.
struct PassInputs {
    const Scene& scene;
    const EmbreeScene& bvh;
    const VisibilityStore& store;
    const DirectLighting& lighting;
    const std::vector<Vec3>& faceNormal;  // unit, per face
    const std::vector<Vec3>& faceOrigin;  // first vertex, per face
    const CameraRays& rays;
    const RenderSettings& settings;
    int pass = 0;
    int samples = 0;  // shadow rays per light of the sampled and reference methods
    bool exact = false;
    // The pixel cells whose query reached the work limit in the film's earlier passes
    // (ExactScratch::overLimitBefore).
    const std::unordered_set<uint64_t>* overLimitBefore = nullptr;
    // Of them, those whose light-edge attempt failed too (ExactScratch::edgeFailedBefore), and
    // those where it declined (ExactScratch::edgeDeclinedBefore).
    const std::unordered_set<uint64_t>* edgeFailedBefore = nullptr;
    const std::unordered_set<uint64_t>* edgeDeclinedBefore = nullptr;
    // Exact: this pass's answer per (pixel, light) cell (ExactScratch::answers), or null.
    uint8_t* answers = nullptr;
    // Exact: what each cell's evaluation saw of its light (ExactScratch::seen), or null.
    uint8_t* seen = nullptr;
};

// One thread's share of a pass: per tile, traces the primary rays, then shades the hits into the
// image. The buffers are reused from tile to tile; what the tiles used accumulates in `scratch`
// (pairs, evaluations) and `faces`.
class TileShader {
  public:
    // `pooled`: this thread's query workspace, lent to scratch.query for the shader's life.
    TileShader(const PassInputs& in, bool buildMissing, vis::FromPointQuery& pooled)
        : in_(in), pooled_(pooled) {
        std::swap(scratch.query, pooled_);
        scratch.query.setWorkLimit(in.settings.exactWorkLimit);
        scratch.overLimitBefore = in.overLimitBefore;
        scratch.edgeFailedBefore = in.edgeFailedBefore;
        scratch.edgeDeclinedBefore = in.edgeDeclinedBefore;
        // (With no work limit no path gives up: nothing is left to the light-edge path.)
        scratch.lightEdgeWorkLimit =
            in.settings.exactWorkLimit != 0 ? in.settings.lightEdgeWorkLimit : 0;
        scratch.answers = in.answers;
        scratch.seen = in.seen;
        vis::FromPointQuery::ChainOptions chain;
        chain.minOccluders = in.settings.chainMinOccluders;
        scratch.query.setChainOptions(chain);
        scratch.buildMissing = buildMissing;
    }
    ~TileShader() { std::swap(scratch.query, pooled_); }
    TileShader(const TileShader&) = delete;
    TileShader& operator=(const TileShader&) = delete;

    void trace(const Tile& tile) {
        hits_.clear();
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x) {
                const Ray ray = primaryRay(in_.rays, in_.settings, in_.pass, x, y);
                hits_.push_back({ray, in_.bvh.intersect(ray.origin, ray.direction)});
            }
        }
    }

    // The traced tile's points, shaded group by group for the exact method, a group being the
    // points of one receiver patch in one region cell of the tile: the query then decides once per
    // group the nodes that send all of its points the same way (ExactScratch::regionCorners). Each
    // pixel's value does not depend on the order (its random numbers are its own).
    void shade(const Tile& tile, std::vector<Vec3>& image) {
        collectPoints(tile);
        orderPoints();
        auto same = [&](size_t a, size_t b) {
            const TilePoint &p = points_[order_[a]], &q = points_[order_[b]];
            return p.group == q.group && p.cell == q.cell;
        };
        for (size_t g = 0; g < order_.size();) {
            size_t end = g + 1;
            while (end < order_.size() && same(end, g)) ++end;
            shadeGroup(g, end, image);
            g = end;
        }
        scratch.regionCorners.clear();
        scratch.pointKey.reset();
    }

    ExactScratch scratch;
    std::vector<uint32_t> faces;  // the faces seen, in tile order (repeats in a row collapsed)

  private:
    struct PrimaryHit {
        Ray ray;
        std::optional<EmbreeScene::Hit> hit;
    };
    struct TilePoint {
        int x = 0, y = 0;
        SurfacePoint point;
        // Receiver face and the patch field of its first light's key (a refined patch's
        // sub-patch: PatchLayout::keyAt), and the region cell (exact method).
        uint64_t group = 0;
        uint32_t cell = 0;
        std::optional<PairKey> firstKey;  // that key (ExactScratch::pointKey)
    };

    // order_: the indices of points_ in the order they are shaded, for the exact method grouped
    // by group (in the order of their first point) and within a group by region cell, each
    // group's points in tile order: a counting sort by (group's rank, cell), linear in the
    // points (a comparison sort of the points was some 4% of the Cornell box's render).
    void orderPoints() {
        order_.resize(points_.size());
        if (!in_.exact) {
            for (uint32_t i = 0; i < points_.size(); ++i) order_[i] = i;
            return;
        }
        constexpr uint32_t kCells = (kTileSize / kRegionCell) * (kTileSize / kRegionCell);
        groups_.clear();
        bucketOf_.resize(points_.size());
        for (size_t i = 0; i < points_.size(); ++i) {
            uint32_t rank = 0;
            if (i > 0 && points_[i].group == points_[i - 1].group) {
                rank = bucketOf_[i - 1] / kCells;
            } else {
                rank = static_cast<uint32_t>(
                    std::find(groups_.begin(), groups_.end(), points_[i].group) - groups_.begin());
                if (rank == groups_.size()) groups_.push_back(points_[i].group);
            }
            bucketOf_[i] = rank * kCells + points_[i].cell;
        }
        bucketStart_.assign(groups_.size() * kCells + 1, 0);
        for (uint32_t b : bucketOf_) ++bucketStart_[b + 1];
        for (size_t b = 1; b < bucketStart_.size(); ++b) bucketStart_[b] += bucketStart_[b - 1];
        for (uint32_t i = 0; i < points_.size(); ++i) order_[bucketStart_[bucketOf_[i]]++] = i;
    }

    void collectPoints(const Tile& tile) {
        points_.clear();
        LastFacePlane plane{in_.scene.mesh};
        uint32_t hintFace = UINT32_MAX, hintPatch = vis::ReceiverPatches::kNoHint;
        size_t i = 0;
        for (int y = tile.y0; y < tile.y1; ++y) {
            for (int x = tile.x0; x < tile.x1; ++x, ++i) {
                const PrimaryHit& ph = hits_[i];
                if (!ph.hit) continue;  // background: black
                const uint32_t f = ph.hit->face;
                const Vec3 n = in_.faceNormal[f];
                // A receiver sees only its face's front hemisphere, and a light emits only to its
                // front: a face seen from behind is black.
                if (!(dot(ph.ray.direction, n) < 0)) continue;
                if (faces.empty() || faces.back() != f) faces.push_back(f);
                TilePoint tp;
                tp.x = x;
                tp.y = y;
                SurfacePoint& p = tp.point;
                p.face = f;
                p.input = p.x = surfacePoint(ph.hit->point, n, in_.faceOrigin[f]);
                // The exact method answers the point on the face's closed front side, every path
                // the same one (shading_point.h); the sampled ones trace from the projection.
                if (in_.exact) p.x = vis::answeredPoint(plane.of(f), p.input).at;
                p.n = n;
                p.wo = -ph.ray.direction;
                p.material = &in_.scene.material(f);
                p.kd = in_.scene.kdAt(f, p.input);
                if (in_.exact) {
                    tp.cell = static_cast<uint32_t>(((y - tile.y0) / kRegionCell) *
                                                        (kTileSize / kRegionCell) +
                                                    (x - tile.x0) / kRegionCell);
                    const std::vector<uint32_t>& lights = in_.scene.lights;
                    const auto light = std::find_if(lights.begin(), lights.end(),
                                                    [f](uint32_t l) { return l != f; });
                    // The previous point's patch first (ReceiverPatches::find): neighbouring
                    // pixels mostly share one, and one exact test then replaces the lookup.
                    const uint32_t hint = f == hintFace ? hintPatch : vis::ReceiverPatches::kNoHint;
                    if (light != lights.end())
                        tp.firstKey = in_.store.layout().keyAt(f, p.x, *light, hint);
                    const uint32_t patch = tp.firstKey
                                               ? tp.firstKey->patch
                                               : in_.store.layout().patches(f).find(p.x, hint);
                    hintFace = f;
                    hintPatch = tp.firstKey ? PatchLayout::patchOf(*tp.firstKey) : patch;
                    tp.group = (static_cast<uint64_t>(f) << 32) | patch;
                }
                points_.push_back(tp);
            }
        }
    }

    void shadeGroup(size_t begin, size_t end, std::vector<Vec3>& image) {
        if (in_.exact) {
            vis::Bounds3 box;
            for (size_t q = begin; q < end; ++q) box.add(points_[order_[q]].point.x);
            boxCorners(box, scratch.regionCorners);
            scratch.regionId = ++regionCounter_;
        }
        const RenderSettings& settings = in_.settings;
        for (size_t q = begin; q < end; ++q) {
            const TilePoint& tp = points_[order_[q]];
            const SurfacePoint& p = tp.point;
            const int x = tp.x, y = tp.y;
            Vec3 radiance = p.material->isEmissive() ? p.material->ke : Vec3{};
            SplitMix64 rng = SplitMix64::forIndices(
                {kLightStream, settings.lightSeed, static_cast<uint64_t>(in_.pass),
                 static_cast<uint64_t>(y) * static_cast<uint64_t>(settings.width) +
                     static_cast<uint64_t>(x)});
            if (in_.exact) {
                scratch.pixel = static_cast<uint64_t>(y) * static_cast<uint64_t>(settings.width) +
                                static_cast<uint64_t>(x);
                scratch.pointKey = tp.firstKey;
                radiance += in_.lighting.exactAreaLights(p, settings.glossySamples,
                                                         settings.lightSamples, rng, scratch);
            } else {
                // One point in ExactScratch::kTimedEvery timed, as exact evaluations are
                // (EvaluationCosts::sampledNs).
                const bool timed = scratch.timeNext();
                const auto start = timed ? Clock::now() : Clock::time_point{};
                radiance += in_.lighting.sampledAreaLights(p, in_.samples, rng);
                if (timed) scratch.evaluations.costs.sampledNs.addSince(start);
            }
            radiance += in_.lighting.pointLights(p);
            image[static_cast<size_t>(y) * settings.width + x] = radiance;
        }
    }

    const PassInputs& in_;
    vis::FromPointQuery& pooled_;
    std::vector<PrimaryHit> hits_;
    std::vector<TilePoint> points_;
    std::vector<uint32_t> order_;
    std::vector<uint64_t> groups_;                  // orderPoints' scratch
    std::vector<uint32_t> bucketOf_, bucketStart_;  // (the same)
    uint64_t regionCounter_ = 0;
};

// What one pass's tiles found, merged under the lock as each task ends.
struct SharedFindings {
    std::mutex mutex;
    PassFindings all;

    void add(const TileShader& shader) {
        const ExactScratch& scratch = shader.scratch;
        std::lock_guard lock(mutex);
        auto append = [](auto& to, const auto& from) {
            to.insert(to.end(), from.begin(), from.end());
        };
        append(all.usedKeys, scratch.used);
        append(all.facesSeen, shader.faces);
        all.evaluations += scratch.evaluations;
        append(all.directKeys, scratch.usedDirect);
        append(all.overLimitNow, scratch.overLimitNow);
        append(all.overLimitTrees, scratch.overLimitTrees);
        append(all.edgeFailedNow, scratch.edgeFailedNow);
        append(all.edgeDeclinedNow, scratch.edgeDeclinedNow);
    }
};

// The tiles a process was handed (ProgressiveRenderer::shadeTiles), taken by its threads as a
// pass's TileSchedule is: each tile's thread time kept by its place in the list.
class TileList {
  public:
    TileList(std::span<const int> tiles, std::vector<int64_t>& costNs)
        : tiles_(tiles), costNs_(costNs) {
        costNs_.assign(tiles.size(), 0);
        for (size_t i = 0; i < tiles.size(); ++i) placeOf_[tiles[i]] = i;
    }
    int next() {
        const size_t i = next_.fetch_add(1, std::memory_order_relaxed);
        return i < tiles_.size() ? tiles_[i] : -1;
    }
    void record(int index, int64_t ns) { costNs_[placeOf_.at(index)] = ns; }

  private:
    std::span<const int> tiles_;
    std::vector<int64_t>& costNs_;
    std::unordered_map<int, size_t> placeOf_;
    std::atomic<size_t> next_{0};
};

// One worker's share of a pass: the tiles it takes from the schedule, traced and shaded into
// image, each tile's thread time recorded in the schedule and added to primaryNs and shadingNs
// (when not null); false when cancelled before a tile. `Tiles`: a TileSchedule or a TileList.
template <typename Tiles>
bool shadeFromSchedule(TileShader& shader, Tiles& schedule, const RenderSettings& settings,
                       std::vector<Vec3>& image, const std::atomic<bool>* cancel,
                       std::atomic<int64_t>* primaryNs, std::atomic<int64_t>* shadingNs) {
    auto ns = [](Clock::time_point a, Clock::time_point b) {
        return std::chrono::duration_cast<std::chrono::nanoseconds>(b - a).count();
    };
    for (int t = schedule.next(); t >= 0; t = schedule.next()) {
        if (cancel != nullptr && cancel->load(std::memory_order_relaxed)) return false;
        const Tile tile = tileAt(t, settings);
        const auto a = Clock::now();
        shader.trace(tile);
        const auto b = Clock::now();
        shader.shade(tile, image);
        const auto c = Clock::now();
        schedule.record(t, ns(a, c));
        if (primaryNs != nullptr) {
            primaryNs->fetch_add(ns(a, b), std::memory_order_relaxed);
            shadingNs->fetch_add(ns(b, c), std::memory_order_relaxed);
        }
    }
    return true;
}

// A pass's byte per (pixel, light) cell added to the film's counts per pixel (none when `cells`
// is empty: not recorded).
template <size_t N>
void addCells(std::vector<std::array<uint32_t, N>>& counts, const std::vector<uint8_t>& cells,
              size_t pixels, size_t lights) {
    if (cells.empty()) return;
    if (counts.size() != pixels) counts.assign(pixels, {});
    for (size_t cell = 0; cell < cells.size(); ++cell)
        if (cells[cell] != ExactScratch::kNoAnswer) ++counts[cell / lights][cells[cell]];
}

// A whole pass added to the film (reset first on the film's first pass): its image, and the
// answers of its (pixel, light) cells and what they saw of their lights when recorded.
void addPass(Film& film, int pass, int w, int h, const std::vector<Vec3>& image,
             const std::vector<uint8_t>& answers, const std::vector<uint8_t>& seen, size_t lights) {
    if (pass == 0) film.reset(w, h);
    for (size_t i = 0; i < image.size(); ++i) film.sum[i] += image[i];
    addCells(film.answers, answers, image.size(), lights);
    addCells(film.seen, seen, image.size(), lights);
    ++film.passes;
}

}  // namespace

const char* toString(DirectMethod m) {
    switch (m) {
        case DirectMethod::Exact:
            return "exact";
        case DirectMethod::Sampled:
            return "sampled";
        case DirectMethod::Reference:
            return "reference";
    }
    return "?";
}

void Film::reset(int w, int h) {
    width = w;
    height = h;
    passes = 0;
    sum.assign(static_cast<size_t>(w) * static_cast<size_t>(h), Vec3{});
    answers.clear();
    seen.clear();
}

Vec3 Film::mean(int x, int y) const {
    if (passes == 0) return {};
    return sum[static_cast<size_t>(y) * width + x] / passes;
}

// Thread time spent per phase in one pass, summed over tiles.
struct ProgressiveRenderer::PassTimes {
    std::atomic<int64_t> primaryNs{0}, shadingNs{0};
    double wall = 0;
    double refine = 0;  // of wall, refining after the pass (refineWhere)
    double refineCpu = 0;
};

struct ProgressiveRenderer::QueryPool {
    tbb::enumerable_thread_specific<vis::FromPointQuery> perThread;
};

ProgressiveRenderer::ProgressiveRenderer(const Scene& scene, const EmbreeScene& bvh,
                                         VisibilityStore& store)
    : scene_(scene),
      bvh_(bvh),
      store_(store),
      lighting_(std::make_unique<DirectLighting>(scene, bvh, &store)),
      queries_(std::make_unique<QueryPool>()) {
    faceNormal_.reserve(scene.faceCount());
    faceOrigin_.reserve(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) {
        faceNormal_.push_back(normalize(scene.mesh.faceAreaNormal(f)));
        faceOrigin_.push_back(
            scene.mesh.faces[f].empty() ? Vec3{} : scene.mesh.vertices[scene.mesh.faces[f][0]]);
    }
    faceSeen_.assign(scene.faceCount(), 0);
}

ProgressiveRenderer::~ProgressiveRenderer() = default;

void ProgressiveRenderer::recordUse(const std::vector<PairKey>& keys,
                                    const std::vector<uint32_t>& faces,
                                    const RenderSettings& settings,
                                    const ExactEvaluations& evaluations,
                                    const std::vector<PairKey>& directKeys) {
    std::lock_guard lock(mutex_);
    evaluations_ += evaluations;
    minTreeSamples_ = settings.minTreeSamples;
    directUsed_.insert(directKeys.begin(), directKeys.end());
    exactWorkLimit_ = settings.exactWorkLimit;
    lightEdgeWorkLimit_ = settings.exactWorkLimit != 0 ? settings.lightEdgeWorkLimit : 0;
    usedKeys_.insert(keys.begin(), keys.end());
    for (uint32_t f : faces) faceSeen_[f] = 1;
    rendered_ = true;
    method_ = settings.method;
    lightSamples_ = settings.method == DirectMethod::Reference ? settings.referenceSamples
                                                               : settings.lightSamples;
    glossySamples_ = settings.glossySamples;
}

void ProgressiveRenderer::resetEffects() {
    std::lock_guard lock(mutex_);
    usedKeys_.clear();
    faceSeen_.assign(scene_.faceCount(), 0);
    rendered_ = false;
    evaluations_ = {};
    directUsed_.clear();
    refinedParents_.clear();
    refineNotWorth_.clear();
    refinedTrees_ = 0;
    refineSeconds_ = 0;
    groupedNoTree_.clear();
    groupedNoTreeFaces_ = 0;
}

double ProgressiveRenderer::prepare(const Camera& camera, const RenderSettings& settings,
                                    const std::atomic<bool>* cancel) {
    validate(settings);
    if (settings.method != DirectMethod::Exact) return 0;
    const auto t0 = Clock::now();
    auto cancelled = [cancel] {
        return cancel != nullptr && cancel->load(std::memory_order_relaxed);
    };

    // The pairs the primary hits of every pass need (each pass jitters its rays: on a finely
    // tessellated mesh a pixel covers many receivers, and later passes hit others).
    const CameraRays rays(camera, settings.width, settings.height);
    // With a tree for every pair (minTreeSamples 0) every pass is traced, so that the passes find
    // all their trees built; otherwise the first two give the counts.
    const int passesTraced =
        settings.minTreeSamples == 0 ? settings.spp : std::min(settings.spp, 2);
    std::mutex mutex;
    std::unordered_map<PairKey, uint64_t, PairKeyHash> needed;  // samples per pair
    std::vector<uint32_t> facesSeen;
    tbb::parallel_for(
        tbb::blocked_range<int>(0, tileCount(settings), 1),
        [&](const tbb::blocked_range<int>& range) {
            std::unordered_map<PairKey, uint64_t, PairKeyHash> local;
            std::vector<uint32_t> faces;
            LastFacePlane plane{scene_.mesh};
            for (int t = range.begin(); t != range.end(); ++t) {
                if (cancelled()) return;
                const Tile tile = tileAt(t, settings);
                for (int pass = 0; pass < passesTraced; ++pass)
                    for (int y = tile.y0; y < tile.y1; ++y) {
                        for (int x = tile.x0; x < tile.x1; ++x) {
                            const Ray ray = primaryRay(rays, settings, pass, x, y);
                            const auto hit = bvh_.intersect(ray.origin, ray.direction);
                            if (!hit) continue;
                            const uint32_t f = hit->face;
                            const Vec3 n = faceNormal_[f];
                            if (!(dot(ray.direction, n) < 0)) continue;  // back side
                            if (faces.empty() || faces.back() != f) faces.push_back(f);
                            // The point the exact method answers (collectPoints).
                            const Vec3 xs =
                                vis::answeredPoint(plane.of(f),
                                                   surfacePoint(hit->point, n, faceOrigin_[f]))
                                    .at;
                            for (uint32_t lf : scene_.lights)
                                if (lf != f) ++local[store_.layout().keyAt(f, xs, lf)];
                        }
                    }
            }
            std::lock_guard lock(mutex);
            for (const auto& [key, count] : local) needed[key] += count;
            facesSeen.insert(facesSeen.end(), faces.begin(), faces.end());
        });
    if (cancelled()) return seconds(t0, Clock::now());
    // A pair the image samples fewer than minTreeSamples times gets no tree: its points are
    // evaluated directly (FromPointQuery::runDirect), which costs no precompute. The counts come
    // from the first passes (scaled to all of them), so that prepare does not trace the whole
    // image's rays twice; a pair no traced pass hit is rare, and evaluated directly too.
    std::vector<PairKey> keys, all;
    for (const auto& [key, count] : needed) {
        all.push_back(key);
        const uint64_t estimate = count * static_cast<uint64_t>(settings.spp) / passesTraced;
        if (estimate >= settings.minTreeSamples || store_.find(key) != nullptr) keys.push_back(key);
    }
    // Of those, a pair whose shaft is large and mostly in face groups gets no tree either: its
    // partial tree would be answered by the direct path with the groups (groupsWillAnswer).
    const bool skipGrouped = settings.minTreeSamples > 0 && settings.groupedShaftMin > 0;
    std::vector<std::pair<PairKey, size_t>> grouped;  // by mutex: the pairs left, their shafts
    std::vector<PairKey> toBuild;                     // (the same) those to build
    tbb::parallel_for(tbb::blocked_range<size_t>(0, keys.size(), 1),
                      [&](const tbb::blocked_range<size_t>& range) {
                          for (size_t i = range.begin(); i != range.end(); ++i) {
                              if (cancelled()) return;
                              if (store_.find(keys[i]) != nullptr) continue;
                              if (skipGrouped) {
                                  const auto shaft = store_.shaftCount(keys[i]);
                                  if (groupsWillAnswer(shaft, settings.groupedShaftMin)) {
                                      std::lock_guard lock(mutex);
                                      grouped.emplace_back(keys[i], shaft.faces);
                                      continue;
                                  }
                              }
                              if (cluster_ != nullptr) {
                                  std::lock_guard lock(mutex);
                                  toBuild.push_back(keys[i]);
                              } else {
                                  store_.getOrBuild(keys[i]);
                              }
                          }
                      });
    if (cluster_ != nullptr && !cancelled()) {
        // In key order, so that the ranks' batches do not depend on this process's threads.
        std::sort(toBuild.begin(), toBuild.end());
        cluster_->buildTrees(toBuild);
    }
    {
        std::lock_guard lock(mutex_);
        groupedShaftMin_ = settings.groupedShaftMin;
        for (const auto& [key, faces] : grouped)
            if (groupedNoTree_.insert(key).second) groupedNoTreeFaces_ += faces;
    }
    recordUse(all, facesSeen, settings);
    directMissing_ = settings.minTreeSamples > 0;
    return seconds(t0, Clock::now());
}

bool ProgressiveRenderer::renderPass(const Camera& camera, const RenderSettings& settings,
                                     Film& film, const std::atomic<bool>* cancel) {
    return renderPassTimed(camera, settings, film, cancel, nullptr);
}

void ProgressiveRenderer::shadeTiles(const Camera& camera, const RenderSettings& settings, int pass,
                                     const PassCells& cells, std::span<const int> tiles,
                                     std::vector<Vec3>& pixels, std::vector<int64_t>& costNs,
                                     PassFindings& found, const std::atomic<bool>* cancel) {
    validate(settings);
    const int w = settings.width, h = settings.height;
    std::vector<Vec3> image(static_cast<size_t>(w) * h);
    const CameraRays rays(camera, w, h);
    const bool exact = settings.method == DirectMethod::Exact;
    const PassInputs in{scene_,
                        bvh_,
                        store_,
                        *lighting_,
                        faceNormal_,
                        faceOrigin_,
                        rays,
                        settings,
                        pass,
                        settings.method == DirectMethod::Reference ? settings.referenceSamples
                                                                   : settings.lightSamples,
                        exact,
                        cells.overLimit,
                        cells.edgeFailed,
                        cells.edgeDeclined,
                        nullptr,
                        nullptr};
    // As rank 0's prepare() leaves it: with minTreeSamples the pairs without a tree are evaluated
    // point by point.
    const bool buildMissing = !(exact && settings.minTreeSamples > 0);
    TileList list(tiles, costNs);
    SharedFindings shared;
    tbb::parallel_for(0, tbb::this_task_arena::max_concurrency(), [&](int) {
        TileShader shader(in, buildMissing, queries_->perThread.local());
        shadeFromSchedule(shader, list, settings, image, cancel, nullptr, nullptr);
        shared.add(shader);
    });
    pixels.clear();
    for (const int t : tiles) {
        const Tile tile = tileAt(t, settings);
        for (int y = tile.y0; y < tile.y1; ++y)
            for (int x = tile.x0; x < tile.x1; ++x)
                pixels.push_back(image[static_cast<size_t>(y) * w + x]);
    }
    found = std::move(shared.all);
    found.lightEdgeIndices = lighting_->lightEdgesBuilt();
}

bool ProgressiveRenderer::renderPassTimed(const Camera& camera, const RenderSettings& settings,
                                          Film& film, const std::atomic<bool>* cancel,
                                          PassTimes* times) {
    validate(settings);
    const auto t0 = Clock::now();
    const int w = settings.width, h = settings.height;
    const int pass =
        film.width == w && film.height == h && film.sum.size() == static_cast<size_t>(w) * h
            ? film.passes
            : 0;
    std::vector<Vec3> image(static_cast<size_t>(w) * h);
    // This pass's answers, a byte per (pixel, light) cell, added to the film's counts once the
    // pass is whole (a cancelled pass leaves the film as it was).
    const size_t lights = scene_.lights.size();
    const bool answering =
        settings.method == DirectMethod::Exact && settings.recordAnswers && lights > 0;
    passAnswers_.assign(answering ? image.size() * lights : 0, ExactScratch::kNoAnswer);
    const bool seeing =
        settings.method == DirectMethod::Exact && settings.recordVisibleFraction && lights > 0;
    passSeen_.assign(seeing ? image.size() * lights : 0, ExactScratch::kNoAnswer);
    std::atomic<bool> cancelled{false};
    SharedFindings shared;
    // The cells of the film's earlier passes, for this film, work limit and store only: with
    // trees added since (the viewer's background precompute) a remembered pixel's pair may have
    // one now, whose walk is far cheaper than the direct path that reached the limit, so every
    // pixel is tried again.
    const size_t trees = store_.treeCount();
    if (pass == 0 || overLimitCellsLimit_ != settings.exactWorkLimit ||
        overLimitCellsEdgeLimit_ != settings.lightEdgeWorkLimit || overLimitCellsTrees_ != trees) {
        overLimitCells_.clear();
        edgeFailedCells_.clear();
        edgeDeclinedCells_.clear();
    }
    overLimitCellsLimit_ = settings.exactWorkLimit;
    overLimitCellsEdgeLimit_ = settings.lightEdgeWorkLimit;
    overLimitCellsTrees_ = trees;
    const CameraRays rays(camera, w, h);
    const PassInputs in{scene_,
                        bvh_,
                        store_,
                        *lighting_,
                        faceNormal_,
                        faceOrigin_,
                        rays,
                        settings,
                        pass,
                        settings.method == DirectMethod::Reference ? settings.referenceSamples
                                                                   : settings.lightSamples,
                        settings.method == DirectMethod::Exact,
                        &overLimitCells_,
                        &edgeFailedCells_,
                        &edgeDeclinedCells_,
                        answering ? passAnswers_.data() : nullptr,
                        seeing ? passSeen_.data() : nullptr};

    // Each worker takes tiles from the schedule until none is left (tile_schedule.h).
    schedule_.start(w, h);
    std::atomic<bool> stopHere{false};
    const std::atomic<bool>* stop = cluster_ != nullptr ? &stopHere : cancel;
    const auto shadeHere = [&] {
        tbb::parallel_for(0, tbb::this_task_arena::max_concurrency(), [&](int) {
            TileShader shader(in, !directMissing_, queries_->perThread.local());
            if (!shadeFromSchedule(shader, schedule_, settings, image, stop,
                                   times != nullptr ? &times->primaryNs : nullptr,
                                   times != nullptr ? &times->shadingNs : nullptr)) {
                cancelled.store(true, std::memory_order_relaxed);
                return;
            }
            shared.add(shader);
        });
    };
    if (cluster_ == nullptr) {
        shadeHere();
    } else {
        // (Merged once the pass is whole: this process's threads add to `shared` meanwhile.)
        const PassCells cells{&overLimitCells_, &edgeFailedCells_, &edgeDeclinedCells_};
        PassFindings remote;
        if (!cluster_->shadePass(pass, w, h, cells, schedule_, image, shadeHere, stopHere, remote,
                                 cancel))
            cancelled.store(true);
        shared.all.add(remote);
        // The light-edge indices the other processes built: the summary counts them here too.
        for (const uint32_t k : remote.lightEdgeIndices)
            if (k < scene_.lights.size()) lighting_->buildLightEdges(k);
    }
    if (cancelled.load()) return false;
    schedule_.finish();

    const PassFindings& found = shared.all;
    overLimitCells_.insert(found.overLimitNow.begin(), found.overLimitNow.end());
    edgeFailedCells_.insert(found.edgeFailedNow.begin(), found.edgeFailedNow.end());
    edgeDeclinedCells_.insert(found.edgeDeclinedNow.begin(), found.edgeDeclinedNow.end());
    addPass(film, pass, w, h, image, passAnswers_, passSeen_, lights);
    recordUse(found.usedKeys, found.facesSeen, settings, found.evaluations, found.directKeys);
    // Refined between passes: the film of this pass is complete; the next one finds the trees.
    const auto r0 = Clock::now();
    const double cpu0 = times != nullptr ? processCpuSeconds() : 0;
    // A cancelled refinement keeps what it built.
    refineWhere(found.overLimitTrees, settings, settings.spp - (pass + 1), cancel);
    if (times != nullptr) {
        times->refine = seconds(r0, Clock::now());
        times->refineCpu = processCpuSeconds() - cpu0;  // nothing else runs meanwhile
        times->wall = seconds(t0, Clock::now());
    }
    return true;
}

bool ProgressiveRenderer::refineWhere(const std::vector<OverLimitPoint>& points,
                                      const RenderSettings& settings, int passesLeft,
                                      const std::atomic<bool>* cancel) {
    if (settings.method != DirectMethod::Exact || settings.refineLevels == 0 || points.empty() ||
        passesLeft <= 0)
        return true;
    const auto t0 = Clock::now();
    // Per sub-patch of a refinable tree's patch, this pass's sampled points in it, and the tree.
    std::map<PairKey, std::pair<uint64_t, PairKey>> subPatches;
    std::vector<std::pair<PairKey, uint64_t>> cells;  // per point considered: sub-patch, cell
    std::set<PairKey> refined;                        // the pairs refined
    for (const OverLimitPoint& p : points) {
        if (PatchLayout::refineLevel(p.key) >= settings.refineLevels) continue;
        if (!store_.layout().refine(p.key)) continue;
        refined.insert(p.key);
        const PairKey sub = store_.layout().subKeyAt(p.key, p.x);
        auto& [count, parent] = subPatches[sub];
        ++count;
        parent = p.key;
        cells.emplace_back(sub, p.cell);
    }
    // Built where it costs less than what sampling would cost there, both in shadow rays: a
    // sub-patch tree takes at most about what its parent's build took (the same budget, a
    // narrower shaft), and the passes left would sample about as many points there as this one
    // did. (A partial tree reached the budget, whatever its file kept of its statistics.)
    std::vector<PairKey> keys, notWorth;
    const double budget = static_cast<double>(store_.options().build.maxLpSolves);
    for (const auto& [sub, entry] : subPatches) {
        const PairRecord* parent = store_.find(entry.second);
        double lpSolves = parent != nullptr ? static_cast<double>(parent->stats.lpSolves) : budget;
        if (parent != nullptr && parent->tree.partial()) lpSolves = std::max(lpSolves, budget);
        const double buildRays = kRefineRaysPerTree + kRefineRaysPerLpSolve * lpSolves;
        const double samplingRays =
            static_cast<double>(entry.first) * passesLeft * settings.lightSamples;
        if (samplingRays * settings.refineCostShare >= buildRays)
            keys.push_back(sub);
        else
            notWorth.push_back(sub);
    }
    const size_t trees0 = store_.treeCount();
    std::atomic<bool> stopped{false};
    if (cluster_ != nullptr) {
        // Every process refines its layout as this one did, then the trees are built across them.
        cluster_->refined(std::vector<PairKey>(refined.begin(), refined.end()));
        std::vector<PairKey> missing;
        for (const PairKey& key : keys)
            if (store_.find(key) == nullptr) missing.push_back(key);
        if (!cluster_->buildTrees(missing)) stopped.store(true);
    } else {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, keys.size(), 1),
                          [&](const tbb::blocked_range<size_t>& range) {
                              for (size_t i = range.begin(); i != range.end(); ++i) {
                                  try {
                                      store_.getOrBuild(keys[i], cancel);
                                  } catch (const vis::BuildCancelled&) {
                                      stopped.store(true, std::memory_order_relaxed);
                                      return;
                                  }
                              }
                          });
    }
    // The next pass tries again the cells of the points whose sub-patch got a tree; the other
    // cells stay skipped (their pairs did not change), unless trees came from elsewhere too.
    const std::set<PairKey> built(keys.begin(), keys.end());
    for (const auto& [sub, cell] : cells)
        if (built.count(sub) != 0 && store_.find(sub) != nullptr) {
            overLimitCells_.erase(cell);
            edgeFailedCells_.erase(cell);
            edgeDeclinedCells_.erase(cell);
        }
    if (overLimitCellsTrees_ == trees0) overLimitCellsTrees_ = store_.treeCount();
    std::lock_guard lock(mutex_);
    for (const PairKey& key : keys) {
        refinedParents_.insert(subPatches[key].second);
        refineNotWorth_.erase(key);
    }
    refinedTrees_ += keys.size();
    refineNotWorth_.insert(notWorth.begin(), notWorth.end());
    refineSeconds_ += seconds(t0, Clock::now());
    return !stopped.load();
}

Film ProgressiveRenderer::render(const Camera& camera, const RenderSettings& settings,
                                 RenderTimes* times, const std::atomic<bool>* cancel) {
    validate(settings);
    const auto t0 = Clock::now();
    const double cpu0 = processCpuSeconds();
    Film film;
    film.reset(settings.width, settings.height);
    const double precompute = prepare(camera, settings, cancel);
    const double cpu1 = processCpuSeconds();
    double primary = 0, shading = 0, refine = 0, refineCpu = 0;
    for (int i = 0; i < settings.spp; ++i) {
        PassTimes pt;
        const bool done = renderPassTimed(camera, settings, film, cancel, &pt);
        refine += pt.refine;
        refineCpu += pt.refineCpu;
        if (!done) break;
        pt.wall -= pt.refine;
        // Thread time per phase, scaled so that the two phases add up to the pass's wall time.
        const double p = pt.primaryNs.load() * 1e-9, s = pt.shadingNs.load() * 1e-9;
        if (p + s > 0) {
            primary += pt.wall * p / (p + s);
            shading += pt.wall * s / (p + s);
        }
    }
    if (times != nullptr) {
        times->precompute = precompute + refine;
        times->refine = refine;
        times->primary = primary;
        times->shading = shading;
        times->total = seconds(t0, Clock::now());
        times->precomputeCpu = cpu1 - cpu0 + refineCpu;
        times->totalCpu = processCpuSeconds() - cpu0;
    }
    return film;
}

EffectsSummary ProgressiveRenderer::effects() const {
    EffectsSummary s;
    s.areaLights = scene_.lights.size();
    s.defaultLight = scene_.defaultLight.has_value();
    s.pointLights = scene_.pointLights.size();
    const vis::ClosedSurfaces& surfaces = bvh_.faceClusters().surfaces();
    s.components = surfaces.componentCount();
    s.closedComponents = surfaces.closedCount();
    s.closedFaces = surfaces.closedFaces();
    s.faces = scene_.faceCount();
    std::lock_guard lock(mutex_);
    if (!rendered_) return s;
    s.method = toString(method_);
    s.lightSamples = lightSamples_;  // exact: the points over the work limit
    s.exactEvaluations = evaluations_.all;
    s.sampledEvaluations = evaluations_.sampled;
    s.sampledDirectEvaluations = evaluations_.sampledDirect;
    s.overLimitAt = evaluations_.overLimitAt;
    s.workAt = evaluations_.workAt;
    s.exactWorkLimit = exactWorkLimit_;
    s.lightEdgeWorkLimit = lightEdgeWorkLimit_;
    s.lightEdgeEvaluations = evaluations_.lightEdges;
    s.lightEdgeNotTaken = evaluations_.lightEdgesNotTaken;
    s.lightEdgeOverLimit = evaluations_.lightEdgesOverLimit;
    s.lightEdgeSkipped = evaluations_.lightEdgesSkipped;
    s.lightEdgeDeclinedBy = evaluations_.lightEdgesDeclinedBy;
    s.lightEdgeOverLimitAt = evaluations_.lightEdgesOverLimitAt;
    s.retriedEvaluations = evaluations_.retried;
    s.retriedOverLimit = evaluations_.retriedOverLimit;
    s.lightEdgeIndex = lighting_->lightEdgeStats();
    s.pairsDirect = directUsed_.size();
    s.directEvaluations = evaluations_.direct;
    s.directGroupedEvaluations = evaluations_.directGrouped;
    s.directSolidEvaluations = evaluations_.directSolid;
    s.directHiddenBySolidEvaluations = evaluations_.directHiddenBySolid;
    s.partialByGroupsEvaluations = evaluations_.partialByGroups;
    s.costs = evaluations_.costs;
    s.minTreeSamples = minTreeSamples_;
    s.pairsGroupedNoTree = groupedNoTree_.size();
    s.groupedNoTreeFaces = groupedNoTreeFaces_;
    s.groupedShaftMin = groupedShaftMin_;
    s.glossySamples = method_ == DirectMethod::Exact ? glossySamples_ : 0;
    // Materials of the faces the image saw.
    std::vector<char> materialSeen(scene_.materials.size() + 1, 0);  // last slot: the default
    for (uint32_t f = 0; f < scene_.faceCount(); ++f) {
        if (!faceSeen_[f]) continue;
        const int32_t m = f < scene_.faceMaterial.size() ? scene_.faceMaterial[f] : -1;
        materialSeen[m >= 0 ? static_cast<size_t>(m) : scene_.materials.size()] = 1;
    }
    for (size_t m = 0; m < materialSeen.size(); ++m) {
        if (!materialSeen[m]) continue;
        const Material& mat = m < scene_.materials.size() ? scene_.materials[m] : Material{};
        if (method_ == DirectMethod::Exact && !mat.isGlossy())
            ++s.materialsAnalytic;
        else
            ++s.materialsSampled;
    }
    if (method_ != DirectMethod::Exact) return s;
    s.refinedPairs = refinedParents_.size();
    s.refineNotWorth = refineNotWorth_.size();
    s.refinedTrees = refinedTrees_;
    s.refineSeconds = refineSeconds_;
    // Pairs by kind, from the trees the images used (a refined patch's sub-patch trees apart).
    size_t patchKeys = 0;
    for (const PairKey& key : usedKeys_) {
        if (PatchLayout::refineLevel(key) > 0) {
            ++s.refinedTreesUsed;
            continue;
        }
        ++patchKeys;
        const PairRecord* record = store_.find(key);
        if (record == nullptr) continue;
        switch (record->tree.kind) {
            case vis::PairKind::BackFacing:
                ++s.pairsBackFacing;
                break;
            case vis::PairKind::FullyVisible:
                ++s.pairsFullyVisible;
                break;
            case vis::PairKind::FullyHidden:
                ++s.pairsFullyHidden;
                break;
            case vis::PairKind::Penumbra:
                ++s.pairsPenumbra;
                if (record->tree.partial()) {
                    ++s.pairsPartial;
                    s.deferredOccluders += record->tree.deferred.size();
                }
                break;
        }
    }
    // Lights that no pair the image used is lit by.
    std::vector<size_t> lightOfFace(scene_.faceCount(), SIZE_MAX);
    for (size_t k = 0; k < scene_.lights.size(); ++k) lightOfFace[scene_.lights[k]] = k;
    struct LightPairs {
        size_t backFacing = 0, hidden = 0, lit = 0;
    };
    std::vector<LightPairs> perLight(scene_.lights.size());
    for (const PairKey& key : usedKeys_) {
        const PairRecord* record = store_.find(key);
        if (record == nullptr || lightOfFace[key.lightFace] == SIZE_MAX) continue;
        LightPairs& l = perLight[lightOfFace[key.lightFace]];
        const vis::HistoryTree& t = record->tree;
        if (t.kind == vis::PairKind::BackFacing)
            ++l.backFacing;
        else if (t.kind == vis::PairKind::FullyHidden ||
                 (t.kind == vis::PairKind::Penumbra && t.leafCount(true) == 0))
            ++l.hidden;
        else
            ++l.lit;
    }
    for (const PairKey& key : directUsed_)
        if (lightOfFace[key.lightFace] != SIZE_MAX) ++perLight[lightOfFace[key.lightFace]].lit;
    for (size_t k = 0; k < perLight.size(); ++k)
        if (perLight[k].lit == 0 && perLight[k].hidden > 0)
            s.hiddenLights.push_back(hiddenLightWarning(scene_, k, perLight[k].backFacing,
                                                        perLight[k].hidden,
                                                        "every receiver the image sees"));
    // Every (receiver patch, light) pair of the scene that no image needed.
    size_t total = 0;
    for (uint32_t f = 0; f < scene_.faceCount(); ++f) {
        const size_t patches = store_.layout().patchCount(f);
        for (uint32_t lf : scene_.lights)
            if (lf != f) total += patches;
    }
    s.pairsNeverSeen = total > patchKeys ? total - patchKeys : 0;
    return s;
}

}  // namespace penumbra
