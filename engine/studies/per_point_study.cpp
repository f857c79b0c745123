#include "engine/studies/per_point_study.h"

#include <algorithm>
#include <optional>
#include <set>
#include <vector>

#include "engine/precompute/point_inspection.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/scene/surface_samples.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/visible_outline.h"

namespace penumbra {
namespace per_point_detail {

struct Sample {
    uint32_t face;
    Vec3 x;
    const PairRecord* rec;  // the tree of (x's patch, light 0)
};

// The measurements over one set of points, each loop summing what it computes into `sink` (the
// checksum printed at the end), so that no loop is optimised away.
class PerPointMeasure {
  public:
    PerPointMeasure(const Scene& scene, const EmbreeScene& embree, std::vector<Sample> samples)
        : scene_(scene), mesh_(scene.mesh), embree_(embree), samples_(std::move(samples)) {}

    double meanUs(StudyClock::time_point since) const {
        return secondsBetween(since, StudyClock::now()) / samples_.size() * 1e6;
    }

    // The partial trees the points use, once each, and their silhouettes.
    void countSilhouettes(ChainStats& c) const {
        std::set<const vis::HistoryTree*> seen;
        for (const Sample& s : samples_) {
            const vis::HistoryTree& t = s.rec->tree;
            if (!t.partial() || !seen.insert(&t).second) continue;
            ++c.partialTrees;
            if (!t.silhouettes.usable()) continue;
            ++c.silhouetteTrees;
            c.silhouetteUses += t.silhouettes.totalUses;
            c.silhouetteKept += t.silhouettes.keptUses;
        }
    }

    // One untimed pass first: the timed loops after it (the product's, then Algorithm 1 only)
    // all start warm (the first pass over the points is some 20% slower on every scene). It
    // keeps each point's fragments for the visible region's boundary (what `penumbra query` and
    // the viewer show): their edges against the outline's loops and edges, and per point the
    // fragments' form factor (the renderer's) against the outline built and integrated
    // (Lambert's contour integral: the same value).
    OutlineStats measureOutline() {
        OutlineStats o;
        std::vector<std::vector<vis::Polygon3>> pieces;
        pieces.reserve(samples_.size());
        for (const Sample& s : samples_) {
            pieces.push_back(query_.run(mesh_, s.rec->tree, s.x).polygons());
            for (const vis::Polygon3& f : pieces.back()) o.fragmentEdges += f.size();
        }
        const auto f0 = StudyClock::now();
        for (size_t k = 0; k < samples_.size(); ++k) {
            const Vec3 n = normal(samples_[k]);
            for (const vis::Polygon3& f : pieces[k]) sink_ += vis::formFactor(samples_[k].x, n, f);
        }
        o.integrationUs = meanUs(f0);
        const auto b0 = StudyClock::now();
        for (size_t k = 0; k < samples_.size(); ++k) {
            const vis::VisibleOutline outline = vis::visibleOutline(pieces[k]);
            sink_ += vis::formFactorOfLoops(samples_[k].x, normal(samples_[k]), outline.loops);
            o.edges += outline.edges();
            o.loops += outline.loops.size();
        }
        o.outlineUs = meanUs(b0);
        return o;
    }

    // The product's query and its fragments' form factor at every point, with the chain's counts.
    void measureQuery(PerPointRow& row) {
        size_t visited = 0, fragments = 0;
        ChainStats& chain = row.chain;
        const auto q0 = StudyClock::now();
        for (const Sample& s : samples_) {
            const Vec3 n = normal(s);
            const vis::FragmentList& r = query_.run(mesh_, s.rec->tree, s.x);
            for (size_t i = 0; i < r.size(); ++i) sink_ += vis::formFactor(s.x, n, r[i]);
            visited += query_.nodesVisited();
            fragments += r.size();
            const vis::FromPointQuery::ChainCounts& c = query_.chainCounts();
            chain.manyOccluderPoints += c.occluderEdges > 0;
            chain.occluderEdges += c.occluderEdges;
            chain.boundaryEdges += c.boundaryEdges;
            chain.points += c.cells > 0;
            chain.silhouettePoints += query_.usedSilhouettes();
            chain.cells += c.cells;
            chain.crossingLabels += c.crossingLabels;
            if (c.cells > 0) chain.fragments += r.size();
        }
        row.exactUs = meanUs(q0);
        row.nodesPerQuery = static_cast<double>(visited) / samples_.size();
        row.fragmentsPerQuery = static_cast<double>(fragments) / samples_.size();
    }

    // The same points with every occluder clipped one by one (Algorithm 1 only).
    double measureOneByOne() {
        vis::FromPointQuery oneByOne;
        oneByOne.setChainOptions({0, 0});
        const auto o0 = StudyClock::now();
        for (const Sample& s : samples_) {
            const Vec3 n = normal(s);
            const vis::FragmentList& r = oneByOne.run(mesh_, s.rec->tree, s.x);
            for (size_t i = 0; i < r.size(); ++i) sink_ += vis::formFactor(s.x, n, r[i]);
        }
        return meanUs(o0);
    }

    // The distribution: each point timed alone.
    Quantiles measureEachPoint() {
        std::vector<double> eachUs;
        eachUs.reserve(samples_.size());
        for (const Sample& s : samples_) {
            const auto a = StudyClock::now();
            const Vec3 n = normal(s);
            const vis::FragmentList& r = query_.run(mesh_, s.rec->tree, s.x);
            for (size_t i = 0; i < r.size(); ++i) sink_ += vis::formFactor(s.x, n, r[i]);
            eachUs.push_back(secondsBetween(a, StudyClock::now()) * 1e6);
        }
        return quantiles(std::move(eachUs));
    }

    ClickLatency measureClicks() const {
        ClickLatency click;
        click.points = std::min<size_t>(samples_.size(), 200);
        std::vector<double> directMs;
        const uint64_t work = clickWorkPerLight(scene_.lights.size());
        for (size_t i = 0; i < click.points; ++i) {
            const auto a = StudyClock::now();
            const std::optional<PointInspection> p =
                inspectPointDirect(scene_, embree_.faceBoxes(), samples_[i].face, samples_[i].x,
                                   work, &embree_.faceClusters());
            directMs.push_back(secondsBetween(a, StudyClock::now()) * 1e3);
            click.overBudget += !p.has_value();
        }
        click.treePoints = std::min<size_t>(samples_.size(), 20);
        std::vector<double> treeMs;
        VisibilityStore cold(scene_, &embree_);
        for (size_t i = 0; i < click.treePoints; ++i) {
            const auto a = StudyClock::now();
            inspectPoint(cold, samples_[i].face, samples_[i].x);
            treeMs.push_back(secondsBetween(a, StudyClock::now()) * 1e3);
        }
        const Quantiles direct = quantiles(directMs), tree = quantiles(treeMs);
        click.fragmentsMedianMs = direct.median;
        click.fragmentsP99Ms = direct.p99;
        click.fragmentsMaxMs = direct.max;
        click.withTreesMedianMs = tree.median;
        click.withTreesMaxMs = tree.max;
        return click;
    }

    double measureRays(int n) {
        const uint32_t light = scene_.lights[0];
        const auto a = StudyClock::now();
        for (const Sample& s : samples_) sink_ += embree_.sampledFraction(s.face, light, s.x, n, 7);
        return meanUs(a);
    }

    double checksum() const { return sink_; }

  private:
    Vec3 normal(const Sample& s) const { return vis::normalize(mesh_.faceAreaNormal(s.face)); }

    const Scene& scene_;
    const vis::PolygonMesh& mesh_;
    const EmbreeScene& embree_;
    std::vector<Sample> samples_;
    vis::FromPointQuery query_;
    double sink_ = 0;
};

void logRow(const PerPointRow& p, double checksum, const StudyLog& log) {
    const double n = static_cast<double>(p.points);
    const ClickLatency& k = p.click;
    logLine(log,
            "per point %s: exact query + form factor %.2f us (median %.2f, p99 %.2f; %.1f nodes, "
            "%.2f fragments); 16 rays %.2f us; 128 rays %.2f us; click: fragments %.2f ms "
            "(median; p99 %.2f), with the trees %.1f ms (median; max %.1f) (checksum %.3g)",
            p.scene.c_str(), p.exactUs, p.exactMedianUs, p.exactP99Us, p.nodesPerQuery,
            p.fragmentsPerQuery, p.rays16Us, p.rays128Us, k.fragmentsMedianMs, k.fragmentsP99Ms,
            k.withTreesMedianMs, k.withTreesMaxMs, checksum);
    const ChainStats& c = p.chain;
    logLine(
        log,
        "  boundary chain: %zu points with many occluders, %zu of their %zu edges left "
        "(%.1f%%); %zu points by the chain, %zu cells (%zu labelled by crossings), %zu "
        "fragments; Algorithm 1 only: %.2f us",
        c.manyOccluderPoints, c.boundaryEdges, c.occluderEdges,
        c.occluderEdges == 0 ? 0.0 : 100.0 * static_cast<double>(c.boundaryEdges) / c.occluderEdges,
        c.points, c.cells, c.crossingLabels, c.fragments, c.oneByOneUs);
    const OutlineStats& o = p.outline;
    logLine(log,
            "  boundary of the visible region: per point %.1f fragment edges, %.2f loops of %.1f "
            "edges; the fragments' form factor %.3f us, the outline built and integrated %.3f us",
            static_cast<double>(o.fragmentEdges) / n, static_cast<double>(o.loops) / n,
            static_cast<double>(o.edges) / n, o.integrationUs, o.outlineUs);
    logLine(log,
            "  silhouettes: %zu of %zu partial trees, %llu of their %llu edge uses kept (%.1f%%); "
            "%zu points by them",
            c.silhouetteTrees, c.partialTrees, static_cast<unsigned long long>(c.silhouetteKept),
            static_cast<unsigned long long>(c.silhouetteUses),
            c.silhouetteUses == 0 ? 0.0
                                  : 100.0 * static_cast<double>(c.silhouetteKept) /
                                        static_cast<double>(c.silhouetteUses),
            c.silhouettePoints);
}

}  // namespace per_point_detail

PerPointRow runPerPointStudy(const std::string& path, const Scene& scene, size_t points,
                             const StudyLog& log) {
    using namespace per_point_detail;
    const EmbreeScene embree(scene.mesh);
    VisibilityStore store(scene, &embree);
    const uint32_t light = scene.lights[0];
    std::vector<Sample> samples;
    for (const SurfaceSample& s : surfaceSamples(scene, points, 1))
        samples.push_back(
            {s.face, s.x, &store.getOrBuild(store.layout().keyAt(s.face, s.x, light))});
    PerPointMeasure measure(scene, embree, std::move(samples));
    PerPointRow row;
    row.scene = path;
    row.points = points;
    measure.countSilhouettes(row.chain);
    row.outline = measure.measureOutline();
    measure.measureQuery(row);
    row.chain.oneByOneUs = measure.measureOneByOne();
    const Quantiles each = measure.measureEachPoint();
    row.exactMedianUs = each.median;
    row.exactP99Us = each.p99;
    row.exactMaxUs = each.max;
    row.click = measure.measureClicks();
    row.rays16Us = measure.measureRays(16);
    row.rays128Us = measure.measureRays(128);
    logRow(row, measure.checksum(), log);
    return row;
}

}  // namespace penumbra
