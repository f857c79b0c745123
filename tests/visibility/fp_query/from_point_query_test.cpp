// FPQuery against independent references: the exact CGAL computation of L minus the central
// projections of the occluders (tests/support/exact_reference.h), and a Monte Carlo estimate with
// independent double-precision segment tests. Plus the properties of the fragments.
#include "visibility/fp_query/from_point_query.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "engine/precompute/point_query.h"
#include "engine/scene/procedural_scenes.h"
#include "tests/support/exact_reference.h"
#include "tests/support/face_boxes.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/box_tree.h"
#include "visibility/form_factor.h"
#include "visibility/history_tree_builder.h"
#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"
#include "visibility/visible_outline.h"

namespace penumbra {
namespace {

using vis::Vec3;

struct QueryOutcome {
    double fraction = 0, visibleArea = 0, formFactor = 0;
    vis::FromPointResult raw;
};

Vec3 unitNormal(const vis::PolygonMesh& m, uint32_t f) {
    return vis::normalize(m.faceAreaNormal(f));
}

QueryOutcome evaluate(const vis::PolygonMesh& m, const vis::HistoryTree& t, const Vec3& x) {
    QueryOutcome q;
    q.raw = vis::fromPointQuery(m, t, x);
    const Vec3 n = unitNormal(m, t.receiver);
    for (const auto& f : q.raw.fragments) {
        q.visibleArea += vis::polygonArea(f);
        q.formFactor += vis::formFactor(x, n, f);
    }
    q.fraction = q.visibleArea / m.faceArea(t.light);
    return q;
}

using test::randomPointOn;  // strictly inside a face (tests/support/random_points.h)

// Trees per (receiver patch, light), as the query command builds them.
struct Trees {
    const Scene& scene;
    VisibilityStore store;
    explicit Trees(const Scene& s, const VisibilityStore::Options& o = {})
        : scene(s), store(s, nullptr, o) {}
    const vis::HistoryTree& get(uint32_t r, uint32_t l, const Vec3& x) {
        return store.getOrBuild(store.layout().keyAt(r, x, l)).tree;
    }
};

// Compares FPQuery with the exact reference at `points` random points on random receivers, with
// the trees built under `options` (a small build budget makes partial trees). Some points must
// lie in a penumbra (else only the trivial answers 0 and 1 were compared), and with
// `expectPartial` some trees must have been partial. Returns the points whose tree was partial.
int checkAgainstReference(const Scene& scene, int points, uint64_t seed, const char* name,
                          const VisibilityStore::Options& options = {},
                          bool expectPartial = false) {
    EXPECT_FALSE(scene.lights.empty());
    if (scene.lights.empty()) return 0;
    const vis::PolygonMesh& m = scene.mesh;
    Trees trees{scene, options};
    std::mt19937_64 rng(seed);
    std::uniform_int_distribution<uint32_t> faceDist(0, scene.faceCount() - 1);
    int compared = 0, nonTrivial = 0, partial = 0;
    for (int i = 0; i < points; ++i) {
        const uint32_t r = faceDist(rng);
        const uint32_t l = scene.lights[rng() % scene.lights.size()];
        if (r == l) continue;
        const Vec3 x = randomPointOn(m, r, rng);
        const vis::HistoryTree& tree = trees.get(r, l, x);
        partial += tree.partial() ? 1 : 0;
        const QueryOutcome q = evaluate(m, tree, x);
        const test::ReferenceResult ref = test::exactReference(m, r, l, x);
        ++compared;
        nonTrivial += ref.fraction > 1e-9 && ref.fraction < 1 - 1e-9;
        EXPECT_NEAR(q.fraction, ref.fraction, 1e-9)
            << name << ": receiver " << r << " light " << l << " x " << vis::toString(x);
        EXPECT_NEAR(q.formFactor, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
            << name << ": receiver " << r << " light " << l << " x " << vis::toString(x);
        if (::testing::Test::HasFailure()) return partial;  // one report per scene is enough
    }
    EXPECT_GT(compared, points / 2) << name;
    EXPECT_GT(nonTrivial, 0) << name << ": no point in a penumbra";
    if (expectPartial) {
        EXPECT_GT(partial, 0) << name << ": no partial tree";
    }
    return partial;
}

// Partial trees: with a build budget of a few hundred programs most penumbra pairs stop early and
// leave most occluders to the query; with a budget of one program the trees are hardly begun and
// the query clips nearly everything itself. The answers must not change.
VisibilityStore::Options budget(uint64_t lps) {
    VisibilityStore::Options o;
    o.build.maxLpSolves = lps;
    return o;
}

// A budget of one program stops the build of every pair that needs more: at that budget each of
// the four large scenes, and the hard cases together, must have made partial trees. Some hard
// cases have few penumbra points: at least 100 points each, at any PENUMBRA_TEST_SCALE.
TEST(FpQuery, PartialTreesMatchExactReference) {
    int partial = 0;
    for (uint64_t lps : {1, 300}) {
        const bool one = lps == 1;
        partial +=
            checkAgainstReference(makeStairs(), test::scaled(600), 21, "stairs", budget(lps), one);
        partial +=
            checkAgainstReference(makeGrids(), test::scaled(600), 22, "grids", budget(lps), one);
        partial += checkAgainstReference(makeCornellBox(), test::scaled(600), 23, "cornell",
                                         budget(lps), one);
        partial +=
            checkAgainstReference(makeTable(), test::scaled(60), 24, "table", budget(lps), one);
        uint64_t seed = 30;
        int hardPartial = 0;
        for (const auto& [name, scene] : makeHardCases())
            hardPartial += checkAgainstReference(scene, std::max(test::scaled(150), 100), seed++,
                                                 name.c_str(), budget(lps));
        if (one) {
            EXPECT_GT(hardPartial, 0) << "no hard case made a partial tree";
        }
        partial += hardPartial;
    }
    EXPECT_GT(partial, test::scaled(600));  // the budgets did make partial trees
}

TEST(FpQuery, StairsMatchExactReference) {
    checkAgainstReference(makeStairs(), test::scaled(2000), 1, "stairs");
}
TEST(FpQuery, TableMatchesExactReference) {
    checkAgainstReference(makeTable(), test::scaled(60), 2, "table");
}
TEST(FpQuery, GridsMatchExactReference) {
    checkAgainstReference(makeGrids(), test::scaled(2000), 3, "grids");
}
TEST(FpQuery, CornellBoxMatchesExactReference) {
    checkAgainstReference(makeCornellBox(), test::scaled(2000), 4, "cornell");
}

TEST(FpQuery, HardCasesMatchExactReference) {
    uint64_t seed = 10;
    for (const auto& [name, scene] : makeHardCases())
        checkAgainstReference(scene, test::scaled(500), seed++, name.c_str());
}

TEST(FpQuery, RandomSoupsMatchExactReference) {
    for (uint64_t seed = 0; seed < 3; ++seed)
        checkAgainstReference(makeRandomSoup(40, seed), test::scaled(700), 100 + seed, "soup");
}

// The direct query (no tree: the faces in the pyramid from x clipped from x) against the exact
// reference, on every scene and hard case.
void checkDirectAgainstReference(const Scene& scene, int points, uint64_t seed, const char* name) {
    const vis::PolygonMesh& m = scene.mesh;
    std::vector<vis::Bounds3> boxes(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) boxes[f] = m.faceBounds(f);
    const vis::BoxTree faces(boxes);
    vis::FromPointQuery query;
    std::mt19937_64 rng(seed);
    int compared = 0, nonTrivial = 0;
    for (int i = 0; i < points; ++i) {
        const uint32_t r = static_cast<uint32_t>(rng() % scene.faceCount());
        const uint32_t l = scene.lights[rng() % scene.lights.size()];
        if (r == l) continue;
        const Vec3 x = randomPointOn(m, r, rng);
        const vis::FragmentList& fragments = query.runDirect(m, r, l, x, faces);
        double area = 0, ff = 0;
        const Vec3 n = unitNormal(m, r);
        for (size_t k = 0; k < fragments.size(); ++k) {
            area += vis::polygonArea(fragments[k]);
            ff += vis::formFactor(x, n, fragments[k]);
        }
        const test::ReferenceResult ref = test::exactReference(m, r, l, x);
        ++compared;
        nonTrivial += ref.fraction > 1e-9 && ref.fraction < 1 - 1e-9;
        EXPECT_NEAR(area / m.faceArea(l), ref.fraction, 1e-9)
            << name << ": receiver " << r << " light " << l << " x " << vis::toString(x);
        EXPECT_NEAR(ff, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
            << name << ": receiver " << r << " light " << l << " x " << vis::toString(x);
        // The fragments' outline (visible_outline.h): the exact region's area and form factor,
        // tiny, huge and far from the origin too. (Not its number of boundaries: these scenes
        // touch, and where a part touches another at a point CGAL may count one boundary and
        // the outline two loops; nor where a sliver is thinner than the outline's weld.)
        const vis::VisibleOutline outline = vis::visibleOutline(fragments.polygons());
        EXPECT_NEAR(vis::formFactorOfLoops(x, n, outline.loops), ref.formFactor,
                    1e-9 * std::max(ref.formFactor, 1e-6))
            << name << ": outline, receiver " << r << " light " << l << " x " << vis::toString(x);
        EXPECT_NEAR(outline.area() / m.faceArea(l), ref.fraction, 1e-9)
            << name << ": outline, receiver " << r << " light " << l << " x " << vis::toString(x);
        if (::testing::Test::HasFailure()) return;
    }
    EXPECT_GT(compared, points / 2) << name;
    EXPECT_GT(nonTrivial, 0) << name << ": no point in a penumbra";
}

TEST(FpQuery, DirectQueryMatchesExactReference) {
    checkDirectAgainstReference(makeStairs(), test::scaled(1000), 41, "stairs");
    checkDirectAgainstReference(makeGrids(), test::scaled(1000), 42, "grids");
    checkDirectAgainstReference(makeCornellBox(), test::scaled(1000), 43, "cornell");
    checkDirectAgainstReference(makeTable(), test::scaled(100), 44, "table");
    uint64_t seed = 50;
    for (const auto& [name, scene] : makeHardCases())
        checkDirectAgainstReference(scene, test::scaled(300), seed++, name.c_str());
    for (uint64_t seed2 = 0; seed2 < 3; ++seed2)
        checkDirectAgainstReference(makeRandomSoup(40, seed2), test::scaled(300), 60 + seed2,
                                    "soup");
}

// The work limit: a run allowed exactly the plane tests it needs gives the same answer; one test
// fewer stops it and says so.
TEST(FpQuery, WorkLimitStopsARunAndSaysSo) {
    const Scene s = makeTable();
    VisibilityStore::Options o;
    o.build.maxLpSolves = 300;  // partial trees: the limit covers the deferred clipping too
    Trees trees{s, o};
    std::mt19937_64 rng(17);
    vis::FromPointQuery unlimited, limited;
    int checked = 0, stopped = 0;
    for (int i = 0; i < test::scaled(300); ++i) {
        const uint32_t f = static_cast<uint32_t>(rng() % s.faceCount());
        if (f == s.lights[0]) continue;
        const Vec3 x = randomPointOn(s.mesh, f, rng);
        const vis::HistoryTree& tree = trees.get(f, s.lights[0], x);
        const vis::FragmentList& a = unlimited.run(s.mesh, tree, x);
        const std::vector<Vec3> first =
            a.empty() ? std::vector<Vec3>{} : std::vector<Vec3>(a[0].begin(), a[0].end());
        const size_t count = a.size();
        const uint64_t work = unlimited.work();
        EXPECT_FALSE(unlimited.limitReached());
        if (work == 0) continue;
        limited.setWorkLimit(work);
        const vis::FragmentList& b = limited.run(s.mesh, tree, x);
        EXPECT_FALSE(limited.limitReached());
        EXPECT_EQ(b.size(), count);
        if (!first.empty() && b.size() > 0) {
            EXPECT_EQ(std::vector<Vec3>(b[0].begin(), b[0].end()), first);
        }
        limited.setWorkLimit(work - 1);
        if (work > 1) {
            limited.run(s.mesh, tree, x);
            EXPECT_TRUE(limited.limitReached()) << "work " << work;
            ++stopped;
        }
        ++checked;
    }
    EXPECT_GT(checked, test::scaled(300) / 6);
    EXPECT_GT(stopped, test::scaled(300) / 15);
}

// Where a run reached its work limit (FromPointQuery::limitStage): the tree-less query on the
// table (leaves, Algorithm 1) first finds the occluders in the pyramid, then activates them,
// then clips; as the limit grows from 1 to the run's whole work, the stage it stops in goes
// through them in that order, never back.
TEST(FpQuery, WorkLimitSaysWhichStageReachedIt) {
    const Scene s = makeTable();
    const vis::BoxTree faces = test::faceBoxTree(s.mesh);
    std::mt19937_64 rng(29);
    vis::FromPointQuery unlimited, limited;
    unlimited.setChainOptions({0, 0, 0});
    limited.setChainOptions({0, 0, 0});
    const uint32_t light = s.lights[0];
    // Points are drawn until enough of them do some work: a point whose query is trivial (a
    // face that sees the light whole or not at all) says nothing about stages.
    const int wanted = test::scaled(60);
    int clipped = 0, points = 0;
    for (int i = 0; i < 20 * wanted && points < wanted; ++i) {
        const uint32_t f = static_cast<uint32_t>(rng() % s.faceCount());
        if (f == light) continue;
        const Vec3 x = randomPointOn(s.mesh, f, rng);
        unlimited.runDirect(s.mesh, f, light, x, faces);
        const uint64_t work = unlimited.work();
        if (work < 2) continue;
        ++points;
        // The run's work by stage adds up to its work; the stages run in WorkStage's order
        // (checked below), so a limit is reached in the first stage whose running total of the
        // unlimited run's work exceeds it.
        const auto& byStage = unlimited.stageWork();
        uint64_t sum = 0;
        for (uint64_t w : byStage) sum += w;
        ASSERT_EQ(sum, work);
        const auto byStageCopy = byStage;
        auto predictedStage = [&](uint64_t limit) {
            uint64_t total = 0;
            for (size_t i = 0; i < byStageCopy.size(); ++i) {
                total += byStageCopy[i];
                if (total > limit) return static_cast<vis::WorkStage>(i);
            }
            return vis::WorkStage::Walk;
        };
        int last = -1;
        bool sawClip = false;
        for (uint64_t limit = 1; limit < work; limit += std::max<uint64_t>(1, work / 40)) {
            limited.setWorkLimit(limit);
            limited.runDirect(s.mesh, f, light, x, faces);
            ASSERT_TRUE(limited.limitReached()) << "limit " << limit << " of " << work;
            const vis::WorkStage stage = limited.limitStage();
            EXPECT_EQ(stage, predictedStage(limit)) << "limit " << limit << " of " << work;
            if (limit == 1) {
                EXPECT_EQ(stage, vis::WorkStage::FindOccluders);
            }
            EXPECT_TRUE(stage == vis::WorkStage::FindOccluders ||
                        stage == vis::WorkStage::ActivateOccluders ||
                        stage == vis::WorkStage::ClipOccluders)
                << vis::toString(stage);
            EXPECT_GE(static_cast<int>(stage), last) << "limit " << limit;
            last = static_cast<int>(stage);
            sawClip = sawClip || stage == vis::WorkStage::ClipOccluders;
        }
        clipped += sawClip;
    }
    EXPECT_EQ(points, wanted);
    EXPECT_GT(clipped, points / 10);  // the clip stage was reached too
}

// The penumbra points must actually exercise the trees: in the grids scene most receiver points
// under the grid see a partly hidden light.
TEST(FpQuery, GridsHaveRealPenumbrae) {
    const Scene s = makeGrids();
    Trees trees{s};
    std::mt19937_64 rng(5);
    int partial = 0, total = 0;
    for (uint32_t f = 0; f < s.faceCount() && total < 400; ++f) {
        if (f == s.lights[0]) continue;
        for (int i = 0; i < 5; ++i) {
            const Vec3 x = randomPointOn(s.mesh, f, rng);
            const auto& t = trees.get(f, s.lights[0], x);
            if (t.kind != vis::PairKind::Penumbra) continue;
            const QueryOutcome q = evaluate(s.mesh, t, x);
            partial += q.fraction > 1e-6 && q.fraction < 1 - 1e-6;
            ++total;
        }
    }
    EXPECT_GT(total, 20);
    EXPECT_GT(partial, total / 4);
}

TEST(FpQuery, MonteCarloAgrees) {
    const Scene s = makeRandomSoup(40, 7);
    Trees trees{s};
    std::mt19937_64 rng(9);
    const uint32_t l = s.lights[0];
    int checked = 0;
    for (int i = 0; i < 40 && checked < 12; ++i) {
        const uint32_t r = static_cast<uint32_t>(rng() % s.faceCount());
        if (r == l) continue;
        const Vec3 x = randomPointOn(s.mesh, r, rng);
        const QueryOutcome q = evaluate(s.mesh, trees.get(r, l, x), x);
        double sd = 0;
        const double mc = test::monteCarloFraction(s.mesh, r, l, x, 20000, 1000 + i, &sd);
        EXPECT_NEAR(q.fraction, mc, 5 * std::max(sd, 2e-4))
            << "receiver " << r << " x " << vis::toString(x);
        ++checked;
    }
    EXPECT_GE(checked, 10);
}

// Fragments are disjoint, lie inside L, and their areas add up to the visible area.
TEST(FpQuery, FragmentsAreDisjointAndInsideTheLight) {
    const Scene s = makeRandomSoup(40, 3);
    const vis::PolygonMesh& m = s.mesh;
    Trees trees{s};
    std::mt19937_64 rng(11);
    const uint32_t l = s.lights[0];
    const vis::FacePlane lp = vis::facePlane(m, l);
    int multi = 0;
    const int points = test::scaled(200);
    for (int i = 0; i < points; ++i) {
        const uint32_t r = static_cast<uint32_t>(rng() % s.faceCount());
        if (r == l) continue;
        const Vec3 x = randomPointOn(m, r, rng);
        const QueryOutcome q = evaluate(m, trees.get(r, l, x), x);
        const auto& frags = q.raw.fragments;
        multi += frags.size() > 1;
        const double lightArea = m.faceArea(l);
        const double scale = std::sqrt(lightArea);
        for (const auto& f : frags) {
            ASSERT_GE(f.size(), 3u);
            for (const Vec3& p : f) {
                // In L's plane and inside every edge's half-plane (within rounding).
                const Vec3 n = vis::normalize(m.faceAreaNormal(l));
                EXPECT_NEAR(vis::dot(n, p - lp.a), 0, 1e-9 * scale);
                const auto& li = m.faces[l];
                for (size_t e = 0; e < li.size(); ++e) {
                    const Vec3 a = m.vertices[li[e]], b = m.vertices[li[(e + 1) % li.size()]];
                    EXPECT_GE(vis::dot(vis::cross(b - a, p - a), n), -1e-9 * scale * scale);
                }
            }
        }
        // Pairwise overlap: clip one fragment by the other's edge planes (planes through each
        // edge, perpendicular to L), the remaining area must vanish.
        const Vec3 n = vis::normalize(m.faceAreaNormal(l));
        for (size_t a = 0; a < frags.size(); ++a)
            for (size_t b = a + 1; b < frags.size(); ++b) {
                std::vector<Vec3> piece = frags[a];
                const auto& fb = frags[b];
                for (size_t e = 0; e < fb.size() && piece.size() >= 3; ++e) {
                    const Vec3 p = fb[e], q2 = fb[(e + 1) % fb.size()];
                    // keep the side of the edge towards fragment b's interior (b is CCW about n
                    // like L, or CW: pick the side where b's centroid lies)
                    Vec3 c{};
                    for (const Vec3& v : fb) c += v / static_cast<double>(fb.size());
                    vis::OrientedPlane plane{p, q2, p + n};
                    if (plane.side(c) == vis::Sign::Negative) plane = {q2, p, q2 + n};
                    piece = vis::clipConvexPositive(piece, plane);
                }
                const double overlap = piece.size() >= 3 ? vis::polygonArea(piece) : 0.0;
                EXPECT_LT(overlap, 1e-9 * lightArea)
                    << "fragments " << a << " and " << b << " overlap";
            }
        double sum = 0;
        for (const auto& f : frags) sum += vis::polygonArea(f);
        const test::ReferenceResult ref = test::exactReference(m, r, l, x);
        EXPECT_NEAR(sum, ref.visibleArea, 1e-9 * lightArea);
    }
    EXPECT_GT(multi, points / 40);  // the property was exercised on multi-fragment answers
}

// Leaf merging and quadric pruning change the tree, never the answer.
TEST(FpQuery, OptimisationsDoNotChangeResults) {
    const Scene s = makeRandomSoup(30, 5);
    const vis::PolygonMesh& m = s.mesh;
    const uint32_t l = s.lights[0];
    std::mt19937_64 rng(13);
    size_t nodesAll = 0, nodesNone = 0;
    for (int i = 0; i < 6; ++i) {
        const uint32_t r = static_cast<uint32_t>(rng() % s.faceCount());
        if (r == l) continue;
        vis::HistoryTree trees[4];
        for (int k = 0; k < 4; ++k)
            trees[k] = vis::buildHistoryTree(
                m, r, l, {.mergeLeaves = (k & 1) != 0, .quadricPruning = (k & 2) != 0});
        nodesAll += trees[3].nodes.size();
        nodesNone += trees[0].nodes.size();
        for (int p = 0; p < 30; ++p) {
            const Vec3 x = randomPointOn(m, r, rng);
            const QueryOutcome base = evaluate(m, trees[0], x);
            for (int k = 1; k < 4; ++k) {
                const QueryOutcome q = evaluate(m, trees[k], x);
                EXPECT_NEAR(q.fraction, base.fraction, 1e-12) << "variant " << k;
                EXPECT_NEAR(q.formFactor, base.formFactor, 1e-12 * std::max(1.0, base.formFactor));
            }
        }
    }
    EXPECT_LE(nodesAll, nodesNone);
}

// The reusable FromPointQuery keeps what depends only on the pair (the light clipped to the
// receiver's front) between runs: interleaved pairs, and a light edited in place between two runs
// on the same mesh object, must answer exactly as a fresh one-shot query.
TEST(FpQuery, ReusedQueryAnswersAsAFreshOne) {
    Scene s = makeRandomSoup(30, 7);
    vis::PolygonMesh& m = s.mesh;
    const uint32_t l = s.lights[0];
    std::mt19937_64 rng(21);
    std::vector<vis::HistoryTree> trees;
    for (int i = 0; trees.size() < 4 && i < 200; ++i) {
        const uint32_t r = static_cast<uint32_t>(rng() % s.faceCount());
        if (r == l) continue;
        vis::HistoryTree t = vis::buildHistoryTree(m, r, l);
        if (t.kind == vis::PairKind::Penumbra) trees.push_back(std::move(t));
    }
    ASSERT_GE(trees.size(), 2u);
    auto same = [&](const vis::FragmentList& a, const vis::FromPointResult& b) {
        if (a.size() != b.fragments.size()) return false;
        for (size_t i = 0; i < a.size(); ++i)
            if (!std::equal(a[i].begin(), a[i].end(), b.fragments[i].begin(), b.fragments[i].end()))
                return false;
        return true;
    };
    vis::FromPointQuery reused;
    size_t nonEmpty = 0;
    for (int p = 0; p < 200; ++p) {
        const vis::HistoryTree& t = trees[rng() % trees.size()];
        const Vec3 x = randomPointOn(m, t.receiver, rng);
        const vis::FragmentList& got = reused.run(m, t, x);
        nonEmpty += !got.empty();
        EXPECT_TRUE(same(got, vis::fromPointQuery(m, t, x))) << "run " << p;
    }
    EXPECT_GT(nonEmpty, 0u);
    // Shrink the light towards its centroid, in place: same mesh object, same ids.
    const vis::HistoryTree& t = trees[0];
    const Vec3 x = randomPointOn(m, t.receiver, rng);
    const vis::FragmentList& before = reused.run(m, t, x);
    const double areaBefore = before.empty() ? 0 : vis::polygonArea(before[0]);
    Vec3 centroid{};
    for (uint32_t v : m.faces[l]) centroid += m.vertices[v];
    centroid = centroid / static_cast<double>(m.faces[l].size());
    for (uint32_t v : m.faces[l]) m.vertices[v] = centroid + (m.vertices[v] - centroid) * 0.5;
    const vis::FragmentList& after = reused.run(m, t, x);
    EXPECT_TRUE(same(after, vis::fromPointQuery(m, t, x)));
    ASSERT_GT(areaBefore, 0);
    ASSERT_FALSE(after.empty());
    EXPECT_NE(vis::polygonArea(after[0]), areaBefore);
}

// A point exactly on a splitting plane: no sliver, no lost area.
TEST(FpQuery, PointOnSplittingPlaneLosesNoArea) {
    // Floor [0,4]^2 at z=0, light [1,3]^2 at z=4 facing down, occluder square [1.5,2.5]^2 at z=2.
    vis::PolygonMesh m;
    m.vertices = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0},     {0, 4, 0},     {1, 1, 4},     {1, 3, 4},
                  {3, 3, 4}, {3, 1, 4}, {1.5, 1.5, 2}, {2.5, 1.5, 2}, {2.5, 2.5, 2}, {1.5, 2.5, 2}};
    m.faces = {{0, 1, 2, 3}, {4, 5, 6, 7}, {8, 9, 10, 11}};
    const vis::HistoryTree t = vis::buildHistoryTree(m, 0, 1);
    ASSERT_EQ(t.kind, vis::PairKind::Penumbra);
    // The occluder's shadow from x on the light's plane is x + 2 (o - x). Hand-derived:
    struct Case {
        Vec3 x;
        double visible;
    };
    const Case cases[] = {
        {{2, 2, 0}, 0.0},    // shadow exactly [1,3]^2: all four planes pass through L's edges
        {{1, 2, 0}, 2.0},    // shadow x in [2, 4]: blocks [2,3] x [1,3]
        {{0.5, 2, 0}, 3.0},  // shadow x in [2.5, 4.5], y in [1, 3]: blocks 1
        {{2, 1, 0}, 2.0},    // shadow y in [2, 4]: blocks [1,3] x [2,3]; x planes through L's edges
        {{1.5, 1.5, 0}, 1.75},  // shadow [1.5, 3.5]^2: blocks [1.5, 3]^2 = 2.25
    };
    for (const Case& c : cases) {
        const QueryOutcome q = evaluate(m, t, c.x);
        EXPECT_NEAR(q.visibleArea, c.visible, 1e-12) << vis::toString(c.x);
        EXPECT_NEAR(test::exactReference(m, 0, 1, c.x).visibleArea, c.visible, 1e-12);
        for (const auto& f : q.raw.fragments) EXPECT_GT(vis::polygonArea(f), 1e-3) << "sliver";
    }
}

TEST(HistoryTree, NodesAreSixteenBytesAndPairsAreClassified) {
    static_assert(sizeof(vis::HistoryNode) == 16);
    vis::PolygonMesh m;
    m.vertices = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0},     {0, 4, 0},    {1, 1, 4},   {1, 3, 4},
                  {3, 3, 4}, {3, 1, 4}, {-10, -10, 2}, {10, -10, 2}, {10, 10, 2}, {-10, 10, 2}};
    // No occluder: fully visible.
    m.faces = {{0, 1, 2, 3}, {4, 5, 6, 7}};
    EXPECT_EQ(vis::buildHistoryTree(m, 0, 1).kind, vis::PairKind::FullyVisible);
    // A huge plate in between: fully hidden by a single occluder.
    m.faces.push_back({8, 9, 10, 11});
    vis::HistoryTree t = vis::buildHistoryTree(m, 0, 1);
    EXPECT_EQ(t.kind, vis::PairKind::FullyHidden);
    EXPECT_TRUE(t.nodes.empty());
    // Light facing away from the receiver: back-facing.
    m.faces = {{0, 1, 2, 3}, {7, 6, 5, 4}};
    EXPECT_EQ(vis::buildHistoryTree(m, 0, 1).kind, vis::PairKind::BackFacing);
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// The build budget: a penumbra pair of the Cornell box built with a budget below what it needs
// gets a partial tree (fewer nodes, the rest of its occluders deferred) that answers every point
// as the complete tree does; a budget just above the need changes nothing.
TEST(HistoryTree, BuildBudgetGivesAPartialTreeWithTheSameAnswers) {
    const Scene scene = makeCornellBox();
    const uint32_t light = scene.lights[0];
    std::mt19937_64 rng(9);
    int checked = 0;
    for (uint32_t r = 0; r < scene.faceCount() && checked < 3; ++r) {
        if (r == light) continue;
        vis::BuildOptions unlimited;
        unlimited.maxLpSolves = 0;
        vis::BuildStats full;
        const vis::HistoryTree tree =
            vis::buildHistoryTree(scene.mesh, r, light, unlimited, {}, &full);
        if (tree.kind != vis::PairKind::Penumbra || full.lpSolves < 50) continue;
        EXPECT_FALSE(tree.partial());
        vis::BuildOptions tight;
        tight.maxLpSolves = full.lpSolves / 2;
        vis::BuildStats stats;
        const vis::HistoryTree cut = vis::buildHistoryTree(scene.mesh, r, light, tight, {}, &stats);
        EXPECT_EQ(cut.kind, vis::PairKind::Penumbra);
        EXPECT_TRUE(stats.budgetExceeded);
        EXPECT_TRUE(cut.partial());
        EXPECT_EQ(stats.occludersDeferred, cut.deferred.size());
        EXPECT_LT(cut.nodes.size(), tree.nodes.size());
        for (const vis::DeferredOccluder& d : cut.deferred) EXPECT_FALSE(d.box.empty());
        // The same answer at random points of the receiver (and the exact reference agrees).
        for (int i = 0; i < 40; ++i) {
            const Vec3 x = randomPointOn(scene.mesh, r, rng);
            const QueryOutcome a = evaluate(scene.mesh, tree, x), b = evaluate(scene.mesh, cut, x);
            EXPECT_NEAR(a.fraction, b.fraction, 1e-12) << "receiver " << r;
            EXPECT_NEAR(a.formFactor, b.formFactor, 1e-12 * std::max(a.formFactor, 1e-6));
            if (i < 5) {
                const test::ReferenceResult ref = test::exactReference(scene.mesh, r, light, x);
                EXPECT_NEAR(b.fraction, ref.fraction, 1e-9);
            }
        }
        // A budget just above the need changes nothing.
        tight.maxLpSolves = full.lpSolves + 1;
        const vis::HistoryTree same = vis::buildHistoryTree(scene.mesh, r, light, tight);
        EXPECT_EQ(same.kind, vis::PairKind::Penumbra);
        EXPECT_FALSE(same.partial());
        EXPECT_EQ(same.nodes.size(), tree.nodes.size());
        ++checked;
    }
    EXPECT_EQ(checked, 3);
}

}  // namespace
}  // namespace penumbra
