// FaceClusters (visibility/face_clusters.h): each group's boundary against the sum of its faces'
// edge uses (hand-derived on a flat grid, counted independently on curved meshes), and every
// side it certifies against the exact sign of each face's plane, in rational arithmetic (GMP),
// on smooth, bumpy, tiny, huge, rotated and far-from-origin meshes, for points far off, near the
// surface and in the faces' planes.
#include "visibility/face_clusters.h"

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "tests/support/face_boxes.h"
#include "tests/support/test_scale.h"
#include "visibility/box_tree.h"

namespace penumbra::face_clusters_test {
namespace {

using vis::Vec3;

// A grid of n x n quads over [0, n]^2 at height z(i, j), each split into two triangles,
// counter-clockwise seen from +z (shared vertices).
vis::PolygonMesh grid(int n, double (*z)(int, int)) {
    vis::PolygonMesh m;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            m.vertices.push_back({static_cast<double>(i), static_cast<double>(j), z(i, j)});
    auto id = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return m;
}

// A latitude-longitude sphere of triangles, outward (shared vertices).
vis::PolygonMesh sphere(const Vec3& c, double r, int slices, int stacks) {
    vis::PolygonMesh m;
    m.vertices.push_back(c - Vec3{0, 0, r});
    m.vertices.push_back(c + Vec3{0, 0, r});
    for (int i = 1; i < stacks; ++i) {
        const double t = std::numbers::pi * i / stacks - std::numbers::pi / 2;
        for (int j = 0; j < slices; ++j) {
            const double p = 2 * std::numbers::pi * j / slices;
            m.vertices.push_back(c + Vec3{r * std::cos(t) * std::cos(p),
                                          r * std::cos(t) * std::sin(p), r * std::sin(t)});
        }
    }
    auto at = [&](int i, int j) { return static_cast<uint32_t>(2 + i * slices + j % slices); };
    for (int j = 0; j < slices; ++j) {
        m.faces.push_back({0, at(0, j + 1), at(0, j)});
        for (int i = 0; i + 2 < stacks; ++i) {
            m.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            m.faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
        m.faces.push_back({1, at(stacks - 2, j), at(stacks - 2, j + 1)});
    }
    return m;
}

// The sign of (v1 - v0) x (v2 - v0) . (x - v0), in rationals: the doubles exactly.
int exactSide(const vis::PolygonMesh& m, uint32_t face, const Vec3& x) {
    const auto& ids = m.faces[face];
    auto q = [](const Vec3& v) {
        return std::array<mpq_class, 3>{mpq_class(v.x), mpq_class(v.y), mpq_class(v.z)};
    };
    const auto a = q(m.vertices[ids[0]]), b = q(m.vertices[ids[1]]), c = q(m.vertices[ids[2]]);
    const auto p = q(x);
    std::array<mpq_class, 3> u, v, w;
    for (int i = 0; i < 3; ++i) {
        u[i] = b[i] - a[i];
        v[i] = c[i] - a[i];
        w[i] = p[i] - a[i];
    }
    const mpq_class d = (u[1] * v[2] - u[2] * v[1]) * w[0] + (u[2] * v[0] - u[0] * v[2]) * w[1] +
                        (u[0] * v[1] - u[1] * v[0]) * w[2];
    return sgn(d);
}

// Each group's boundary, counted here: per edge (lower id, higher id) the sum of its faces'
// uses in that direction.
void expectBoundariesAreTheFacesSums(const vis::PolygonMesh& m, const vis::BoxTree& t,
                                     const vis::FaceClusters& c, const std::string& what) {
    for (uint32_t node = 0; node < t.nodeCount(); ++node) {
        const uint32_t k = c.clusterAt(node);
        if (k == vis::FaceClusters::kNone) continue;
        std::map<std::pair<uint32_t, uint32_t>, int> sum;
        for (uint32_t f : t.nodeItems(node)) {
            const auto& ids = m.faces[f];
            for (size_t i = 0; i < ids.size(); ++i) {
                const uint32_t a = ids[i], b = ids[(i + 1) % ids.size()];
                sum[{std::min(a, b), std::max(a, b)}] += a < b ? 1 : -1;
            }
        }
        std::map<std::pair<uint32_t, uint32_t>, int> expected, stored;
        for (const auto& [e, w] : sum)
            if (w != 0) expected[e] = w;
        for (const vis::FaceClusters::Use& u : c.boundary(k)) {
            EXPECT_LT(u.lo, u.hi);
            EXPECT_EQ(stored.count({u.lo, u.hi}), 0u) << what << ": an edge stored twice";
            stored[{u.lo, u.hi}] = u.weight;
        }
        EXPECT_EQ(stored, expected) << what << ", node " << node;
    }
}

TEST(FaceClusters, AFlatGridIsOneGroupWithItsRimAsBoundary) {
    // 4 x 4 quads, 32 triangles in the plane z = 0, all facing +z: the root holds every face,
    // its cone is the +z axis alone, and of its 80 edge uses only the 16 rim edges remain, each
    // once, counter-clockwise seen from +z.
    const vis::PolygonMesh m = grid(4, [](int, int) { return 0.0; });
    const vis::BoxTree t = test::faceBoxTree(m);
    const vis::FaceClusters c(m, t);
    const uint32_t root = c.clusterAt(0);
    ASSERT_NE(root, vis::FaceClusters::kNone);
    const auto rim = c.boundary(root);
    ASSERT_EQ(rim.size(), 16u);
    for (const vis::FaceClusters::Use& u : rim) {
        const Vec3 a = m.vertices[u.lo], b = m.vertices[u.hi];
        // On the rim: both ends on one side of the square.
        const bool onRim =
            (a.x == b.x && (a.x == 0 || a.x == 4)) || (a.y == b.y && (a.y == 0 || a.y == 4));
        EXPECT_TRUE(onRim) << vis::toString(a) << " - " << vis::toString(b);
        // Counter-clockwise from +z: along +x at y = 0, +y at x = 4, -x at y = 4, -y at x = 0;
        // lo -> hi has the vertex order of the grid (row by row), so its weight says which.
        const Vec3 d = (b - a) * static_cast<double>(u.weight);
        const bool ccw = (a.y == 0 && b.y == 0 && d.x > 0) || (a.x == 4 && b.x == 4 && d.y > 0) ||
                         (a.y == 4 && b.y == 4 && d.x < 0) || (a.x == 0 && b.x == 0 && d.y < 0);
        EXPECT_TRUE(ccw) << vis::toString(a) << " - " << vis::toString(b) << " " << u.weight;
    }
    expectBoundariesAreTheFacesSums(m, t, c, "flat grid");
    for (uint32_t f = 0; f < m.faces.size(); ++f) EXPECT_TRUE(c.grouped(f)) << "face " << f;
    EXPECT_FALSE(c.grouped(static_cast<uint32_t>(m.faces.size())));
    // Above the plane every face is seen from the front, below from the back, in the plane
    // (beside the grid, or on it) from neither: not certain.
    EXPECT_EQ(c.facing(root, {2, 2, 1}), 1);
    EXPECT_EQ(c.facing(root, {50, -7, 1e-3}), 1);
    EXPECT_EQ(c.facing(root, {2, 2, -0.5}), -1);
    EXPECT_EQ(c.facing(root, {9, 2, 0}), 0);
    EXPECT_EQ(c.facing(root, {2, 2, 0}), 0);
}

TEST(FaceClusters, LooseFacesMakeNoGroup) {
    // 32 triangles that share no edge (leaves): nothing cancels, no group.
    vis::PolygonMesh m;
    for (int k = 0; k < 32; ++k) {
        const double x = k;
        const uint32_t v = static_cast<uint32_t>(m.vertices.size());
        m.vertices.push_back({x, 0, 0});
        m.vertices.push_back({x + 0.5, 0, 0});
        m.vertices.push_back({x, 0.5, 0});
        m.faces.push_back({v, v + 1, v + 2});
    }
    const vis::BoxTree t = test::faceBoxTree(m);
    const vis::FaceClusters c(m, t);
    EXPECT_EQ(c.size(), 0u);
    for (uint32_t f = 0; f < m.faces.size(); ++f) EXPECT_FALSE(c.grouped(f)) << "face " << f;
}

// Random points against every group of the mesh: a side it certifies is the exact side of
// each of the group's faces. Returns how many (point, group) pairs it certified.
int checkSides(const vis::PolygonMesh& m, const std::string& what, int points, uint64_t seed) {
    const vis::BoxTree t = test::faceBoxTree(m);
    const vis::FaceClusters c(m, t);
    expectBoundariesAreTheFacesSums(m, t, c, what);
    EXPECT_GT(c.size(), 0u) << what;
    vis::Bounds3 all;
    for (const Vec3& v : m.vertices) all.add(v);
    const Vec3 size = all.hi - all.lo;
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 2);
    std::uniform_int_distribution<size_t> pickVertex(0, m.vertices.size() - 1);
    std::uniform_int_distribution<size_t> pickFace(0, m.faces.size() - 1);
    int certified = 0, wrong = 0;
    for (int i = 0; i < points; ++i) {
        Vec3 x;
        switch (i % 3) {
            case 0:  // anywhere around the mesh
                x = all.lo + Vec3{size.x * u(rng), size.y * u(rng), size.z * u(rng)};
                break;
            case 1: {  // a vertex moved by a few units in the last place
                x = m.vertices[pickVertex(rng)];
                for (int k = 0; k < 3; ++k) {
                    const double s = std::uniform_int_distribution<int>(-3, 3)(rng);
                    x = {k == 0 ? x.x + s * std::abs(x.x) * 1e-16 : x.x,
                         k == 1 ? x.y + s * std::abs(x.y) * 1e-16 : x.y,
                         k == 2 ? x.z + s * std::abs(x.z) * 1e-16 : x.z};
                }
                break;
            }
            default: {  // a point of a face (rounded) or of its plane's extension
                const auto& ids = m.faces[pickFace(rng)];
                const double a = u(rng), b = u(rng);
                const Vec3 p0 = m.vertices[ids[0]], p1 = m.vertices[ids[1]],
                           p2 = m.vertices[ids[2]];
                x = p0 + (p1 - p0) * a + (p2 - p0) * b;
                break;
            }
        }
        for (uint32_t node = 0; node < t.nodeCount(); ++node) {
            const uint32_t k = c.clusterAt(node);
            if (k == vis::FaceClusters::kNone) continue;
            const int side = c.facing(k, x);
            if (side == 0) continue;
            ++certified;
            for (uint32_t f : t.nodeItems(node)) {
                if (exactSide(m, f, x) != side && wrong++ < 5)
                    ADD_FAILURE() << what << ": group at node " << node << " certified side "
                                  << side << " at x = " << vis::toString(x) << ", but face " << f
                                  << "'s exact side is " << exactSide(m, f, x);
            }
        }
    }
    return certified;
}

vis::PolygonMesh moved(vis::PolygonMesh m, double scale, const Vec3& t, std::mt19937_64& rng) {
    // A random rotation (a unit quaternion), then the scale and the translation, in doubles.
    std::normal_distribution<double> g;
    double w = g(rng), a = g(rng), b = g(rng), c = g(rng);
    const double n = std::sqrt(w * w + a * a + b * b + c * c);
    w /= n, a /= n, b /= n, c /= n;
    const Vec3 r0{1 - 2 * (b * b + c * c), 2 * (a * b - c * w), 2 * (a * c + b * w)};
    const Vec3 r1{2 * (a * b + c * w), 1 - 2 * (a * a + c * c), 2 * (b * c - a * w)};
    const Vec3 r2{2 * (a * c - b * w), 2 * (b * c + a * w), 1 - 2 * (a * a + b * b)};
    for (Vec3& v : m.vertices)
        v = Vec3{vis::dot(r0, v), vis::dot(r1, v), vis::dot(r2, v)} * scale + t;
    return m;
}

TEST(FaceClusters, CertifiedSidesAreTheExactOnes) {
    std::mt19937_64 rng(11);
    const int points = test::scaled(150);
    const vis::PolygonMesh ball = sphere({0.2, -0.1, 0.5}, 0.7, 32, 20);
    const vis::PolygonMesh bumps =
        grid(20, [](int i, int j) { return 0.3 * std::sin(0.4 * i) * std::cos(0.3 * j); });
    // (Not vacuous: each mesh has certified sides for a good share of the points.)
    EXPECT_GT(checkSides(ball, "sphere", points, 1), points / 4);
    EXPECT_GT(checkSides(bumps, "bumpy grid", points, 2), points / 4);
    EXPECT_GT(checkSides(moved(ball, 1, {1e5, -3e4, 7e4}, rng), "sphere far off", points, 3),
              points / 4);
    EXPECT_GT(checkSides(moved(bumps, 1e-6, {0.1, 0.2, 0.3}, rng), "tiny bumps", points, 4),
              points / 4);
    EXPECT_GT(checkSides(moved(bumps, 1e6, {-2e6, 1e6, 3e5}, rng), "huge bumps", points, 5),
              points / 4);
}

}  // namespace
}  // namespace penumbra::face_clusters_test
