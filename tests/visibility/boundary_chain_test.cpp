// The boundary chain (visibility/boundary_chain.h) and FPQuery's evaluation by it: which edges
// cancel (hand-derived), and the answers of the chain path against the exact CGAL reference on
// meshes whose faces share their vertices: closed, open (holes), non-manifold, inconsistently
// oriented, standing on the receiver, and two touching closed components.
#include "visibility/boundary_chain.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "engine/scene/scene.h"
#include "tests/support/exact_reference.h"
#include "tests/support/face_boxes.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/box_tree.h"
#include "visibility/face_clusters.h"
#include "visibility/face_plane.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"
#include "visibility/light_edge_index.h"
#include "visibility/mesh_edges.h"
#include "visibility/pair_occluders.h"
#include "visibility/visible_outline.h"

// (Its own namespace: in a unity build it shares a file with other tests.)
namespace penumbra::boundary_chain_test {
namespace {

using vis::Vec3;

std::vector<uint32_t> remainingOf(vis::BoundaryChain& chain, std::vector<int>* weights = nullptr) {
    std::vector<uint32_t> refs;
    std::vector<int> w;
    chain.remaining(refs, w);
    if (weights != nullptr) *weights = w;
    return refs;
}

// Two triangles of one consistently oriented quad (0 1 2 3): their shared diagonal 0-2 is used
// once each way. Both facing the point: the diagonal cancels, the four sides remain. One facing
// it and one not (a fold seen edge-on): the diagonal is used twice the same way and remains.
TEST(BoundaryChain, SharedEdgeCancelsOnlyBetweenFacesTurnedTheSameWay) {
    vis::BoundaryChain chain;
    auto quad = [&](int a, int b) {
        chain.clear();
        chain.add(0, 1, a, 1);  // triangle 0 1 2: refs 1..3
        chain.add(1, 2, a, 2);
        chain.add(2, 0, a, 3);
        chain.add(0, 2, b, 4);  // triangle 0 2 3: refs 4..6
        chain.add(2, 3, b, 5);
        chain.add(3, 0, b, 6);
        return remainingOf(chain);
    };
    EXPECT_EQ(quad(1, 1), (std::vector<uint32_t>{1, 2, 5, 6}));
    EXPECT_EQ(quad(-1, -1), (std::vector<uint32_t>{1, 2, 5, 6}));
    EXPECT_EQ(quad(1, -1), (std::vector<uint32_t>{1, 2, 3, 5, 6}));
    EXPECT_EQ(chain.uses(), 6u);
    // The weights, each edge directed from its lower vertex id: the sides 0->1 and 1->2 of the
    // face of weight 1, the fold 0-2 (2->0 by weight 1, 0->2 by weight -1: -2), and 2->3 and
    // 3->0 of the face of weight -1 (-1, and +1 for 0->3).
    std::vector<int> weights;
    remainingOf(chain, &weights);
    EXPECT_EQ(weights, (std::vector<int>{1, 1, -2, -1, 1}));
}

// A closed tetrahedron seen from outside: the faces turned towards the point and those turned
// away share the silhouette; every other edge is shared by two faces turned the same way.
// Vertices 0..3 = (0,0,0), (1,0,0), (0,1,0), (0,0,1), faces oriented outwards; seen from far
// along -z (below), only face (0 2 1) faces the point: its three edges are the silhouette.
TEST(BoundaryChain, ClosedTetrahedronKeepsItsSilhouette) {
    const std::vector<std::array<uint32_t, 3>> faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    const std::vector<int> seenFromBelow = {1, -1, -1, -1};
    vis::BoundaryChain chain;
    for (size_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            chain.add(faces[f][k], faces[f][(k + 1) % 3], seenFromBelow[f],
                      static_cast<uint32_t>(f * 3 + k));
    EXPECT_EQ(remainingOf(chain), (std::vector<uint32_t>{0, 1, 2}));
    // Seen from far along (1, 1, 1): only face (1 2 3) faces the point; its edges remain, the
    // three edges at vertex 0 cancel.
    chain.clear();
    const std::vector<int> seenFromFar = {-1, -1, -1, 1};
    for (size_t f = 0; f < faces.size(); ++f)
        for (int k = 0; k < 3; ++k)
            chain.add(faces[f][k], faces[f][(k + 1) % 3], seenFromFar[f],
                      static_cast<uint32_t>(f * 3 + k));
    std::vector<uint32_t> refs = remainingOf(chain);
    ASSERT_EQ(refs.size(), 3u);
    // The first use of each remaining edge: (2 1) of face 0, (1 3) of face 1, (3 2) of face 2.
    EXPECT_EQ(refs, (std::vector<uint32_t>{1, 4, 7}));
}

// A non-manifold edge used by three faces turned the same way cannot cancel; by two turned
// opposite ways with the same direction (inconsistent orientation) it does.
TEST(BoundaryChain, NonManifoldAndInconsistentUses) {
    vis::BoundaryChain chain;
    chain.add(4, 7, 1, 0);
    chain.add(7, 4, 1, 1);
    chain.add(4, 7, 1, 2);
    EXPECT_EQ(remainingOf(chain), (std::vector<uint32_t>{0}));
    chain.clear();
    chain.add(4, 7, 1, 0);
    chain.add(4, 7, -1, 1);
    EXPECT_TRUE(remainingOf(chain).empty());
}

// ---- Meshes with shared vertices, against the exact reference -------------------------------

// A scene built vertex by vertex: face 0 the floor z = h (the receiver), face 1 the light.
class MeshScene {
  public:
    // The light [-0.5, 0.5]^2 at z = h + 2 facing down, or (`crossing`) the light x = 1.5,
    // |y| <= 0.5, z in [h - 0.5, h + 1.5] facing -x: cut by the floor's plane.
    explicit MeshScene(double h, bool crossing = false) : h_(h) {
        Material white, light;
        white.name = "white";
        light.name = "light";
        light.ke = {15, 15, 15};
        s_.materials = {white, light};
        face({vertex({-2, -2, h}), vertex({2, -2, h}), vertex({2, 2, h}), vertex({-2, 2, h})});
        if (crossing) {
            face({vertex({1.5, -0.5, h - 0.5}), vertex({1.5, -0.5, h + 1.5}),
                  vertex({1.5, 0.5, h + 1.5}), vertex({1.5, 0.5, h - 0.5})},
                 1);
        } else {
            face({vertex({-0.5, -0.5, h + 2}), vertex({-0.5, 0.5, h + 2}),
                  vertex({0.5, 0.5, h + 2}), vertex({0.5, -0.5, h + 2})},
                 1);
        }
    }
    uint32_t vertex(const Vec3& p) {
        s_.mesh.vertices.push_back(p);
        return static_cast<uint32_t>(s_.mesh.vertices.size() - 1);
    }
    void face(std::vector<uint32_t> ids, int material = 0) {
        s_.mesh.faces.push_back(std::move(ids));
        s_.faceMaterial.push_back(material);
        s_.faceSourceLine.push_back(0);
    }
    // A latitude-longitude sphere of triangles, outward, with shared vertices; `skip` leaves out
    // every skip-th face (holes; 0 = none), `flip` reverses every flip-th face (0 = none).
    void sphere(const Vec3& c, double r, int slices, int stacks, int skip = 0, int flip = 0) {
        const uint32_t south = vertex(c - Vec3{0, 0, r}), north = vertex(c + Vec3{0, 0, r});
        std::vector<std::vector<uint32_t>> ring(static_cast<size_t>(stacks - 1));
        for (int i = 1; i < stacks; ++i) {
            const double t = std::numbers::pi * i / stacks - std::numbers::pi / 2;
            for (int j = 0; j < slices; ++j) {
                const double p = 2 * std::numbers::pi * j / slices;
                ring[static_cast<size_t>(i - 1)].push_back(
                    vertex(c + Vec3{r * std::cos(t) * std::cos(p), r * std::cos(t) * std::sin(p),
                                    r * std::sin(t)}));
            }
        }
        int count = 0;
        auto tri = [&](uint32_t a, uint32_t b, uint32_t d) {
            ++count;
            if (skip != 0 && count % skip == 0) return;
            if (flip != 0 && count % flip == 0) std::swap(b, d);
            face({a, b, d});
        };
        for (int j = 0; j < slices; ++j) {
            const size_t k = static_cast<size_t>(j), n = static_cast<size_t>((j + 1) % slices);
            tri(south, ring[0][n], ring[0][k]);
            for (size_t i = 0; i + 1 < ring.size(); ++i) {
                tri(ring[i][k], ring[i][n], ring[i + 1][n]);
                tri(ring[i][k], ring[i + 1][n], ring[i + 1][k]);
            }
            tri(north, ring.back()[k], ring.back()[n]);
        }
    }
    // Every face but the floor and the light stored again, turned the other way: two-sided
    // sheets, as CFD meshes store their thin parts (the motorbike's 67,326 repeated faces).
    void twoSided() {
        const size_t n = s_.mesh.faces.size();
        for (size_t f = 2; f < n; ++f) {
            std::vector<uint32_t> turned(s_.mesh.faces[f].rbegin(), s_.mesh.faces[f].rend());
            face(std::move(turned), s_.faceMaterial[f]);
        }
    }
    // A box [lo, hi] of n x n quads per side, split into triangles, outward, shared vertices.
    void box(const Vec3& lo, const Vec3& hi, int n) {
        std::map<std::tuple<int, int, int>, uint32_t> ids;
        auto at = [&](int i, int j, int k) {
            const auto key = std::make_tuple(i, j, k);
            auto it = ids.find(key);
            if (it != ids.end()) return it->second;
            const Vec3 p{lo.x + (hi.x - lo.x) * i / n, lo.y + (hi.y - lo.y) * j / n,
                         lo.z + (hi.z - lo.z) * k / n};
            return ids[key] = vertex(p);
        };
        // Each side: a fixed axis at 0 or n, the two others over the grid, oriented outwards.
        for (int axis = 0; axis < 3; ++axis) {
            for (int end = 0; end <= n; end += n) {
                for (int a = 0; a < n; ++a) {
                    for (int b = 0; b < n; ++b) {
                        auto g = [&](int u, int v) {
                            int c[3];
                            c[axis] = end;
                            c[(axis + 1) % 3] = u;
                            c[(axis + 2) % 3] = v;
                            return at(c[0], c[1], c[2]);
                        };
                        uint32_t q[4] = {g(a, b), g(a + 1, b), g(a + 1, b + 1), g(a, b + 1)};
                        if (end == 0) std::swap(q[1], q[3]);
                        face({q[0], q[1], q[2]});
                        face({q[0], q[2], q[3]});
                    }
                }
            }
        }
    }
    // A wall x = x0 of 8 x 8 quads over y in [-1, 1], z in [z0, z1], facing -x (or +x).
    void wall(double x0, double z0, double z1, bool towardsMinusX) {
        const int n = 8;
        std::vector<std::vector<uint32_t>> id(n + 1, std::vector<uint32_t>(n + 1));
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                id[j][i] = vertex({x0, -1 + 2.0 * j / n, z0 + (z1 - z0) * i / n});
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                uint32_t q[4] = {id[j][i], id[j + 1][i], id[j + 1][i + 1], id[j][i + 1]};
                if (towardsMinusX) std::swap(q[1], q[3]);  // (y, z) counter-clockwise: +x
                face({q[0], q[1], q[2]});
                face({q[0], q[2], q[3]});
            }
    }
    // A ceiling z = z0 over [-2, 2]^2 of 8 x 8 quads, facing down.
    void ceiling(double z0) {
        const int n = 8;
        std::vector<std::vector<uint32_t>> id(n + 1, std::vector<uint32_t>(n + 1));
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                id[j][i] = vertex({-2 + 4.0 * i / n, -2 + 4.0 * j / n, z0});
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                // (x, y) clockwise seen from above: facing -z
                face({id[j][i], id[j + 1][i + 1], id[j][i + 1]});
                face({id[j][i], id[j + 1][i], id[j + 1][i + 1]});
            }
    }
    // A horizontal plate z = z0 over [x0, x1] x [y0, y1] of 8 x 8 quads, facing down (or up).
    void plate(double x0, double x1, double y0, double y1, double z0, bool facingDown) {
        const int n = 8;
        std::vector<std::vector<uint32_t>> id(n + 1, std::vector<uint32_t>(n + 1));
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i)
                id[j][i] = vertex({x0 + (x1 - x0) * i / n, y0 + (y1 - y0) * j / n, z0});
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                uint32_t a = id[j][i], b = id[j][i + 1], c = id[j + 1][i + 1], d = id[j + 1][i];
                if (facingDown) std::swap(b, d);  // (x, y) counter-clockwise from above: up
                face({a, b, c});
                face({a, c, d});
            }
    }
    // A steep bowl z = z0 + 3 (x^2 + y^2) over [-0.5, 0.5]^2 of n x n quads, facing up (inward):
    // each face's neighbours rise in front of its plane (valleys everywhere).
    void bowl(double z0, int n) {
        std::vector<std::vector<uint32_t>> id(n + 1, std::vector<uint32_t>(n + 1));
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                const double x = -0.5 + 1.0 * i / n, y = -0.5 + 1.0 * j / n;
                id[j][i] = vertex({x, y, z0 + 3 * (x * x + y * y)});
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t a = id[j][i], b = id[j][i + 1], c = id[j + 1][i + 1],
                               d = id[j + 1][i];  // (x, y) counter-clockwise from above: up
                face({a, b, c});
                face({a, c, d});
            }
    }
    // Removes face f (a hole where it was).
    void dropFace(size_t f) {
        s_.mesh.faces.erase(s_.mesh.faces.begin() + static_cast<std::ptrdiff_t>(f));
        s_.faceMaterial.erase(s_.faceMaterial.begin() + static_cast<std::ptrdiff_t>(f));
        s_.faceSourceLine.erase(s_.faceSourceLine.begin() + static_cast<std::ptrdiff_t>(f));
    }
    size_t faceCount() const { return s_.mesh.faces.size(); }
    Scene finish() {
        s_.collectLights();
        return s_;
    }
    double h() const { return h_; }

  private:
    double h_;
    Scene s_;
};

struct Measured {
    double fraction = 0, formFactor = 0;
};

Measured measure(const vis::PolygonMesh& m, const Vec3& x, const vis::FragmentList& f) {
    Measured a;
    const Vec3 n = vis::normalize(m.faceAreaNormal(0));
    double area = 0;
    for (size_t k = 0; k < f.size(); ++k) {
        area += vis::polygonArea(f[k]);
        a.formFactor += vis::formFactor(x, n, f[k]);
    }
    a.fraction = area / m.faceArea(1);
    return a;
}

// The same from the fragments' outline (visible_outline.h): the region's boundary only.
Measured measureOutline(const vis::PolygonMesh& m, const Vec3& x, const vis::FragmentList& f) {
    const vis::VisibleOutline outline = vis::visibleOutline(f.polygons());
    return {outline.area() / m.faceArea(1),
            vis::formFactorOfLoops(x, vis::normalize(m.faceAreaNormal(0)), outline.loops)};
}

// The fragments answered for x on receiver face f against the exact reference: false, and the
// first five failures reported (counted in `reported`), where they differ.
bool matchesOnFace(const vis::PolygonMesh& m, uint32_t f, const Vec3& x,
                   const vis::FragmentList& list, const test::ReferenceResult& ref,
                   const std::string& what, int& reported) {
    const Vec3 n = vis::normalize(m.faceAreaNormal(f));
    double area = 0, formFactor = 0;
    for (size_t i = 0; i < list.size(); ++i) {
        area += vis::polygonArea(list[i]);
        formFactor += vis::formFactor(x, n, list[i]);
    }
    const double fraction = area / m.faceArea(1);
    const bool ok = std::fabs(fraction - ref.fraction) <= 1e-9 &&
                    std::fabs(formFactor - ref.formFactor) <= 1e-9 * std::max(ref.formFactor, 1e-6);
    if (!ok && reported++ < 5)
        ADD_FAILURE() << what << " on face " << f << " at x = " << vis::toString(x)
                      << " answers fraction " << fraction << " form factor " << formFactor
                      << ", the exact reference " << ref.fraction << " and " << ref.formFactor;
    return ok;
}

// Of checkScene's points: how many the chain evaluated (cells were cut) on the direct path, and
// how many the partial tree answered from its silhouettes (deferred_silhouettes.h); and of the
// cells of both paths, how many were labelled by crossings (from the last counted cell's count
// and the chain edges between them) and how many were cut in all.
struct Checked {
    int chain = 0, silhouettes = 0;
    int grouped = 0;  // direct path: points that took face groups whole (face_clusters.h)
    // Of them, points that took a group its cone test left undecided, by its faces' exact sides.
    int groupedByExactSides = 0;
    int cells = 0, crossingLabels = 0;
    // Cells decided whole before the edges left in them were cut (FromPointQuery::ChainCounts).
    int hiddenWhole = 0, seenWhole = 0;
    // Cells labelled from the point of a cell holding them, found inside them on the way down.
    int refLabels = 0;
    // Points that left out faces of a closed surface seen from behind (closed_surfaces.h), and
    // points that such a surface hid whole.
    int solid = 0, hiddenBySolid = 0;
    // Points the light-edge path answered (edge_path.h), with the chain forced, and their cells.
    int lightEdges = 0, lightEdgeCells = 0;
    // Runs of the light-edge path that skipped subtrees of edges seen wholly from one side
    // (silhouette_cull.h), and the edges they skipped.
    int lightEdgeSkips = 0;
    long lightEdgesSkipped = 0;
    // Cells of the light-edge path whose point could not be certified (clipped by Algorithm 1
    // against the faces near the cell: EdgePath::activateNear).
    int lightEdgeFallbacks = 0;
    // Points FromPointQuery::runLightEdges answered (the path alone, default options).
    int lightEdgesAlone = 0;
};

// S_L and its hierarchies for light face 1 (light_edge_index.h).
vis::LightEdgeIndex lightEdgesOf(const vis::PolygonMesh& m, uint32_t light = 1) {
    return vis::LightEdgeIndex(m, vis::MeshEdges(m), light);
}

// Floor points under and around the mesh: the direct query and a partial tree's per-point
// clipping, with the chain forced and with Algorithm 1 only, against the exact reference.
Checked checkScene(const Scene& s, const std::string& what, int points, uint64_t seed,
                   const std::vector<Vec3>& given = {}) {
    vis::BuildOptions partialBudget;
    partialBudget.maxLpSolves = 1;
    vis::HistoryTree partial = vis::buildHistoryTree(s.mesh, 0, 1, partialBudget, {});
    // The silhouettes for the whole floor even where too few edges cancel there for them to pay
    // (kSilhouetteMaxKeptPercent): their answers are checked, whatever they cost.
    vis::prepareSilhouettes(s.mesh, partial, {}, 100);
    const vis::BoxTree faces = test::faceBoxTree(s.mesh);
    const vis::FaceClusters groups(s.mesh, faces);
    const vis::LightEdgeIndex lightEdges = lightEdgesOf(s.mesh);
    vis::FromPointQuery chain, oneByOne, defaults;
    // The chain, its labels by crossings, and closed surfaces as solids, always.
    chain.setChainOptions({1, 0, 0, 0});
    oneByOne.setChainOptions({0, 0});
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    Checked used;
    int reported = 0;
    for (int i = 0; i < points; ++i) {
        const Vec3 x = given.empty() ? Vec3{u(rng), u(rng), s.mesh.vertices[0].z} : given[i];
        const test::ReferenceResult ref = test::exactReference(s.mesh, 0, 1, x);
        auto compare = [&](const char* path, const Measured& a) {
            const bool ok =
                std::fabs(a.fraction - ref.fraction) <= 1e-9 &&
                std::fabs(a.formFactor - ref.formFactor) <= 1e-9 * std::max(ref.formFactor, 1e-6);
            if (!ok && reported++ < 5)
                ADD_FAILURE() << what << ": " << path << " at x = " << vis::toString(x)
                              << " answers fraction " << a.fraction << " form factor "
                              << a.formFactor << ", the exact reference " << ref.fraction << " and "
                              << ref.formFactor;
        };
        const vis::FragmentList& chained = chain.runDirect(s.mesh, 0, 1, x, faces);
        compare("direct, chain", measure(s.mesh, x, chained));
        compare("direct, chain, the outline of its fragments", measureOutline(s.mesh, x, chained));
        used.chain += chain.chainCounts().cells > 0;
        used.cells += chain.chainCounts().cells;
        used.crossingLabels += chain.chainCounts().crossingLabels;
        used.hiddenWhole += chain.chainCounts().hiddenWhole;
        used.seenWhole += chain.chainCounts().seenWhole;
        used.refLabels += chain.chainCounts().refLabels;
        compare("direct, one by one",
                measure(s.mesh, x, oneByOne.runDirect(s.mesh, 0, 1, x, faces)));
        compare("direct, face groups",
                measure(s.mesh, x, chain.runDirect(s.mesh, 0, 1, x, faces, &groups)));
        // (A group seen from behind on a surface taken as a solid is left out whole.)
        used.grouped += chain.clustersUsed() > 0 || chain.solidGroupsLeftOut() > 0;
        used.groupedByExactSides += chain.clustersUsedByExactSides() > 0;
        used.solid += chain.solidGroupsLeftOut() + chain.solidFacesLeftOut() > 0;
        used.hiddenBySolid += chain.hiddenBySolid();
        compare("direct, face groups, default options",
                measure(s.mesh, x, defaults.runDirect(s.mesh, 0, 1, x, faces, &groups)));
        // The light-edge path (the chain from S_L's edges near the cone, edge_path.h), its
        // crossings forced, then with the defaults (groups given: the path comes first).
        const vis::FragmentList& edged =
            chain.runDirect(s.mesh, 0, 1, x, faces, nullptr, &lightEdges);
        compare("direct, light edges", measure(s.mesh, x, edged));
        compare("direct, light edges, the outline of its fragments",
                measureOutline(s.mesh, x, edged));
        used.lightEdges += chain.usedLightEdges();
        used.lightEdgeCells += chain.usedLightEdges() ? chain.chainCounts().cells : 0;
        used.refLabels += chain.chainCounts().refLabels;
        if (chain.usedLightEdges()) {
            const vis::ChainCounts& k = chain.chainCounts();
            EXPECT_LE(k.lightEdgesExamined, k.occluderEdges);
            used.lightEdgeSkips += k.occluderEdges > k.lightEdgesExamined;
            used.lightEdgesSkipped += k.occluderEdges - k.lightEdgesExamined;
            used.lightEdgeFallbacks += static_cast<int>(k.fallbacks);
        }
        compare(
            "direct, light edges, default options",
            measure(s.mesh, x, defaults.runDirect(s.mesh, 0, 1, x, faces, &groups, &lightEdges)));
        // The light-edge path alone (the renderer's step after the work limit): taken only
        // where runDirect takes it (and the edges near the cone mostly cancel), with the same
        // answer; nothing answered where it is not.
        const bool took = defaults.usedLightEdges();
        const vis::FragmentList* alone =
            defaults.runLightEdges(s.mesh, 0, 1, vis::answeredAsGiven(x), faces, lightEdges);
        EXPECT_TRUE(!defaults.usedLightEdges() || took) << what << " at x = " << vis::toString(x);
        if (alone != nullptr) compare("the light-edge path alone", measure(s.mesh, x, *alone));
        used.lightEdgesAlone += alone != nullptr && defaults.usedLightEdges();
        // (Algorithm 1 only: the groups are not taken.)
        oneByOne.runDirect(s.mesh, 0, 1, x, faces, &groups);
        EXPECT_EQ(oneByOne.clustersUsed(), 0u);
        compare("partial tree, chain", measure(s.mesh, x, chain.run(s.mesh, partial, x)));
        used.silhouettes += chain.usedSilhouettes();
        used.cells += chain.chainCounts().cells;
        used.crossingLabels += chain.chainCounts().crossingLabels;
        used.hiddenWhole += chain.chainCounts().hiddenWhole;
        used.seenWhole += chain.chainCounts().seenWhole;
        used.refLabels += chain.chainCounts().refLabels;
        compare("partial tree, one by one", measure(s.mesh, x, oneByOne.run(s.mesh, partial, x)));
        EXPECT_FALSE(oneByOne.usedSilhouettes());  // the chain is off
    }
    return used;
}

TEST(BoundaryChainQuery, ClosedSphereMatchesTheExactReference) {
    MeshScene m(0);
    m.sphere({0.1, -0.05, 0.9}, 0.45, 16, 10);
    const Checked used = checkScene(m.finish(), "sphere", test::scaled(60), 1);
    EXPECT_GT(used.chain, test::scaled(60) / 3);
    // Most points see groups of the sphere's faces one way: they enter the chain whole.
    EXPECT_GT(used.grouped, test::scaled(60) / 2);
    // Near the sphere the cone test of a group is not certain; its faces' exact sides decide.
    EXPECT_GT(used.groupedByExactSides, test::scaled(60) / 4);
    // Every point is in the face's region and the sphere's edges cancel: always the silhouettes.
    EXPECT_EQ(used.silhouettes, test::scaled(60));
    // Most cells follow from the one before them (the first of each run is counted on its line).
    EXPECT_GT(used.crossingLabels, used.cells / 2);
    // No face near L's plane: every point takes the light-edge path.
    EXPECT_EQ(used.lightEdges, test::scaled(60));
    EXPECT_GT(used.lightEdgesAlone, 0);
    EXPECT_GT(used.lightEdgeCells, test::scaled(60));
    // From below, the sphere's lower cap faces every point and its upper cap faces none: those
    // subtrees of S_L hold no silhouette and are skipped whole at most points (the answers the
    // same as the reference's).
    EXPECT_GT(used.lightEdgeSkips, test::scaled(60) / 2);
}

// Three closed spheres that overlap as seen from the floor: where their shadows overlap a line
// crosses four faces or six, more than the few silhouette edges left in a small cell can take
// away, so cells are decided hidden before those edges cut them (decideCellWhole); the answers
// still match the exact reference.
TEST(BoundaryChainQuery, CellsDecidedWholeUnderOverlappingSpheresMatchTheExactReference) {
    MeshScene m(0);
    m.sphere({0.1, -0.05, 0.7}, 0.4, 16, 10);
    m.sphere({-0.15, 0.1, 1.15}, 0.3, 16, 10);
    m.sphere({0.05, 0.2, 1.55}, 0.2, 12, 8);
    const Checked used = checkScene(m.finish(), "overlapping spheres", test::scaled(60), 5);
    EXPECT_GT(used.chain, test::scaled(60) / 3);
    EXPECT_GT(used.hiddenWhole, 0);
    // Decided whole, a cell is not cut further: fewer cells than the leaves would be.
    EXPECT_LT(used.hiddenWhole + used.seenWhole, used.cells);
    // A cell's point that did not decide it lies in one of the cells it is cut into, which is
    // then decided or labelled from it (no point of its own), with the same answers.
    EXPECT_GT(used.refLabels, 0);
    EXPECT_EQ(used.lightEdges, test::scaled(60));
    EXPECT_GT(used.lightEdgesAlone, 0);
}

// Closed surfaces taken as solids (closed_surfaces.h): a floor point leaves out the faces of a
// closed mesh it sees from behind, where nothing of the mesh's open edges, nothing that reaches
// L's plane and nothing through x lies in its pyramid, and the mesh's winding along one segment
// to L is 0; where that winding is not 0 (x inside the mesh) it sees nothing. A sphere sunk into
// the floor (points inside it), a box standing on the floor (points under it, on its bottom's
// plane, and on the foot of its sides: x on their planes, their component is then no solid),
// and a box that crosses the floor (points on its contact lines).
TEST(BoundaryChainQuery, ClosedSurfacesTakenAsSolidsMatchTheExactReference) {
    MeshScene m(0);
    m.sphere({-0.5, 0.5, 0.1}, 0.45, 14, 9);
    m.box({0.25, -0.75, 0}, {0.75, -0.25, 0.5}, 3);
    m.box({-0.75, -0.75, -0.25}, {-0.25, -0.25, 0.75}, 2);
    std::vector<Vec3> points;
    std::mt19937_64 rng(31);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    for (int i = 0; i < test::scaled(40); ++i) points.push_back({u(rng), u(rng), 0});
    for (int i = 0; i <= 8; ++i) {
        const double t = i / 8.0;
        points.push_back({0.25 + 0.5 * t, -0.75, 0});   // on a side of the standing box
        points.push_back({0.25 + 0.25 * t, -0.5, 0});   // under it
        points.push_back({-0.25, -0.75 + 0.5 * t, 0});  // on a side of the crossing box
        points.push_back({-0.5, 0.5 + 0.5 * t, 0});     // inside the sphere, and out of it
    }
    const Checked c = checkScene(m.finish(), "solids", static_cast<int>(points.size()), 0, points);
    EXPECT_GT(c.solid, static_cast<int>(points.size()) / 8);
    EXPECT_GT(c.hiddenBySolid, 4);
    EXPECT_EQ(c.lightEdges, static_cast<int>(points.size()));
}

// Where a closed mesh's winding is not constant over the cone, the mesh is no solid: a hole in
// a sphere's underside (a segment through it crosses only a face seen from behind), and a box
// that holds part of the floor and part of the light (segments from inside it reach the part of
// the light inside without crossing any face, the others cross a face seen from behind; from
// outside, a segment to a corner inside crosses one seen from the front, the others none).
TEST(BoundaryChainQuery, ClosedSurfacesWhoseWindingChangesInTheConeAreNoSolids) {
    {
        MeshScene m(0);
        const size_t first = m.faceCount();
        m.sphere({0.1, -0.05, 1.0}, 0.5, 14, 9);
        m.dropFace(first + 16 * 3);  // the face at the south pole of the fourth slice
        std::vector<Vec3> points;
        for (int i = -4; i <= 4; ++i)
            for (int j = -4; j <= 4; ++j) points.push_back({i / 4.0, j / 4.0, 0});
        const Checked c =
            checkScene(m.finish(), "sphere, one hole", static_cast<int>(points.size()), 0, points);
        EXPECT_GT(c.solid, 0);  // where the hole is out of the pyramid
        EXPECT_EQ(c.hiddenBySolid, 0);
    }
    {
        MeshScene m(0);
        m.box({-3, -3, -1}, {0.25, 3, 2.5}, 8);  // (fine enough for face groups)
        const Checked c = checkScene(m.finish(), "box around the light", test::scaled(40), 33);
        EXPECT_EQ(c.hiddenBySolid, 0);
    }
}

// A closed sphere (faces first .. first + 160, 16 slices of 10 stacks) over the floor, shaded by
// a smaller one above it; the face hierarchy and groups of the direct path.
struct SphereUnderSphere {
    Scene s;
    uint32_t first = 0;
    vis::BoxTree faces;
    vis::FaceClusters groups;
    vis::LightEdgeIndex lightEdges;
    SphereUnderSphere() {
        MeshScene m(0);
        first = static_cast<uint32_t>(m.faceCount());
        m.sphere({0, 0, 0.6}, 0.5, 16, 10);
        m.sphere({0.3, 0.1, 1.45}, 0.25, 12, 8);
        s = m.finish();
        faces = test::faceBoxTree(s.mesh);
        groups = vis::FaceClusters(s.mesh, faces);
        lightEdges = lightEdgesOf(s.mesh);
    }
};

// Receivers on a closed mesh: points on the faces of a sphere, shaded by a second sphere above
// it; x is a rounded point of its face, off its plane by a rounding either way (behind it, the
// receiver's own component is no solid: what lies in its plane may then reach into the cone).
TEST(BoundaryChainQuery, PointsOnAClosedMeshUnderAnotherMatchTheExactReference) {
    const SphereUnderSphere scene;
    const Scene& s = scene.s;
    const uint32_t first = scene.first;
    const vis::BoxTree& faces = scene.faces;
    const vis::FaceClusters& groups = scene.groups;
    vis::FromPointQuery query;
    vis::FromPointQuery::ChainOptions solidsAlways;
    solidsAlways.solidMinFaces = 0;
    query.setChainOptions(solidsAlways);
    std::mt19937_64 rng(41);
    int checked = 0, solid = 0, penumbra = 0, reported = 0, lightEdges = 0;
    for (uint32_t f = first; f < first + 16 * 10 && checked < test::scaled(120); ++f) {
        if (vis::normalize(s.mesh.faceAreaNormal(f)).z < 0.3) continue;  // facing the light
        const Vec3 x = test::randomPointOn(s.mesh, f, rng);
        ++checked;
        const test::ReferenceResult ref = test::exactReference(s.mesh, f, 1, x);
        penumbra += ref.fraction > 0.001 && ref.fraction < 0.999;
        matchesOnFace(s.mesh, f, x, query.runDirect(s.mesh, f, 1, x, faces, &groups), ref,
                      "direct, face groups", reported);
        solid += query.solidGroupsLeftOut() + query.solidFacesLeftOut() > 0;
        // Self-shadowing through the light-edge path: x on a face of the mesh whose edges are
        // in S_L (its own face left out of every weight, the contact rule at its neighbours).
        matchesOnFace(s.mesh, f, x,
                      query.runDirect(s.mesh, f, 1, x, faces, &groups, &scene.lightEdges), ref,
                      "direct, light edges", reported);
        lightEdges += query.usedLightEdges();
    }
    EXPECT_GE(checked, test::scaled(120) / 2);
    EXPECT_GT(penumbra, checked / 8);
    EXPECT_GT(solid, 0);
    EXPECT_GT(lightEdges, checked / 4);  // (not those a rounding behind their face's plane)
}

// Receiver points on the edges of a closed mesh: x rounded from a point of an edge its face
// shares with a neighbour, so that x may lie a rounding behind the face's plane with the
// neighbour's plane through or near it; the neighbour's sliver between x and B's plane must
// block nothing (only what lies in front of B's plane occludes, exact_reference.h), and what
// the neighbour hides beyond B's plane must be hidden. And the edge's vertex itself, exactly in
// the planes of the faces around it. Each point is taken as a point of both faces that share
// the edge, on every direct path.
TEST(BoundaryChainQuery, PointsOnTheEdgesOfAClosedMeshMatchTheExactReference) {
    const SphereUnderSphere scene;
    const Scene& s = scene.s;
    const uint32_t first = scene.first;
    const vis::BoxTree& faces = scene.faces;
    const vis::FaceClusters& groups = scene.groups;
    vis::FromPointQuery chain, oneByOne, defaults;
    chain.setChainOptions({1, 0, 0, 0});  // the chain, crossings and solids always
    oneByOne.setChainOptions({0, 0});
    std::mt19937_64 rng(43);
    std::uniform_real_distribution<double> u(0, 1);
    // The faces of the lower sphere that use each directed edge.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> edgeFace;
    const uint32_t last = first + 16 * 10;
    for (uint32_t f = first; f < last; ++f) {
        const auto& ids = s.mesh.faces[f];
        for (size_t i = 0; i < ids.size(); ++i) edgeFace[{ids[i], ids[(i + 1) % ids.size()]}] = f;
    }
    int checked = 0, penumbra = 0, behind = 0, reported = 0, lightEdges = 0;
    for (uint32_t f = first; f < last && checked < test::scaled(64); ++f) {
        if (vis::normalize(s.mesh.faceAreaNormal(f)).z < 0.3) continue;  // facing the light
        const auto& ids = s.mesh.faces[f];
        for (size_t i = 0; i < ids.size(); ++i) {
            const auto other = edgeFace.find({ids[(i + 1) % ids.size()], ids[i]});
            if (other == edgeFace.end()) continue;
            const Vec3 a = s.mesh.vertices[ids[i]], b = s.mesh.vertices[ids[(i + 1) % ids.size()]];
            // The rounded midpoint, a rounded random point, and the edge's first vertex itself
            // (x exactly in the planes of every face around it).
            const double t = i % 3 == 0 ? 0.5 : i % 3 == 1 ? u(rng) : 0.0;
            const Vec3 x = a + (b - a) * t;
            for (const uint32_t g : {f, other->second}) {
                if (vis::normalize(s.mesh.faceAreaNormal(g)).z < 0.3) continue;
                ++checked;
                behind += vis::facePlane(s.mesh, g).orient().sign(x) == vis::Sign::Negative;
                const test::ReferenceResult ref = test::exactReference(s.mesh, g, 1, x);
                penumbra += ref.fraction > 0.001 && ref.fraction < 0.999;
                matchesOnFace(s.mesh, g, x, chain.runDirect(s.mesh, g, 1, x, faces), ref,
                              "edge point, direct, chain", reported);
                matchesOnFace(s.mesh, g, x, oneByOne.runDirect(s.mesh, g, 1, x, faces), ref,
                              "edge point, direct, one by one", reported);
                matchesOnFace(s.mesh, g, x, chain.runDirect(s.mesh, g, 1, x, faces, &groups), ref,
                              "edge point, direct, face groups and solids", reported);
                matchesOnFace(s.mesh, g, x, defaults.runDirect(s.mesh, g, 1, x, faces, &groups),
                              ref, "edge point, direct, default options", reported);
                matchesOnFace(s.mesh, g, x,
                              chain.runDirect(s.mesh, g, 1, x, faces, nullptr, &scene.lightEdges),
                              ref, "edge point, direct, light edges", reported);
                lightEdges += chain.usedLightEdges();
            }
        }
    }
    EXPECT_GE(checked, test::scaled(64) / 2);
    EXPECT_GT(penumbra, checked / 8);
    EXPECT_GT(behind, checked / 8);  // x behind its face's plane by a rounding was exercised
    // (A point strictly behind its face's plane takes the face-by-face path.)
    EXPECT_GT(lightEdges, checked / 4);
}

TEST(BoundaryChainQuery, OpenInconsistentAndNonManifoldMeshesMatchTheExactReference) {
    {
        MeshScene m(0);
        m.sphere({0, 0, 1}, 0.5, 14, 9, 7);  // holes: every 7th face left out
        const Checked c = checkScene(m.finish(), "sphere with holes", test::scaled(40), 2);
        EXPECT_GT(c.chain, 0);
        EXPECT_GT(c.crossingLabels, c.cells / 2);
        EXPECT_EQ(c.silhouettes, test::scaled(40));
        EXPECT_EQ(c.lightEdges, test::scaled(40));  // (open edges are always in S_L)
    }
    {
        MeshScene m(0);
        m.sphere({0, 0.1, 1}, 0.5, 14, 9, 0, 5);  // every 5th face reversed
        const Checked c = checkScene(m.finish(), "inconsistent sphere", test::scaled(40), 3);
        EXPECT_GT(c.chain, 0);
        EXPECT_GT(c.crossingLabels, c.cells / 2);
        EXPECT_EQ(c.silhouettes, test::scaled(40));
        EXPECT_EQ(c.lightEdges, test::scaled(40));  // (open edges are always in S_L)
    }
    {
        // A box with a fin on its top edge: that edge has three faces.
        MeshScene m(0);
        m.box({-0.3, -0.3, 0.6}, {0.3, 0.3, 1.1}, 3);
        const Scene boxOnly = m.finish();
        uint32_t p = 0, q = 0;  // two top corners of the box
        for (uint32_t v = 0; v < boxOnly.mesh.vertices.size(); ++v) {
            const Vec3& c = boxOnly.mesh.vertices[v];
            if (c.z == 1.1 && c.y == -0.3 && c.x == -0.3) p = v;
            if (c.z == 1.1 && c.y == -0.3 && c.x == 0.3) q = v;
        }
        ASSERT_NE(p, q);
        const uint32_t top = m.vertex({0, -0.6, 1.5});
        m.face({p, q, top});
        const Checked c = checkScene(m.finish(), "box with a fin", test::scaled(40), 4);
        EXPECT_GT(c.chain, 0);
        EXPECT_GT(c.crossingLabels, c.cells / 2);
        EXPECT_EQ(c.silhouettes, test::scaled(40));
        EXPECT_EQ(c.lightEdges, test::scaled(40));  // (open edges are always in S_L)
    }
}

// Two-sided sheets: a sphere with holes, and a box under a loose triangle, each face stored twice,
// the copy turned the other way. Every edge is non-manifold (in S_L whatever the light), and a
// point sees one copy of each face from the front and the other from behind; the light-edge path's
// cull counts a copy as the face it repeats (light_edge_index.h), so subtrees the point sees from
// one side are still skipped, and every answer is the exact reference's.
TEST(BoundaryChainQuery, TwoSidedSheetsMatchTheExactReference) {
    {
        MeshScene m(0);
        m.sphere({0, 0, 1}, 0.5, 14, 9, 7);  // holes: every 7th face left out
        m.twoSided();
        const Checked c =
            checkScene(m.finish(), "two-sided sphere with holes", test::scaled(40), 6);
        EXPECT_GT(c.chain, 0);
        EXPECT_EQ(c.lightEdges, test::scaled(40));
        EXPECT_GT(c.lightEdgesAlone, 0);
        // Not possible with both copies counted apart: no node would hold faces all on one side.
        EXPECT_GT(c.lightEdgeSkips, test::scaled(40) / 4);
    }
    {
        MeshScene m(0);
        m.box({-0.3, -0.3, 0.6}, {0.3, 0.3, 1.1}, 3);
        m.face({m.vertex({-0.3, -0.3, 1.1}), m.vertex({0.3, -0.3, 1.1}), m.vertex({0, -0.6, 1.5})});
        m.twoSided();
        const Checked c =
            checkScene(m.finish(), "two-sided box under a triangle", test::scaled(40), 7);
        EXPECT_GT(c.chain, 0);
        EXPECT_EQ(c.lightEdges, test::scaled(40));
    }
}

// Standing exactly on the receiver (its bottom in the floor's plane, its sides touching it), a
// box and a sphere that touches it: contact, chords and two closed components.
TEST(BoundaryChainQuery, MeshesStandingOnTheReceiverMatchTheExactReference) {
    for (double h : {0.0, 0.1, 1e5}) {
        MeshScene m(h);
        m.box({-0.4, -0.3, h}, {0.2, 0.35, h + 0.7}, 4);
        m.sphere({0.45, 0.1, h + 0.35}, 0.25, 12, 8);
        const Checked c =
            checkScene(m.finish(), "standing, h = " + std::to_string(h), test::scaled(40), 5);
        EXPECT_GT(c.chain, 0);
        EXPECT_GT(c.crossingLabels, c.cells / 3);
        EXPECT_EQ(c.silhouettes, test::scaled(40));
        EXPECT_EQ(c.lightEdges, test::scaled(40));
    }
}

// A light that the floor's plane cuts: the cells are bounded by the cone over the whole light,
// the answer is its part in front of the floor.
TEST(BoundaryChainQuery, LightCutByTheReceiverPlaneMatchesTheExactReference) {
    MeshScene m(0, true);
    m.sphere({0.8, 0.05, 0.45}, 0.3, 14, 9);
    m.box({0.3, -0.6, 0}, {0.5, -0.2, 0.5}, 2);
    const Checked c = checkScene(m.finish(), "light cut by the floor", test::scaled(60), 7);
    EXPECT_GT(c.chain, test::scaled(60) / 4);
    // The floor points lie on B's plane: the chords where it cuts the occluders are left out of
    // the chain (they change c only beyond that plane), and the cells are labelled by crossings
    // (each from a point strictly in front of the floor).
    EXPECT_GT(c.crossingLabels, c.cells / 2);
    EXPECT_EQ(c.silhouettes, test::scaled(60));
    EXPECT_EQ(c.lightEdges, test::scaled(60));
}

// Points on the faces of a bowl, many of whose planes cut the light: x is a rounded point of its
// face, off the face's exact plane by a rounding, and the face's own edges belong to its
// neighbours, occluders that rise in front of it, so the plane through x and such an edge is not
// the face's plane (a cell near the line where the face's plane cuts the light may lie between
// the two). Against the exact reference, the chain forced, with and without groups.
TEST(BoundaryChainQuery, PointsOnBowlFacesWhosePlanesCutTheLightMatchTheExactReference) {
    MeshScene m(0, true);  // the light upright at x = 1.5, facing the bowl
    m.bowl(0.2, 12);
    const Scene s = m.finish();
    const vis::BoxTree faces = test::faceBoxTree(s.mesh);
    const vis::FaceClusters groups(s.mesh, faces);
    const vis::LightEdgeIndex lightEdges = lightEdgesOf(s.mesh);
    vis::FromPointQuery chain, defaults;
    chain.setChainOptions({1, 0, 0});
    std::mt19937_64 rng(11);
    int checked = 0, cut = 0, cells = 0, reported = 0, edgePath = 0;
    for (uint32_t f = 2; f < s.faceCount() && checked < test::scaled(240); ++f) {
        const vis::FacePlane plane = vis::facePlane(s.mesh, f);
        bool front = false, behind = false;  // the light's corners against the face's plane
        for (uint32_t v : s.mesh.faces[1]) {
            const vis::Sign side = plane.side(s.mesh.vertices[v]);
            front = front || side == vis::Sign::Positive;
            behind = behind || side == vis::Sign::Negative;
        }
        if (!front) continue;
        cut += behind;
        for (int k = 0; k < 2; ++k, ++checked) {
            const Vec3 x = test::randomPointOn(s.mesh, f, rng);
            const test::ReferenceResult ref = test::exactReference(s.mesh, f, 1, x);
            auto compare = [&](const char* path, const vis::FragmentList& list) {
                matchesOnFace(s.mesh, f, x, list, ref, path, reported);
            };
            compare("chain", chain.runDirect(s.mesh, f, 1, x, faces));
            cells += chain.chainCounts().cells;
            compare("chain, face groups", chain.runDirect(s.mesh, f, 1, x, faces, &groups));
            compare("defaults, face groups", defaults.runDirect(s.mesh, f, 1, x, faces, &groups));
            compare("light edges", chain.runDirect(s.mesh, f, 1, x, faces, nullptr, &lightEdges));
            edgePath += chain.usedLightEdges();
        }
    }
    EXPECT_GE(checked, test::scaled(240) / 2);
    EXPECT_GT(cut, checked / 8);  // faces whose plane cuts the light
    EXPECT_GT(cells, checked);
    // The floor, cut by the upright light's plane, meets every point's cone (its chord on that
    // plane bounds shadows, no input edge does): the light-edge path is never taken here.
    EXPECT_EQ(edgePath, 0);
}

// The chords where the floor's plane cuts the occluders, seen from floor points a rounding off
// that plane: a light upright through the floor's plane, a sphere and a box sunk into the floor,
// the whole scene rotated and translated in doubles. Each point is taken as rounded from its
// barycentric weights, then moved along the normal by the fewest ulps that put it strictly
// behind the floor's plane and on or in front of it (the exact test): from behind, the chords'
// planes through x cut a strip some ulps wide along the floor's edge of the light, where c jumps
// by amounts the chain does not hold (the crossings give up across them); from in front or on
// the plane the chords are left out of the chain and the cells are labelled from points strictly
// in front of the floor. Both against the exact reference, the chain and its crossings forced,
// and with the defaults and groups.
TEST(BoundaryChainQuery, RoundedFloorPointsUnderMeshesSunkIntoTheFloorMatchTheExactReference) {
    std::mt19937_64 rng(23);
    std::uniform_real_distribution<double> u(-1, 1);
    int reported = 0, front = 0, behind = 0;
    int frontCells = 0, frontCrossings = 0, behindCrossings = 0, edgePath = 0;
    for (int i = 0; i < test::scaled(6); ++i) {
        MeshScene m(0, true);  // the light x = 1.5, z in [-0.5, 1.5]: cut by the floor's plane
        m.sphere({0.8 + 0.1 * u(rng), 0.05, 0.1}, 0.3, 14, 9);
        m.box({0.2, -0.7, -0.2}, {0.5, -0.2, 0.4 + 0.1 * u(rng)}, 2);
        Scene s = m.finish();
        s.mesh.faces[0].resize(3);  // triangles: a rotated quad would not stay planar
        s.mesh.faces[1].resize(3);
        const double a = 3 * u(rng), b = 3 * u(rng);
        const Vec3 t{50 * u(rng), 50 * u(rng), 50 * u(rng)};
        auto transform = [&](const Vec3& v) {
            Vec3 p{std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y,
                   v.z};
            p = {p.x, std::cos(b) * p.y - std::sin(b) * p.z, std::sin(b) * p.y + std::cos(b) * p.z};
            return p + t;
        };
        for (Vec3& v : s.mesh.vertices) v = transform(v);
        const vis::BoxTree faces = test::faceBoxTree(s.mesh);
        const vis::FaceClusters groups(s.mesh, faces);
        const vis::LightEdgeIndex lightEdges = lightEdgesOf(s.mesh);
        vis::FromPointQuery chain, defaults;
        chain.setChainOptions({1, 0, 0});
        const vis::PlaneOrient floor = vis::facePlane(s.mesh, 0).orient();
        const Vec3 n = vis::normalize(s.mesh.faceAreaNormal(0));
        std::vector<Vec3> corner;
        for (uint32_t v : s.mesh.faces[0]) corner.push_back(s.mesh.vertices[v]);
        for (int k = 0; k < 12; ++k) {
            // A point of the floor triangle (-2,-2) (2,-2) (2,2) near the meshes, or (every
            // other one) on the box's contact line with the floor, where the box's faces cross
            // its plane: the chords start there, and the strip their planes cut from behind is
            // wide (the incident of a rotated wall's contact line: off by 0.4 of the light);
            // some at its corners, where its edges cross that plane a rounding from x.
            Vec3 rounded;
            if (k % 2 == 0) {
                double px = 0.6 + 0.6 * u(rng), py = 0.6 * u(rng) - 0.3;
                if (py > px) std::swap(px, py);
                const double w0 = (2 - px) / 4, w2 = (py + 2) / 4, w1 = 1 - w0 - w2;
                rounded = corner[0] * w0 + corner[1] * w1 + corner[2] * w2;
            } else if (k % 4 == 1) {
                const double along = 0.5 + 0.45 * u(rng);
                rounded = transform(k % 8 == 1 ? Vec3{0.5, -0.7 + 0.5 * along, 0}
                                               : Vec3{0.2 + 0.3 * along, -0.2, 0});
            } else {  // a corner, where a vertical edge of the box crosses the floor's plane
                rounded = transform({k % 8 == 3 ? 0.5 : 0.2, (k / 4) % 2 == 0 ? -0.2 : -0.7, 0});
            }
            // The fewest doubling steps along +n (-n) that reach the wanted side.
            auto moved = [&](double direction, bool wantBehind) {
                Vec3 x = rounded;
                for (double step = 0x1p-60; step < 1; step *= 2) {
                    const vis::Sign side = floor.sign(x);
                    if ((side == vis::Sign::Negative) == wantBehind) return x;
                    x = rounded + n * (direction * step);
                }
                ADD_FAILURE() << "no point on the wanted side near " << vis::toString(rounded);
                return rounded;
            };
            for (const bool wantBehind : {true, false}) {
                const Vec3 x = moved(wantBehind ? -1 : 1, wantBehind);
                const test::ReferenceResult ref = test::exactReference(s.mesh, 0, 1, x);
                const std::string where = wantBehind ? "behind the floor" : "on or in front";
                matchesOnFace(s.mesh, 0, x, chain.runDirect(s.mesh, 0, 1, x, faces), ref,
                              "chain, " + where, reported);
                const vis::FromPointQuery::ChainCounts c = chain.chainCounts();
                (wantBehind ? behind : front) += 1;
                (wantBehind ? behindCrossings : frontCrossings) += c.crossingLabels;
                if (!wantBehind) frontCells += c.cells;
                matchesOnFace(s.mesh, 0, x, chain.runDirect(s.mesh, 0, 1, x, faces, &groups), ref,
                              "chain, face groups, " + where, reported);
                matchesOnFace(s.mesh, 0, x, defaults.runDirect(s.mesh, 0, 1, x, faces, &groups),
                              ref, "defaults, face groups, " + where, reported);
                matchesOnFace(s.mesh, 0, x,
                              chain.runDirect(s.mesh, 0, 1, x, faces, nullptr, &lightEdges), ref,
                              "light edges, " + where, reported);
                edgePath += chain.usedLightEdges();
            }
        }
    }
    EXPECT_EQ(front, behind);
    // From in front, with the chords left out, most cells are labelled by crossings; from
    // behind, some are (the crossings give up only across a chord's plane).
    EXPECT_GT(frontCrossings, frontCells / 2);
    EXPECT_GT(behindCrossings, 0);
    // The points on or in front of the floor (and none strictly behind it).
    EXPECT_GT(edgePath, 0);
    EXPECT_LE(edgePath, front);
}

// A mesh that crosses the light's plane and the floor's plane (clipped: chords on both).
TEST(BoundaryChainQuery, MeshCrossingBothPlanesMatchesTheExactReference) {
    {
        MeshScene m(0);
        m.box({-0.35, -0.25, -0.2}, {0.3, 0.2, 2.3}, 3);
        // Two thirds of its faces cross a plane: too few edges cancel for the silhouettes.
        const Checked c = checkScene(m.finish(), "crossing box", test::scaled(40), 6);
        EXPECT_EQ(c.silhouettes, 0);
        // Its faces cut by L's plane lie in every point's cone (their chords there bound the
        // shadow, no input edge does): the light-edge path is never taken.
        EXPECT_EQ(c.lightEdges, 0);
    }
    {
        // With a sphere beside it the silhouettes pay: the box's faces that cross a plane are
        // activated per point, the middle row is surface, and the edges between the two rows
        // are summed from both.
        MeshScene m(0);
        m.box({-0.35, -0.25, -0.2}, {0.3, 0.2, 2.3}, 3);
        m.sphere({0.6, 0.55, 1.0}, 0.25, 16, 10);
        EXPECT_EQ(
            checkScene(m.finish(), "crossing box and sphere", test::scaled(40), 8).silhouettes,
            test::scaled(40));
    }
}

// Flat plates of many faces, whose groups the floor points certainly see one way: a ceiling
// above the light (every line from x through the light meets it beyond the light: a group
// behind L's plane taken whole would hide the whole light), a wall rising through the light's
// plane beside the light (the same for its upper part), and one going down through the floor's
// plane. Their groups strictly between the two planes are taken whole.
TEST(BoundaryChainQuery, GroupsBeyondAndThroughTheLightAndFloorPlanesMatchTheExactReference) {
    MeshScene m(0);
    m.wall(0.7, 1.0, 3.0, true);     // through the light's plane z = 2
    m.wall(-0.7, -0.5, 1.2, false);  // through the floor's plane z = 0
    m.ceiling(2.5);
    const Checked c = checkScene(m.finish(), "plates", test::scaled(60), 9);
    EXPECT_GT(c.grouped, test::scaled(60) / 8);
    // The wall's rows meet L's plane z = 2 at a row of vertices: none of its faces is cut by
    // it (those above are behind L, whole), so every point takes the light-edge path.
    EXPECT_EQ(c.lightEdges, test::scaled(60));
}

// Contact lines everywhere: boxes on a dyadic grid (a stack sharing a face, one touching
// another along an edge), the light's corners and the floor points on the same grid, so that
// lines from x through box vertices pass exactly through the light's corners and other boxes'
// vertices, edges of different boxes line up seen from x, and cells and sample triangles touch
// chain edges (the crossings' zero signs, where the count is taken on the line instead).
TEST(BoundaryChainQuery, ContactLinesOnADyadicGridMatchTheExactReference) {
    MeshScene m(0);
    m.box({-0.25, -0.25, 0.75}, {0.25, 0.25, 1.0}, 1);
    m.box({-0.25, -0.25, 1.0}, {0.25, 0.25, 1.25}, 2);  // stacked: the face z = 1 twice
    m.box({0.25, -0.25, 0.5}, {0.75, 0.25, 0.75}, 1);   // touches the first along an edge
    m.box({-0.75, 0.25, 0.5}, {-0.25, 0.5, 1.5}, 2);
    std::vector<Vec3> grid;
    for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j) grid.push_back({i / 4.0, j / 4.0, 0});
    const Checked c =
        checkScene(m.finish(), "dyadic boxes", static_cast<int>(grid.size()), 0, grid);
    EXPECT_GT(c.chain, static_cast<int>(grid.size()) / 4);
    EXPECT_GT(c.crossingLabels, c.cells / 3);
    EXPECT_EQ(c.lightEdges, static_cast<int>(grid.size()));
}

// Slivers: pairs of triangles sharing a corner P, one on each side of an edge from P, the second
// triangle's edge ending some ulps from the first's (PQ and PQ', Q' k ulps off Q in one to three
// coordinates, k = 4, 6, 8). Seen from a floor point the planes through x and PQ, PQ' are nearly
// the same, so they cut the light into wedges barely wider than the rounding of a point inside
// them (where both triangles cover the lines, or neither): where no point of such a cell can be
// certified, the light-edge path clips it by Algorithm 1 against the faces near the cell
// (EdgePath::activateNear). Its answers, and every other path's, against the exact reference.
// (At k = 1 or 2 the cut's snap rule leaves no such cell: none falls back.) What this shows is
// that the path runs there and every answer stays within 1e-9 of the exact one; a cell this thin
// holds far less of L than that, so its own label is below what the comparison sees (activating
// no face for it passes too). That the faces activated are all that can meet the cell is the
// argument of Algorithm 1's own cull for a polygon, whose planes it takes (hullCone).
TEST(BoundaryChainQuery, LightEdgeCellsThinnerThanTheirRoundingMatchTheExactReference) {
    auto step = [](double v, int k) {
        for (int i = 0; i < k; ++i) v = std::nextafter(v, 9.0);
        return v;
    };
    MeshScene m(0);
    auto pair = [&](const Vec3& p, const Vec3& q, const Vec3& q2, const Vec3& r, const Vec3& r2) {
        const uint32_t a = m.vertex(p);
        m.face({a, m.vertex(q), m.vertex(r)});
        m.face({a, m.vertex(r2), m.vertex(q2)});
    };
    for (const int k : {4, 6, 8}) {
        const double dz = 0.02 * k;  // the three sets of pairs a little apart in height
        pair({-0.4, -0.3, 1 + dz}, {0.3, -0.2, 1 + dz}, {step(0.3, k), step(-0.2, k), 1 + dz},
             {-0.4, 0.1, 1 + dz}, {-0.3, -0.7, 1 + dz});
        pair({-0.2, 0.2, 1 + dz}, {0.4, 0.5, 1 + dz}, {0.4, 0.5, step(1 + dz, k)},
             {-0.3, 0.6, 1 + dz}, {0.2, 0.0, 1 + dz});
        pair({0.5, -0.5, 0.8 + dz}, {-0.1, 0.3, 1.2 + dz}, {step(-0.1, k), 0.3, step(1.2 + dz, k)},
             {0.6, 0.2, 0.9 + dz}, {0.0, -0.6, 0.9 + dz});
    }
    const Checked c = checkScene(m.finish(), "slivers", 120, 31);
    EXPECT_EQ(c.lightEdges, 120);
    EXPECT_GT(c.lightEdgeFallbacks, 0);
}

// The face groups at contact lines: flat plates of many faces on the dyadic grid of the floor
// points and the light's corners (lines from x through plate vertices pass exactly through the
// light's corners and through the vertices of the plate above), two coplanar plates touching
// along an edge, one facing up among those facing down, and a wall standing on the floor with
// floor points on its foot. The groups strictly between the two planes are taken whole; their
// answers, and the others', against the exact reference.
TEST(BoundaryChainQuery, GroupsAtContactLinesOnADyadicGridMatchTheExactReference) {
    MeshScene m(0);
    m.plate(-0.5, 0.0, -0.5, 0.5, 1.0, true);
    m.plate(0.0, 0.5, -0.5, 0.5, 1.0, true);        // coplanar, touching the first along x = 0
    m.plate(-0.25, 0.25, -0.25, 0.25, 1.5, false);  // above them, facing up (away from x)
    m.plate(-1.0, -0.5, 0.0, 0.5, 0.5, true);       // its edge under the first plate's
    m.wall(0.75, 0.0, 0.5, true);                   // its foot on the floor, at x = 0.75
    std::vector<Vec3> grid;
    for (int i = -4; i <= 4; ++i)
        for (int j = -4; j <= 4; ++j) grid.push_back({i / 4.0, j / 4.0, 0});
    const Checked c =
        checkScene(m.finish(), "dyadic plates", static_cast<int>(grid.size()), 0, grid);
    EXPECT_GT(c.grouped, static_cast<int>(grid.size()) / 2);
    EXPECT_GT(c.chain, static_cast<int>(grid.size()) / 2);
    EXPECT_EQ(c.lightEdges, static_cast<int>(grid.size()));
}

// A closed box and sphere standing on a triangle of the floor, the whole scene rotated and
// translated in doubles: the box's bottom and the contacts become hair crossings and hair gaps
// of the floor's plane (faces on either side of it by a rounding unit: surface or clipped, and
// sides the receiver's patch decides or not). Then flat plates, transformed the same way, whose
// face groups meet both planes by a hair (scenes of their own, after the closed ones). Floor
// points through the partial tree's silhouettes and through the face groups against the exact
// reference.
TEST(BoundaryChainQuery, TransformedMeshesThroughTheSilhouettesAndTheGroups) {
    std::mt19937_64 rng(21);
    std::uniform_real_distribution<double> u(-1, 1);
    int silhouettes = 0, points = 0, penumbra = 0, grouped = 0, edgePath = 0;
    // Points a rounding above the floor next to the box's bottom (a hair off the floor's plane)
    // are answered from the pair's occluders (FromPointQuery::nearContact), not the silhouettes.
    int contact = 0;
    int closedPoints = 0;  // of the closed meshes' scenes
    const int closedScenes = test::scaled(8);
    for (int i = 0; i < closedScenes + test::scaled(4); ++i) {
        const bool closed = i < closedScenes;
        MeshScene m(0);
        if (closed) {
            // (Fine enough that groups of 16 faces lie on one side of the box.)
            m.box({-0.4, -0.3, 0}, {0.2, 0.35, 0.6 + 0.1 * u(rng)}, 6);
            m.sphere({0.45, 0.1, 0.3}, 0.25, 16, 10);
        } else {
            // Flat plates through the floor's and the light's planes and above the light:
            // transformed, their groups' contacts with both planes are hair crossings.
            m.wall(0.7, 1.0, 3.0, true);
            m.wall(-0.7, 0.0, 1.2, false);  // standing on the floor
            m.ceiling(2.5);
        }
        Scene s = m.finish();
        s.mesh.faces[0].resize(3);  // triangles: a rotated quad would not stay planar
        s.mesh.faces[1].resize(3);
        const double a = 3 * u(rng), b = 3 * u(rng), c = 3 * u(rng);
        const Vec3 t{100 * u(rng), 100 * u(rng), 100 * u(rng)};
        for (Vec3& v : s.mesh.vertices) {
            Vec3 p{std::cos(a) * v.x - std::sin(a) * v.y, std::sin(a) * v.x + std::cos(a) * v.y,
                   v.z};
            p = {p.x, std::cos(b) * p.y - std::sin(b) * p.z, std::sin(b) * p.y + std::cos(b) * p.z};
            p = {std::cos(c) * p.x + std::sin(c) * p.z, p.y,
                 -std::sin(c) * p.x + std::cos(c) * p.z};
            v = p + t;
        }
        vis::BuildOptions partialBudget;
        partialBudget.maxLpSolves = 1;
        vis::HistoryTree tree = vis::buildHistoryTree(s.mesh, 0, 1, partialBudget, {});
        vis::prepareSilhouettes(s.mesh, tree, {}, 100);  // (as checkScene)
        vis::FromPointQuery query;
        query.setChainOptions({1, 0, 0, 0});
        // The direct query with the face groups too: the box's bottom faces are a hair above or
        // below the floor's plane, so groups that hold them are not taken whole (not strictly
        // in front of B), the others may be.
        const vis::BoxTree faces = test::faceBoxTree(s.mesh);
        const vis::FaceClusters groups(s.mesh, faces);
        const vis::LightEdgeIndex lightEdges = lightEdgesOf(s.mesh);
        std::vector<Vec3> floor;
        for (uint32_t v : s.mesh.faces[0]) floor.push_back(s.mesh.vertices[v]);
        for (int k = 0; k < 6; ++k) {
            // A point of the floor triangle (-2,-2) (2,-2) (2,2) near the meshes, from its
            // barycentric weights on the transformed vertices (rounded: a hair off the plane).
            double px = 0.8 * u(rng), py = 0.8 * u(rng);
            if (py > px) std::swap(px, py);
            const double w0 = (2 - px) / 4, w2 = (py + 2) / 4, w1 = 1 - w0 - w2;
            const Vec3 x = floor[0] * w0 + floor[1] * w1 + floor[2] * w2;
            const test::ReferenceResult ref = test::exactReference(s.mesh, 0, 1, x);
            const Measured got = measure(s.mesh, x, query.run(s.mesh, tree, x));
            silhouettes += query.usedSilhouettes();
            contact += query.answeredOnContact();
            ++points;
            if (closed) {
                ++closedPoints;
                penumbra += ref.fraction > 0.001 && ref.fraction < 0.999;
            }
            EXPECT_NEAR(got.fraction, ref.fraction, 1e-9) << vis::toString(x);
            EXPECT_NEAR(got.formFactor, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
                << vis::toString(x);
            const Measured direct =
                measure(s.mesh, x, query.runDirect(s.mesh, 0, 1, x, faces, &groups));
            grouped += query.clustersUsed() > 0 || query.solidGroupsLeftOut() > 0;
            EXPECT_NEAR(direct.fraction, ref.fraction, 1e-9) << "groups, " << vis::toString(x);
            EXPECT_NEAR(direct.formFactor, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
                << "groups, " << vis::toString(x);
            const Measured edged =
                measure(s.mesh, x, query.runDirect(s.mesh, 0, 1, x, faces, nullptr, &lightEdges));
            edgePath += query.usedLightEdges();
            EXPECT_NEAR(edged.fraction, ref.fraction, 1e-9) << "light edges, " << vis::toString(x);
            EXPECT_NEAR(edged.formFactor, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
                << "light edges, " << vis::toString(x);
        }
    }
    EXPECT_GT(edgePath, 0);
    EXPECT_GT(grouped, 0);
    EXPECT_EQ(silhouettes + contact, points);
    EXPECT_LT(contact, points / 8);
    EXPECT_GT(penumbra, closedPoints / 4);
}

// ---- The pair-level silhouettes (deferred_silhouettes.h) ------------------------------------

// A cube (12 triangles, shared vertices) above a small patch of the floor under its centre: from
// every point of the patch the bottom faces face the point and the four sides and the top face
// away (the patch lies strictly inside the sides' slabs). So every edge cancels for the whole
// patch but the bottom's four rim edges (bottom +1, side -1: the same direction twice): four
// groups of two uses, of 36. Hand-derived.
TEST(DeferredSilhouettes, CubeOverASmallPatchKeepsOnlyItsBottomRim) {
    MeshScene m(0);
    m.box({-0.3, -0.3, 0.5}, {0.3, 0.3, 1.1}, 1);
    const Scene s = m.finish();
    vis::HistoryTree tree;
    tree.receiver = 0;
    tree.light = 1;
    tree.kind = vis::PairKind::Penumbra;
    for (uint32_t f = 2; f < s.faceCount(); ++f) tree.deferred.push_back({f, {}});
    const std::vector<Vec3> patch = {{-0.1, -0.1, 0}, {0.1, -0.1, 0}, {0, 0.1, 0}};
    vis::prepareSilhouettes(s.mesh, tree, patch);
    const vis::DeferredSilhouettes& sil = tree.silhouettes;
    ASSERT_TRUE(sil.usable());
    EXPECT_EQ(sil.totalUses, 36u);
    EXPECT_EQ(sil.loneUses, 0u);
    ASSERT_EQ(sil.groupCount(), 4u);
    EXPECT_EQ(sil.keptUses, 8u);
    for (const auto& use : sil.uses) {
        EXPECT_EQ(s.mesh.vertices[use.v0].z, 0.5);  // on the bottom rim
        EXPECT_EQ(s.mesh.vertices[use.v1].z == 0.5, s.mesh.vertices[use.v0].z == 0.5);
        EXPECT_NE(use.side, 0);
    }
    // Over the whole floor (4 x 4) the side faces' planes cross the region: nothing is decided
    // for them, and their edges are kept.
    vis::prepareSilhouettes(s.mesh, tree);
    EXPECT_GT(tree.silhouettes.keptUses, 8u);
    // Only the top's and the bottom's diagonals cancel (4 uses): 32 of 36 kept, too few cancel for
    // the silhouettes to pay, and the query clips the faces instead; forced, they are kept.
    EXPECT_EQ(tree.silhouettes.keptUses, 32u);
    EXPECT_FALSE(tree.silhouettes.usable());
    vis::prepareSilhouettes(s.mesh, tree, {}, 100);
    EXPECT_TRUE(tree.silhouettes.usable());
    // Separate triangles share no edge: not worth it (nothing kept).
    MeshScene loose(0);
    for (int i = 0; i < 6; ++i) {
        const double x = -0.6 + 0.2 * i;
        loose.face(
            {loose.vertex({x, 0, 1}), loose.vertex({x + 0.1, 0, 1}), loose.vertex({x, 0.1, 1})});
    }
    const Scene l = loose.finish();
    vis::HistoryTree leaves = tree;
    leaves.deferred.clear();
    for (uint32_t f = 2; f < l.faceCount(); ++f) leaves.deferred.push_back({f, {}});
    vis::prepareSilhouettes(l.mesh, leaves, patch);
    EXPECT_FALSE(leaves.silhouettes.usable());
    EXPECT_EQ(leaves.silhouettes.loneUses, 18u);
}

// A tree built for a patch of the floor: its silhouettes decide most faces for the patch; the
// points in the patch (random, and on its corners) are answered from them exactly, and a point
// of the face outside the patch's region is not (the decided sides are not its own): both
// against the exact reference.
TEST(BoundaryChainQuery, SilhouettesOfAPatchMatchTheExactReference) {
    MeshScene m(0);
    m.sphere({0.1, -0.05, 0.9}, 0.45, 16, 10);
    m.box({0.5, 0.3, 0}, {0.8, 0.6, 0.4}, 2);  // standing on the floor beside the patch
    const Scene s = m.finish();
    const std::vector<Vec3> patch = {{-0.3, -0.4, 0}, {0.3, -0.4, 0}, {0.0, 0.2, 0}};
    vis::BuildOptions partialBudget;
    partialBudget.maxLpSolves = 1;
    const vis::HistoryTree tree =
        vis::buildHistoryTree(s.mesh, 0, 1, partialBudget, {}, nullptr, patch);
    ASSERT_TRUE(tree.partial());
    ASSERT_TRUE(tree.silhouettes.usable());
    EXPECT_LT(tree.silhouettes.keptUses * 2, tree.silhouettes.totalUses);
    vis::FromPointQuery query;
    query.setChainOptions({1, 0, 0});
    std::vector<Vec3> points(patch.begin(), patch.end());
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (int i = 0; i < test::scaled(40); ++i) {
        double a = u(rng), b = u(rng);
        if (a + b > 1) a = 1 - a, b = 1 - b;
        points.push_back(patch[0] + (patch[1] - patch[0]) * a + (patch[2] - patch[0]) * b);
    }
    for (const Vec3& x : points) {
        const test::ReferenceResult ref = test::exactReference(s.mesh, 0, 1, x);
        const Measured a = measure(s.mesh, x, query.run(s.mesh, tree, x));
        EXPECT_TRUE(query.usedSilhouettes()) << vis::toString(x);
        EXPECT_NEAR(a.fraction, ref.fraction, 1e-9) << vis::toString(x);
        EXPECT_NEAR(a.formFactor, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6))
            << vis::toString(x);
    }
    // The whole face's tree, its silhouettes decided for the patch only: a point of the face
    // outside the patch's region takes the per-point path.
    vis::HistoryTree whole = vis::buildHistoryTree(s.mesh, 0, 1, partialBudget, {});
    vis::prepareSilhouettes(s.mesh, whole, patch);
    ASSERT_TRUE(whole.silhouettes.usable());
    for (const Vec3& x : {Vec3{0, -0.1, 0}, Vec3{1.2, -0.3, 0}}) {
        const test::ReferenceResult ref = test::exactReference(s.mesh, 0, 1, x);
        const Measured a = measure(s.mesh, x, query.run(s.mesh, whole, x));
        EXPECT_EQ(query.usedSilhouettes(), x.x == 0) << vis::toString(x);
        EXPECT_NEAR(a.fraction, ref.fraction, 1e-9) << vis::toString(x);
        EXPECT_NEAR(a.formFactor, ref.formFactor, 1e-9 * std::max(ref.formFactor, 1e-6));
    }
}

}  // namespace
}  // namespace penumbra::boundary_chain_test
