// buildHistoryTree (visibility/history_tree_builder.h): the structure of what it builds, and its
// labels. Structure: a tree in depth-first order (children valid, each node reached once), every
// inner node's edge an edge of an occluder the build inserted or a chord of one (history_tree.h's
// encoding), sibling leaves merged, the kind and its reason consistent with the nodes. Labels: the
// fraction of L that FPQuery sees through the tree equals the exact CGAL reference
// (tests/support/exact_reference.h) to 1e-9 of L's area, or a value derived by hand below.
// Builder-specific: small scenes whose kind (fully visible, fully hidden, penumbra) and tree shape
// are known by construction, occluders that block everything only together, receiver patches,
// candidate lists, the build budget (partial trees answering exactly at every budget), and
// cancellation.
//
// The hand-made scenes: receiver B = [0,4]^2 at z = 0 facing +z (face 0), light L = [1,3]^2 at
// z = 4 facing -z (face 1), occluders horizontal rectangles. A line from b on B to l on L meets
// the plane z = h at b + (l - b) h / 4: at z = 2 at the midpoint, so from x the shadow of an
// occluder at z = 2 on L's plane is x + 2 (o - x).
#include "visibility/history_tree_builder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <random>
#include <set>
#include <string>

#include "engine/scene/procedural_scenes.h"
#include "tests/support/exact_reference.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/pair_occluders.h"

namespace penumbra {
namespace {

using vis::BuildOptions;
using vis::BuildStats;
using vis::HistoryTree;
using vis::PairKind;
using vis::PolygonMesh;
using vis::Vec3;

// ---- scenes ---------------------------------------------------------------------------------

PolygonMesh receiverAndLight() {
    PolygonMesh m;
    m.vertices = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0},
                  {1, 1, 4}, {1, 3, 4}, {3, 3, 4}, {3, 1, 4}};
    m.faces = {{0, 1, 2, 3}, {4, 5, 6, 7}};
    return m;
}

// Adds the rectangle [x0,x1] x [y0,y1] at height z; returns its face.
uint32_t addRectangle(PolygonMesh& m, double x0, double y0, double x1, double y1, double z) {
    const uint32_t v = static_cast<uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}});
    m.faces.push_back({v, v + 1, v + 2, v + 3});
    return static_cast<uint32_t>(m.faces.size() - 1);
}

// ---- what a tree must be --------------------------------------------------------------------

// The structural invariants of any tree the builder returns, for the pair (r, l) of `mesh`.
void expectWellFormed(const PolygonMesh& mesh, const HistoryTree& t, uint32_t r, uint32_t l,
                      const BuildOptions& options, const std::string& where) {
    SCOPED_TRACE(where);
    EXPECT_EQ(t.receiver, r);
    EXPECT_EQ(t.light, l);
    EXPECT_EQ(t.meshVertexCount, mesh.vertices.size());
    ASSERT_EQ(t.nodeOccluder.size(), t.nodes.size());
    // The occluders: distinct faces of the mesh, never B or L; deferred ones likewise.
    const std::set<uint32_t> inserted(t.occluders.begin(), t.occluders.end());
    EXPECT_EQ(inserted.size(), t.occluders.size()) << "an occluder inserted twice";
    std::set<uint32_t> deferred;
    for (const vis::DeferredOccluder& d : t.deferred) deferred.insert(d.face);
    EXPECT_EQ(deferred.size(), t.deferred.size()) << "an occluder deferred twice";
    for (const std::set<uint32_t>* faces :
         std::initializer_list<const std::set<uint32_t>*>{&inserted, &deferred})
        for (uint32_t f : *faces) {
            EXPECT_LT(f, mesh.faces.size());
            EXPECT_NE(f, r);
            EXPECT_NE(f, l);
        }
    // The kind, its reason and the nodes agree.
    switch (t.kind) {
        case PairKind::BackFacing:
            EXPECT_EQ(t.why, vis::reasons::kBackFacing);
            break;
        case PairKind::FullyVisible:
            EXPECT_TRUE(t.why == vis::reasons::kNoOccluder || t.why == vis::reasons::kBlockNothing)
                << t.why;
            EXPECT_EQ(t.why == vis::reasons::kNoOccluder, t.occluders.empty());
            break;
        case PairKind::FullyHidden:
            EXPECT_TRUE(t.why == vis::reasons::kSingleBlocksAll ||
                        t.why == vis::reasons::kTogetherBlockAll)
                << t.why;
            EXPECT_FALSE(t.occluders.empty());
            EXPECT_EQ(t.why == vis::reasons::kSingleBlocksAll, t.occluders.size() == 1);
            break;
        case PairKind::Penumbra:
            EXPECT_EQ(t.why, t.partial() ? vis::reasons::kPartial : vis::reasons::kPenumbra);
            if (!t.partial()) {
                EXPECT_FALSE(t.nodes.empty());
            }
            break;
    }
    if (t.kind != PairKind::Penumbra) {
        EXPECT_TRUE(t.nodes.empty());
        EXPECT_TRUE(t.deferred.empty());
    }
    if (t.partial()) {
        // The interrupted occluder is both inserted (its nodes exist) and deferred.
        ASSERT_FALSE(t.occluders.empty());
        EXPECT_EQ(t.occluders.back(), t.deferred.front().face);
    }
    // A tree in depth-first order: the root is node 0, every child index points further on, every
    // node but the root has exactly one parent.
    std::vector<int> parents(t.nodes.size(), 0);
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        const vis::HistoryNode& n = t.nodes[i];
        for (uint32_t c : n.child) {
            if (vis::isLeaf(c)) continue;
            ASSERT_LT(c, t.nodes.size()) << "node " << i;
            EXPECT_GT(c, i) << "node " << i << ": not depth-first order";
            ++parents[c];
        }
        // With merging, no node has two leaves of the same label.
        if (options.mergeLeaves && vis::isLeaf(n.child[0])) {
            EXPECT_NE(n.child[0], n.child[1]) << "node " << i << ": unmerged sibling leaves";
        }
        // The edge: an input edge of the node's occluder (in the face's order), or the chord
        // where that occluder's plane meets B's or L's plane. The occluder was inserted.
        const uint32_t face = t.nodeOccluder[i];
        EXPECT_TRUE(inserted.count(face)) << "node " << i << ": face " << face;
        if (vis::isClipEdge(n.v0)) {
            EXPECT_EQ(n.v0 & ~vis::kClipEdge, face) << "node " << i;
            EXPECT_TRUE(n.v1 == vis::kReceiverPlaneEdge || n.v1 == vis::kLightPlaneEdge)
                << "node " << i;
        } else {
            ASSERT_LT(face, mesh.faces.size());
            const std::vector<uint32_t>& f = mesh.faces[face];
            bool isEdge = false;
            for (size_t k = 0; k < f.size(); ++k)
                isEdge |= f[k] == n.v0 && f[(k + 1) % f.size()] == n.v1;
            EXPECT_TRUE(isEdge) << "node " << i << ": (" << n.v0 << ", " << n.v1
                                << ") is not an edge of face " << face;
        }
    }
    for (size_t i = 0; i < parents.size(); ++i) EXPECT_EQ(parents[i], i == 0 ? 0 : 1) << i;
    // A complete penumbra tree with merged leaves has both labels.
    if (t.kind == PairKind::Penumbra && !t.partial() && options.mergeLeaves) {
        EXPECT_GE(t.leafCount(true), 1u);
        EXPECT_GE(t.leafCount(false), 1u);
    }
}

double visibleFraction(const PolygonMesh& m, const HistoryTree& t, const Vec3& x) {
    double area = 0;
    for (const auto& f : vis::fromPointQuery(m, t, x).fragments) area += vis::polygonArea(f);
    return area / m.faceArea(t.light);
}

// FPQuery through the tree against the exact reference at `points` random points of `region`
// (the receiver face when empty). Returns how many of them are in a penumbra.
int expectExactLabels(const PolygonMesh& m, const HistoryTree& t, int points, std::mt19937_64& rng,
                      const std::string& where, std::span<const Vec3> region = {}) {
    std::vector<Vec3> corners(region.begin(), region.end());
    if (corners.empty())
        for (uint32_t v : m.faces[t.receiver]) corners.push_back(m.vertices[v]);
    int penumbra = 0;
    for (int i = 0; i < points; ++i) {
        const Vec3 x = test::randomCombination(corners, rng);
        const double ref = test::exactReference(m, t.receiver, t.light, x).fraction;
        EXPECT_NEAR(visibleFraction(m, t, x), ref, 1e-9) << where << " at " << vis::toString(x);
        penumbra += ref > 1e-9 && ref < 1 - 1e-9;
        if (::testing::Test::HasFailure()) break;
    }
    return penumbra;
}

// ---- hand-made scenes of known kind ---------------------------------------------------------

TEST(HistoryTreeBuilder, NoOccluderIsFullyVisible) {
    PolygonMesh m = receiverAndLight();
    // Beside the shaft: lines reach z = 2 at x in [0.5, 3.5], this rectangle is at x >= 5.
    addRectangle(m, 5, 0, 6, 4, 2);
    BuildStats stats;
    const HistoryTree t = vis::buildHistoryTree(m, 0, 1, {}, {}, &stats);
    expectWellFormed(m, t, 0, 1, {}, "beside the shaft");
    EXPECT_EQ(t.kind, PairKind::FullyVisible);
    EXPECT_EQ(stats.occludersInserted, 0u);
    std::mt19937_64 rng(1);
    for (int i = 0; i < 10; ++i) {
        const Vec3 x = test::randomPointOn(m, 0, rng);
        EXPECT_NEAR(visibleFraction(m, t, x), 1.0, 1e-12) << vis::toString(x);
    }
}

// One small square in the middle of the shaft, [1.75, 2.25]^2 at z = 2: the pair is a penumbra,
// and Algorithm 1 inserting one convex occluder into one visible leaf makes a chain, one node per
// edge (every edge splits: lines pass it on both sides, within the part the earlier edges left),
// ending in the one hidden leaf: 4 nodes, 4 visible leaves, 1 hidden, depth 4.
TEST(HistoryTreeBuilder, OneSquareMakesAChainOfItsFourEdges) {
    PolygonMesh m = receiverAndLight();
    const uint32_t square = addRectangle(m, 1.75, 1.75, 2.25, 2.25, 2);
    const HistoryTree t = vis::buildHistoryTree(m, 0, 1);
    expectWellFormed(m, t, 0, 1, {}, "one square");
    ASSERT_EQ(t.kind, PairKind::Penumbra);
    EXPECT_FALSE(t.partial());
    EXPECT_EQ(t.occluders, std::vector<uint32_t>{square});
    ASSERT_EQ(t.nodes.size(), 4u);
    EXPECT_EQ(t.leafCount(true), 4u);
    EXPECT_EQ(t.leafCount(false), 1u);
    EXPECT_EQ(t.depth(), 4u);
    std::set<std::pair<uint32_t, uint32_t>> edges;
    for (const vis::HistoryNode& n : t.nodes) edges.insert({n.v0, n.v1});
    EXPECT_EQ(edges.size(), 4u) << "each edge of the square once";
    // Shadows on L's plane (hand-derived, x + 2 (o - x)) against L = [1,3]^2 (area 4):
    struct Case {
        Vec3 x;
        double fraction;
    };
    const Case cases[] = {
        {{2, 2, 0}, 0.75},    // [1.5, 2.5]^2: 1 of 4 hidden
        {{1, 1, 0}, 0.9375},  // [2.5, 3.5]^2: [2.5, 3]^2 = 0.25 hidden
        {{2, 1, 0}, 0.875},   // [1.5, 2.5] x [2.5, 3.5]: 1 x 0.5 hidden
        {{2, 0.5, 0}, 1.0},   // [1.5, 2.5] x [3, 4]: touches L's edge y = 3, hides no area
        {{0, 0, 0}, 1.0},     // [3.5, 4.5]^2: misses L
    };
    for (const Case& c : cases) {
        EXPECT_NEAR(visibleFraction(m, t, c.x), c.fraction, 1e-12) << vis::toString(c.x);
        EXPECT_NEAR(test::exactReference(m, 0, 1, c.x).fraction, c.fraction, 1e-12);
    }
    std::mt19937_64 rng(2);
    EXPECT_GT(expectExactLabels(m, t, test::scaled(40), rng, "one square"), 0);
}

// Two plates, each blocking only part of the shaft, together every line: A = x <= 2.5 at z = 2,
// C = x >= 1.9 at z = 2.5. A line passing A (x > 2.5 at z = 2) is at x >= 2.5 - 3/8 = 2.125 at
// z = 2.5 (x changes by (lx - bx) / 8 >= -3/8 over that height), so C blocks it. Each plate alone
// leaves lines through (A: from x = 4 to x = 3 passes at 3.5; C: at z = 2.5 lines reach x = 0.625).
TEST(HistoryTreeBuilder, OccludersThatBlockEverythingOnlyTogetherGiveFullyHidden) {
    PolygonMesh m = receiverAndLight();
    const uint32_t a = addRectangle(m, -10, -10, 2.5, 10, 2);
    const uint32_t c = addRectangle(m, 1.9, -10, 10, 10, 2.5);
    const HistoryTree both = vis::buildHistoryTree(m, 0, 1);
    expectWellFormed(m, both, 0, 1, {}, "both plates");
    EXPECT_EQ(both.kind, PairKind::FullyHidden);
    EXPECT_EQ(both.why, vis::reasons::kTogetherBlockAll);
    EXPECT_EQ(both.occluders.size(), 2u);
    std::mt19937_64 rng(3);
    for (int i = 0; i < 10; ++i) {
        const Vec3 x = test::randomPointOn(m, 0, rng);
        EXPECT_EQ(visibleFraction(m, both, x), 0.0) << vis::toString(x);
        EXPECT_EQ(test::exactReference(m, 0, 1, x).fraction, 0.0) << vis::toString(x);
    }
    // Either plate alone (the candidate list restricts the occluders): a penumbra.
    for (uint32_t plate : {a, c}) {
        const std::vector<uint32_t> only{plate};
        const HistoryTree t = vis::buildHistoryTree(m, 0, 1, {}, only);
        expectWellFormed(m, t, 0, 1, {}, "one plate");
        EXPECT_EQ(t.kind, PairKind::Penumbra) << "plate " << plate;
        EXPECT_EQ(t.occluders, only);
    }
    // A alone, hand-derived: from x = (bx, 2, 0) the point l of L is visible iff
    // (bx + lx) / 2 > 2.5, i.e. lx > 5 - bx, with lx in [1, 3].
    const std::vector<uint32_t> onlyA{a};
    const HistoryTree t = vis::buildHistoryTree(m, 0, 1, {}, onlyA);
    for (const auto& [bx, fraction] :
         std::vector<std::pair<double, double>>{{0, 0}, {2, 0}, {3, 0.5}, {3.5, 0.75}, {4, 1}})
        EXPECT_NEAR(visibleFraction(m, t, {bx, 2, 0}), fraction, 1e-12) << "bx " << bx;
}

// A receiver patch: the tree is exact for the lines through the patch only, and its kind is that
// of the patch. Plate x <= 2 at z = 2: from bx <= 0.2 every line reaches z = 2 at
// x <= (0.2 + 3) / 2 = 1.6 (hidden); from bx >= 3.8 at x >= (3.8 + 1) / 2 = 2.4 (visible); the
// whole receiver is a penumbra.
TEST(HistoryTreeBuilder, ReceiverPatchesGetTheKindOfThePatch) {
    PolygonMesh m = receiverAndLight();
    addRectangle(m, -10, -10, 2, 10, 2);
    auto strip = [](double x0, double x1) {
        return std::vector<Vec3>{{x0, 0, 0}, {x1, 0, 0}, {x1, 4, 0}, {x0, 4, 0}};
    };
    const HistoryTree whole = vis::buildHistoryTree(m, 0, 1);
    expectWellFormed(m, whole, 0, 1, {}, "whole receiver");
    EXPECT_EQ(whole.kind, PairKind::Penumbra);
    const std::vector<Vec3> dark = strip(0, 0.2), lit = strip(3.8, 4), middle = strip(1, 3);
    const HistoryTree hidden = vis::buildHistoryTree(m, 0, 1, {}, {}, nullptr, dark);
    expectWellFormed(m, hidden, 0, 1, {}, "dark patch");
    EXPECT_EQ(hidden.kind, PairKind::FullyHidden);
    const HistoryTree visible = vis::buildHistoryTree(m, 0, 1, {}, {}, nullptr, lit);
    expectWellFormed(m, visible, 0, 1, {}, "lit patch");
    EXPECT_EQ(visible.kind, PairKind::FullyVisible);
    const HistoryTree part = vis::buildHistoryTree(m, 0, 1, {}, {}, nullptr, middle);
    expectWellFormed(m, part, 0, 1, {}, "middle patch");
    EXPECT_EQ(part.kind, PairKind::Penumbra);
    std::mt19937_64 rng(4);
    expectExactLabels(m, hidden, 10, rng, "dark patch", dark);
    expectExactLabels(m, visible, 10, rng, "lit patch", lit);
    EXPECT_GT(expectExactLabels(m, part, test::scaled(40), rng, "middle patch", middle), 0);
}

// ---- the build budget -----------------------------------------------------------------------

// One penumbra pair of the grids scene (many bars between the floor and the light) built under
// growing budgets: every tree is well formed and answers exactly; the occluders are inserted in
// one fixed order (a larger budget only goes further along it: fewer deferred occluders); the
// inserted and the deferred occluders together are every occluder of the pair.
TEST(HistoryTreeBuilder, EveryBudgetGivesAnExactTree) {
    const Scene scene = makeGrids();
    const PolygonMesh& m = scene.mesh;
    const uint32_t light = scene.lights[0], receiver = 0;
    BuildStats full;
    BuildOptions unlimited;
    unlimited.maxLpSolves = 0;
    const HistoryTree complete = vis::buildHistoryTree(m, receiver, light, unlimited, {}, &full);
    expectWellFormed(m, complete, receiver, light, unlimited, "unlimited");
    ASSERT_EQ(complete.kind, PairKind::Penumbra);
    ASSERT_FALSE(complete.partial());
    ASSERT_GT(full.lpSolves, 100u) << "the pair is too easy to test budgets on";
    std::mt19937_64 rng(5);
    size_t lastDeferred = SIZE_MAX;
    int partialTrees = 0, penumbraPoints = 0;
    std::vector<uint64_t> budgets = {1, 3, 10, 30, 100, full.lpSolves / 2, full.lpSolves + 1};
    std::sort(budgets.begin(), budgets.end());
    for (uint64_t budget : budgets) {
        const std::string where = "budget " + std::to_string(budget);
        BuildOptions o;
        o.maxLpSolves = budget;
        BuildStats stats;
        const HistoryTree t = vis::buildHistoryTree(m, receiver, light, o, {}, &stats);
        expectWellFormed(m, t, receiver, light, o, where);
        EXPECT_EQ(t.kind, PairKind::Penumbra) << where;
        EXPECT_EQ(stats.budgetExceeded, t.partial()) << where;
        EXPECT_EQ(stats.occludersDeferred, t.deferred.size()) << where;
        if (budget > full.lpSolves) {
            EXPECT_FALSE(t.partial()) << where;
            EXPECT_EQ(t.nodes.size(), complete.nodes.size()) << where;
        }
        if (t.partial()) {
            ++partialTrees;
            EXPECT_GT(stats.lpSolves, budget) << where << ": stopped before its budget";
            // The insertion order: the inserted occluders (the last one interrupted), then the
            // deferred ones, is the complete build's order.
            std::vector<uint32_t> order(t.occluders.begin(), t.occluders.end() - 1);
            for (const vis::DeferredOccluder& d : t.deferred) order.push_back(d.face);
            EXPECT_EQ(order, complete.occluders) << where;
            EXPECT_EQ(order.size(), full.occludersInShaft) << where;
        }
        EXPECT_LE(t.deferred.size(), lastDeferred) << where;
        lastDeferred = t.deferred.size();
        penumbraPoints += expectExactLabels(m, t, test::scaled(12), rng, where);
        // And at more points, the same answer as the complete tree (the reference is slow).
        for (int i = 0; i < 50; ++i) {
            const Vec3 x = test::randomPointOn(m, receiver, rng);
            EXPECT_NEAR(visibleFraction(m, t, x), visibleFraction(m, complete, x), 1e-12)
                << where << " at " << vis::toString(x);
        }
    }
    EXPECT_GE(partialTrees, 5);  // 1 ... 100 and half the need all stop early
    EXPECT_GT(penumbraPoints, 0);
}

// ---- cancellation ---------------------------------------------------------------------------

TEST(HistoryTreeBuilder, ARaisedCancelFlagStopsTheBuild) {
    PolygonMesh m = receiverAndLight();
    addRectangle(m, 1.75, 1.75, 2.25, 2.25, 2);
    std::atomic<bool> cancel{true};
    BuildOptions o;
    o.cancel = &cancel;
    EXPECT_THROW(vis::buildHistoryTree(m, 0, 1, o), vis::BuildCancelled);
    cancel = false;
    EXPECT_EQ(vis::buildHistoryTree(m, 0, 1, o).kind, PairKind::Penumbra);
}

// ---- every pair of several scenes -----------------------------------------------------------

// The invariants on every pair of small scenes (all receivers against every light), with and
// without the optional steps, and exact labels at a few points of each penumbra pair.
TEST(HistoryTreeBuilder, TreesOfEveryPairAreWellFormedAndExact) {
    std::vector<std::pair<std::string, Scene>> scenes = makeHardCases();
    scenes.push_back({"soup", makeRandomSoup(30, 11)});
    scenes.push_back({"cornell", makeCornellBox()});
    std::mt19937_64 rng(6);
    std::map<PairKind, int> kinds;
    int penumbraPoints = 0;
    for (const auto& [name, scene] : scenes) {
        const PolygonMesh& m = scene.mesh;
        for (uint32_t l : scene.lights)
            for (uint32_t r = 0; r < scene.faceCount(); ++r) {
                if (r == l) continue;
                const std::string where = name + " receiver " + std::to_string(r);
                for (int variant = 0; variant < 2; ++variant) {
                    BuildOptions o;
                    o.mergeLeaves = variant == 0;
                    o.quadricPruning = variant == 0;
                    const HistoryTree t = vis::buildHistoryTree(m, r, l, o);
                    expectWellFormed(m, t, r, l, o, where + (variant ? " (plain)" : ""));
                    if (variant == 1) continue;
                    ++kinds[t.kind];
                    if (t.kind == PairKind::Penumbra)
                        penumbraPoints += expectExactLabels(m, t, 2, rng, where);
                }
                if (::testing::Test::HasFailure()) return;
            }
    }
    EXPECT_GT(kinds[PairKind::Penumbra], 20);
    EXPECT_GT(kinds[PairKind::FullyVisible], 0);
    EXPECT_GT(kinds[PairKind::BackFacing], 0);
    EXPECT_GT(penumbraPoints, 10);
}

}  // namespace
}  // namespace penumbra
