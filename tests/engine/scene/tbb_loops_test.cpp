// Tests of the visibility core's builds run by oneTBB's loops (tbb_loops.h): the edge table, S_L's
// light-edge index and box hierarchies built concurrently equal the serial builds field by field
// and node by node, and equal an independent computation (a map of each face's edges; each
// edge's S_L decision and each face's side of L's plane from exact signs taken here). The mesh
// is large enough that every loop and every hierarchy split above the thresholds runs in pieces:
// a bumpy grid of triangles, some stored twice (non-manifold edges), some flipped (inconsistent
// orientation), some cut away (borders), under a light whose plane cuts the grid (Across faces).
#include "engine/scene/tbb_loops.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <optional>
#include <random>
#include <utility>
#include <vector>

#include "tests/support/test_scale.h"
#include "visibility/box_tree.h"
#include "visibility/face_plane.h"
#include "visibility/light_edge_index.h"
#include "visibility/light_silhouette_edges.h"
#include "visibility/mesh_edges.h"

namespace penumbra {
namespace {

using vis::LightEdgeIndex;
using vis::MeshEdges;
using vis::PolygonMesh;
using vis::Sign;

// An n x n grid of quads split into triangles over random heights in [0, 1], and a square light
// tilted so that its plane crosses the grid's heights; the light is the last face.
PolygonMesh bumpyGrid(int n, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> height(0.0, 1.0);
    std::uniform_int_distribution<int> pick(0, 99);
    PolygonMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.vertices.push_back({double(i), double(j), height(rng)});
    auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int r = pick(rng);
            if (r < 2) continue;  // a hole: border edges
            std::vector<uint32_t> t1{at(i, j), at(i + 1, j), at(i + 1, j + 1)};
            std::vector<uint32_t> t2{at(i, j), at(i + 1, j + 1), at(i, j + 1)};
            if (r < 5) std::swap(t1[1], t1[2]);  // flipped: inconsistently oriented edges
            m.faces.push_back(t1);
            m.faces.push_back(t2);
            if (r < 8) m.faces.push_back(t2);  // stored twice: non-manifold edges
        }
    const auto b = static_cast<uint32_t>(m.vertices.size());
    const double c = n / 2.0;
    m.vertices.push_back({c - 2, c - 2, 0.3});
    m.vertices.push_back({c - 2, c + 2, 0.7});
    m.vertices.push_back({c + 2, c + 2, 0.7});
    m.vertices.push_back({c + 2, c - 2, 0.3});
    m.faces.push_back({b, b + 1, b + 2, b + 3});
    return m;
}

void expectSameTree(const vis::BoxTree& a, const vis::BoxTree& b) {
    ASSERT_EQ(a.nodeCount(), b.nodeCount());
    for (uint32_t n = 0; n < a.nodeCount(); ++n) {
        ASSERT_EQ(a.isLeaf(n), b.isLeaf(n)) << n;
        if (!a.isLeaf(n)) {
            ASSERT_EQ(a.rightChild(n), b.rightChild(n)) << n;
        }
        EXPECT_EQ(a.nodeBox(n).lo, b.nodeBox(n).lo);
        EXPECT_EQ(a.nodeBox(n).hi, b.nodeBox(n).hi);
        const auto ia = a.nodeItems(n), ib = b.nodeItems(n);
        ASSERT_EQ(std::vector<uint32_t>(ia.begin(), ia.end()),
                  std::vector<uint32_t>(ib.begin(), ib.end()))
            << n;
    }
}

// Every node's box is the union of its items' boxes and holds its children's; the leaves' items
// are every item once: a hierarchy, whoever built it.
void expectWellFormed(const vis::BoxTree& t, size_t items) {
    std::vector<int> seen(items, 0);
    for (uint32_t n = 0; n < t.nodeCount(); ++n) {
        vis::Bounds3 u;
        for (uint32_t i : t.nodeItems(n)) {
            u.add(t.itemBox(i).lo);
            u.add(t.itemBox(i).hi);
            if (t.isLeaf(n)) ++seen[i];
        }
        EXPECT_EQ(u.lo, t.nodeBox(n).lo) << n;
        EXPECT_EQ(u.hi, t.nodeBox(n).hi) << n;
        if (!t.isLeaf(n)) {
            EXPECT_EQ(t.nodeItems(n + 1).size() + t.nodeItems(t.rightChild(n)).size(),
                      t.nodeItems(n).size());
        }
    }
    for (size_t i = 0; i < items; ++i) EXPECT_EQ(seen[i], 1) << i;
}

TEST(TbbLoops, ParallelLightEdgeIndexEqualsSerialAndAnIndependentComputation) {
    const int n = std::max(150, test::scaled(220));  // every loop in pieces at any scale
    const PolygonMesh m = bumpyGrid(n, 7);
    const auto light = static_cast<uint32_t>(m.faces.size() - 1);
    const vis::ParallelLoops loops = tbbLoops();

    // The edge table: serial and parallel equal, and equal to a map of every face's edges.
    const MeshEdges serialEdges(m), edges(m, loops);
    std::map<std::pair<uint32_t, uint32_t>, std::vector<std::pair<uint32_t, bool>>> byMap;
    for (uint32_t f = 0; f < m.faces.size(); ++f)
        for (size_t i = 0; i < m.faces[f].size(); ++i) {
            const uint32_t a = m.faces[f][i], b = m.faces[f][(i + 1) % m.faces[f].size()];
            byMap[{std::min(a, b), std::max(a, b)}].push_back({f, a < b});
        }
    ASSERT_EQ(edges.size(), byMap.size());
    ASSERT_EQ(serialEdges.size(), byMap.size());
    size_t e = 0;
    for (const auto& [key, uses] : byMap) {
        for (const MeshEdges* t : {&serialEdges, &edges}) {
            ASSERT_EQ(t->edge(e).lo, key.first);
            ASSERT_EQ(t->edge(e).hi, key.second);
            const auto got = t->uses(e);
            ASSERT_EQ(got.size(), uses.size());
            for (size_t u = 0; u < uses.size(); ++u) {
                EXPECT_EQ(got[u].face, uses[u].first);
                EXPECT_EQ(got[u].forward, uses[u].second);
            }
        }
        ++e;
    }

    // S_L: each edge decided here from exact signs of L's vertices against its faces' planes.
    const vis::LightSilhouetteEdges serialSet(m, edges, light), set(m, edges, light, loops);
    size_t kept = 0, open = 0, across = 0;
    for (size_t i = 0; i < edges.size(); ++i) {
        bool inSet = true;
        if (edges.manifold(i)) {
            const auto u = edges.uses(i);
            auto facing = [&](uint32_t f) {
                int front = 0, back = 0;
                for (uint32_t v : m.faces[light]) {
                    const Sign s = vis::facePlane(m, f).side(m.vertices[v]);
                    front += s == Sign::Positive;
                    back += s == Sign::Negative;
                }
                const int all = static_cast<int>(m.faces[light].size());
                return front == all ? 1 : back == all ? -1 : 0;
            };
            const int a = facing(u[0].face), b = facing(u[1].face);
            inSet = !(a != 0 && a == b);
        } else {
            ++open;
        }
        kept += inSet;
        EXPECT_EQ(set.contains(i), inSet) << i;
        EXPECT_EQ(serialSet.contains(i), inSet) << i;
    }
    EXPECT_EQ(set.size(), kept);
    EXPECT_EQ(set.open(), open);
    // The mesh has every kind of edge, and the light's plane cuts some faces.
    EXPECT_GT(open, 1000u);
    EXPECT_GT(kept - open, 1000u);
    EXPECT_GT(edges.size() - kept, 1000u);

    const LightEdgeIndex serial(m, serialEdges, light), index(m, edges, light, loops);
    ASSERT_EQ(index.size(), kept);
    ASSERT_EQ(serial.size(), kept);
    EXPECT_EQ(index.share(), serial.share());
    EXPECT_EQ(index.open(), open);
    // Its edges: S_L's, each once with its uses, numbered in the order of the hierarchy's leaves
    // (item p of the leaves is edge p, its box the edge's).
    std::map<std::pair<uint32_t, uint32_t>, size_t> inTable;
    for (size_t t = 0; t < edges.size(); ++t)
        if (set.contains(t)) inTable[{edges.edge(t).lo, edges.edge(t).hi}] = t;
    for (const LightEdgeIndex* x : {&serial, &index}) {
        std::vector<bool> seen(edges.size(), false);
        const auto leaves = x->edgeBoxes().nodeItems(0);
        ASSERT_EQ(leaves.size(), kept);
        for (uint32_t i = 0; i < x->size(); ++i) {
            EXPECT_EQ(leaves[i], i);
            const MeshEdges::Edge& got = x->edge(i);
            const auto at = inTable.find({got.lo, got.hi});
            ASSERT_NE(at, inTable.end()) << got.lo << "-" << got.hi;
            ASSERT_FALSE(seen[at->second]);
            seen[at->second] = true;
            const auto gotUses = x->uses(i);
            const auto want = edges.uses(at->second);
            ASSERT_EQ(gotUses.size(), want.size());
            for (size_t u = 0; u < want.size(); ++u) {
                EXPECT_EQ(gotUses[u].face, want[u].face);
                EXPECT_EQ(gotUses[u].forward, want[u].forward);
            }
            const vis::Bounds3& box = x->edgeBoxes().itemBox(i);
            for (const uint32_t v : {got.lo, got.hi}) {
                EXPECT_LE(box.lo.x, m.vertices[v].x);
                EXPECT_GE(box.hi.x, m.vertices[v].x);
            }
            EXPECT_EQ(box.lo.x, std::min(m.vertices[got.lo].x, m.vertices[got.hi].x));
            EXPECT_EQ(box.hi.z, std::max(m.vertices[got.lo].z, m.vertices[got.hi].z));
        }
    }
    // Each face's side of L's plane from its vertices' exact signs.
    const vis::FacePlane lp = vis::facePlane(m, light);
    for (uint32_t f = 0; f < m.faces.size(); ++f) {
        bool front = false, behind = false;
        for (uint32_t v : m.faces[f]) {
            const Sign s = lp.side(m.vertices[v]);
            front = front || s == Sign::Positive;
            behind = behind || s == Sign::Negative;
        }
        const auto want = !front   ? LightEdgeIndex::Side::Behind
                          : behind ? LightEdgeIndex::Side::Across
                                   : LightEdgeIndex::Side::Front;
        across += want == LightEdgeIndex::Side::Across;
        EXPECT_EQ(index.side(f), want) << f;
        EXPECT_EQ(serial.side(f), want) << f;
    }
    EXPECT_GT(across, 1000u);
    EXPECT_EQ(index.acrossCount(), across);
    // The Across faces' hierarchy holds each of them once (its items name them).
    for (uint32_t item = 0; item < index.acrossCount(); ++item) {
        EXPECT_EQ(index.side(index.acrossFace(item)), LightEdgeIndex::Side::Across) << item;
        if (item > 0) {
            EXPECT_LT(index.acrossFace(item - 1), index.acrossFace(item)) << item;
        }
    }
    // The Front faces' local numbering and corner copies (the weights' planes), the same whoever
    // built which part.
    ASSERT_EQ(index.localFaceCount(), serial.localFaceCount());
    for (uint32_t l = 0; l < index.localFaceCount(); ++l) {
        EXPECT_EQ(index.localFace(l), serial.localFace(l)) << l;
        EXPECT_EQ(index.localCorners(l), serial.localCorners(l)) << l;
    }
    EXPECT_TRUE(std::ranges::equal(index.localVertices(), serial.localVertices()));
    expectSameTree(index.edgeBoxes(), serial.edgeBoxes());
    expectSameTree(index.acrossFaces(), serial.acrossFaces());
    expectWellFormed(index.edgeBoxes(), index.size());
    // The silhouette cull's bounds per node, and the lookup of an edge by its vertices.
    EXPECT_EQ(index.silhouettes().bytes(), serial.silhouettes().bytes());
    EXPECT_TRUE(index.silhouettes() == serial.silhouettes());
    for (uint32_t i = 0; i < index.size(); i += 97) {
        EXPECT_EQ(index.find(index.edge(i).lo, index.edge(i).hi), std::optional<uint32_t>(i));
        EXPECT_EQ(serial.find(serial.edge(i).lo, serial.edge(i).hi), std::optional<uint32_t>(i));
    }
    for (size_t t = 0; t < edges.size(); t += 101) {
        if (!set.contains(t)) {
            EXPECT_EQ(index.find(edges.edge(t).lo, edges.edge(t).hi), std::nullopt);
        }
    }
}

}  // namespace
}  // namespace penumbra
