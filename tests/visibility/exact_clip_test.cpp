// Exactness where rounded constructions used to decide: occluders that cross the receiver's or
// the light's plane by less than a rounding unit (sub-ulp, a few ulps, decimal residues, a model
// rotated and placed "on" a floor), and query points on contact lines. Every answer of the three
// paths (the complete tree, a partial tree whose occluders the query clips, and the tree-less
// direct query) is compared with the exact CGAL reference (tests/support/exact_reference.h).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "engine/scene/scene.h"
#include "tests/support/exact_reference.h"
#include "tests/support/face_boxes.h"
#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"
#include "visibility/box_tree.h"
#include "visibility/clipped_occluder.h"
#include "visibility/edge_line.h"
#include "visibility/exact_orient.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"
#include "visibility/history_tree_builder.h"
#include "visibility/pair_occluders.h"

namespace penumbra {
namespace {

using vis::Vec3;

// A scene built polygon by polygon: face 0 the receiver, face 1 the light.
struct Polygons {
    Scene scene;
    Polygons() {
        Material white;
        white.name = "white";
        Material light;
        light.name = "light";
        light.ke = {15, 15, 15};
        scene.materials = {white, light};
    }
    void add(const std::vector<Vec3>& pts, bool emissive = false) {
        std::vector<uint32_t> ids;
        for (const Vec3& p : pts) {
            ids.push_back(static_cast<uint32_t>(scene.mesh.vertices.size()));
            scene.mesh.vertices.push_back(p);
        }
        scene.mesh.faces.push_back(ids);
        scene.faceMaterial.push_back(emissive ? 1 : 0);
        scene.faceSourceLine.push_back(0);
    }
    Scene finish() {
        scene.collectLights();
        return scene;
    }
};

// The answers of one path at one point.
struct VisibleAnswer {
    double fraction = 0, formFactor = 0;
};

VisibleAnswer measure(const vis::PolygonMesh& m, uint32_t receiver, uint32_t light, const Vec3& x,
                      const vis::FragmentList& f) {
    VisibleAnswer a;
    const Vec3 n = vis::normalize(m.faceAreaNormal(receiver));
    double area = 0;
    for (size_t k = 0; k < f.size(); ++k) {
        area += vis::polygonArea(f[k]);
        a.formFactor += vis::formFactor(x, n, f[k]);
    }
    a.fraction = area / m.faceArea(light);
    return a;
}

// The three paths for one scene (receiver face 0, light face 1): trees built once.
class Paths {
  public:
    explicit Paths(const Scene& s, std::span<const Vec3> patch = {})
        : scene_(s),
          complete_(vis::buildHistoryTree(s.mesh, 0, 1, {}, {}, nullptr, patch)),
          partial_(vis::buildHistoryTree(s.mesh, 0, 1, budget(1), {}, nullptr, patch)) {
        faces_ = test::faceBoxTree(s.mesh);
        groups_ = vis::FaceClusters(s.mesh, faces_);
    }
    const vis::HistoryTree& complete() const { return complete_; }
    const vis::HistoryTree& partial() const { return partial_; }

    // Number of mismatches at x against the reference (0..5), with a message for the first.
    int check(const Vec3& x, const std::string& what, test::ReferenceResult* refOut = nullptr) {
        const vis::PolygonMesh& m = scene_.mesh;
        const test::ReferenceResult ref = test::exactReference(m, 0, 1, x);
        if (refOut) *refOut = ref;
        int bad = 0;
        auto compare = [&](const char* path, const VisibleAnswer& a) {
            const bool ok =
                std::fabs(a.fraction - ref.fraction) <= 1e-9 &&
                std::fabs(a.formFactor - ref.formFactor) <= 1e-9 * std::max(ref.formFactor, 1e-6);
            if (!ok) {
                ++bad;
                if (reported_++ < 5)
                    ADD_FAILURE() << what << ": " << path << " at x = " << vis::toString(x)
                                  << " answers fraction " << a.fraction << " form factor "
                                  << a.formFactor << ", the exact reference " << ref.fraction
                                  << " and " << ref.formFactor;
            }
        };
        compare("complete tree", measure(m, 0, 1, x, query_.run(m, complete_, x)));
        compare("partial tree", measure(m, 0, 1, x, query_.run(m, partial_, x)));
        compare("direct query", measure(m, 0, 1, x, query_.runDirect(m, 0, 1, x, faces_)));
        // The boundary-chain evaluation (boundary_chain.h), forced for any number of occluders.
        compare("partial tree, chain", measure(m, 0, 1, x, chain_.run(m, partial_, x)));
        compare("direct query, chain", measure(m, 0, 1, x, chain_.runDirect(m, 0, 1, x, faces_)));
        // Through the face groups' entry point (face_clusters.h). These scenes' occluders are too
        // few to form a group, so it answers as the plain direct query; the groups themselves
        // are checked under hair crossings in BoundaryChainQuery.
        compare("direct query, face groups",
                measure(m, 0, 1, x, chain_.runDirect(m, 0, 1, x, faces_, &groups_)));
        compare("direct query, face groups, default options",
                measure(m, 0, 1, x, query_.runDirect(m, 0, 1, x, faces_, &groups_)));
        return bad;
    }

  private:
    static vis::BuildOptions budget(uint64_t lps) {
        vis::BuildOptions o;
        o.maxLpSolves = lps;
        return o;
    }
    const Scene& scene_;
    vis::HistoryTree complete_, partial_;
    vis::BoxTree faces_;
    vis::FaceClusters groups_;
    vis::FromPointQuery query_;
    vis::FromPointQuery chain_ = [] {
        vis::FromPointQuery q;
        q.setChainOptions({1, 0, 0});
        return q;
    }();
    int reported_ = 0;
};

bool hasChord(const vis::HistoryTree& t) {
    for (const vis::HistoryNode& n : t.nodes)
        if (vis::isClipEdge(n.v0)) return true;
    return false;
}

// n steps of nextafter from v towards `to`.
double ulps(double v, int n, double to) {
    for (int i = 0; i < n; ++i) v = std::nextafter(v, to);
    return v;
}

// The floor z = h, [-2, 2]^2 facing up (face 0), and a light [-0.5, 0.5]^2 at z = h + 2 facing
// down (face 1).
Polygons frame(double h) {
    Polygons p;
    p.add({{-2, -2, h}, {2, -2, h}, {2, 2, h}, {-2, 2, h}});
    p.add({{-0.5, -0.5, h + 2}, {-0.5, 0.5, h + 2}, {0.5, 0.5, h + 2}, {0.5, -0.5, h + 2}}, true);
    return p;
}

// The plane through three points, from the same arithmetic the core uses.
TEST(EdgeLine, ChordSideAgreesWithOrient3dOfPointsOnTheChord) {
    // For well-separated random planes, two points on their meet (rounded, far apart) give the
    // same side as the exact chord for every line that is not close to meeting it.
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1, 1);
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)}, c{u(rng), u(rng), u(rng)};
        const Vec3 d{u(rng), u(rng), u(rng)}, e{u(rng), u(rng), u(rng)}, f{u(rng), u(rng), u(rng)};
        const vis::PlaneOrient p1(a, b, c), p2(d, e, f);
        const Vec3 n1 = vis::cross(b - a, c - a), n2 = vis::cross(e - d, f - d);
        const Vec3 dir = vis::cross(n1, n2);
        if (vis::length(dir) < 0.1 * vis::length(n1) * vis::length(n2)) continue;
        // A point on both planes: solve with the direction as third row (Cramer, doubles).
        const double d1 = vis::dot(n1, a), d2 = vis::dot(n2, d);
        const Vec3 p0 = (vis::cross(n2, dir) * d1 + vis::cross(dir, n1) * d2) /
                        vis::dot(dir, vis::cross(n1, n2));
        const Vec3 unit = vis::normalize(dir);
        const Vec3 q0 = p0 - unit * 10.0, q1 = p0 + unit * 10.0;
        const vis::EdgeLine chord = vis::EdgeLine::meet(p1, p2);
        for (int k = 0; k < 10; ++k) {
            const Vec3 y{u(rng), u(rng), u(rng)}, z{u(rng), u(rng), u(rng)};
            const double approx = vis::orient3dApprox(y, z, q0, q1);
            if (std::fabs(approx) < 1e-6) continue;
            EXPECT_EQ(vis::sideSign(y, z, chord),
                      approx > 0 ? vis::Sign::Positive : vis::Sign::Negative);
            // And the filtered value's sign is the exact one.
            EXPECT_EQ(vis::sideSign(y, z, chord), sgn(vis::sideExact(y, z, chord)) > 0
                                                      ? vis::Sign::Positive
                                                      : vis::Sign::Negative);
            ++compared;
        }
    }
    EXPECT_GT(compared, 5000);
}

// The chord of a clip is directed as the face's counter-clockwise boundary: the clipped polygon
// lies on its inner side (the same side as the face's own input edges').
TEST(ClippedOccluder, ChordsRunCounterClockwiseAndSubUlpCrossingsKeepTheFace) {
    for (bool reversed : {false, true}) {
        for (double below : {-1e-300, -0x1p-60, -5.551115123125783e-17, -1e-3}) {
            Polygons p = frame(0);
            std::vector<Vec3> tri{{-0.5, -0.2, below}, {0.5, -0.2, 1}, {0, 0.4, 1}};
            if (reversed) std::swap(tri[1], tri[2]);
            p.add(tri);
            const Scene s = p.finish();
            vis::ClippedOccluder c;
            const vis::PlaneOrient floor = vis::facePlane(s.mesh, 0).orient();
            const vis::PlaneOrient light = vis::facePlane(s.mesh, 1).orient();
            c.clip(s.mesh, 2, floor, light);
            ASSERT_FALSE(c.empty()) << below;
            EXPECT_TRUE(c.clipped());
            // Three input-edge lines and one chord, whatever the size of the part below.
            ASSERT_EQ(c.edges().size(), 4u) << below;
            int chords = 0;
            // The centroid: inside the clipped part (it is in front of the floor), off its edges.
            const Vec3 inside = (tri[0] + tri[1] + tri[2]) / 3.0;
            const vis::Vec3 n = vis::cross(tri[1] - tri[0], tri[2] - tri[0]);
            for (const auto& [v0, v1] : c.edges()) {
                chords += vis::isClipEdge(v0);
                const vis::EdgeLine e = vis::edgeLine(s.mesh, 0, 1, v0, v1);
                // Seen from the face's front, the inside is to the left of each edge: the line
                // from `inside` along the normal passes every edge on the same side.
                const vis::Sign side = vis::sideSign(inside - n, inside + n, e);
                EXPECT_EQ(side, vis::sideSign(inside - n, inside + n,
                                              vis::edgeLine(s.mesh, 0, 1, c.edges()[0].first,
                                                            c.edges()[0].second)))
                    << "below " << below << (reversed ? " reversed" : "");
                EXPECT_NE(side, vis::Sign::Zero);
            }
            EXPECT_EQ(chords, 1);
        }
    }
}

// A leaning triangle with one or two vertices below the floor by `depth` (or above it when
// depth < 0: then it only nearly touches), every winding; random points on the floor.
int crossingConfigurations(double h, const std::vector<double>& depths, int configs, int points,
                           uint64_t seed, int* chordTrees, int* blockedPoints) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0;
    for (int i = 0; i < configs; ++i) {
        const double depth = depths[i % depths.size()];
        const bool two = (i / depths.size()) % 2 == 1;
        const bool reversed = (i / (2 * depths.size())) % 2 == 1;
        Polygons p = frame(h);
        const double low = h - depth;
        const Vec3 a{0.6 * u(rng), 0.6 * u(rng), low};
        const Vec3 b{0.6 * u(rng), 0.6 * u(rng), two ? low : h + 0.5 + 0.8 * std::fabs(u(rng))};
        const Vec3 c{0.6 * u(rng), 0.6 * u(rng), h + 0.5 + 0.8 * std::fabs(u(rng))};
        if (vis::length(vis::cross(b - a, c - a)) < 0.05) continue;
        std::vector<Vec3> tri{a, b, c};
        if (reversed) std::swap(tri[1], tri[2]);
        p.add(tri);
        const Scene s = p.finish();
        Paths paths(s);
        *chordTrees += hasChord(paths.complete());
        for (int k = 0; k < points; ++k) {
            const Vec3 x{1.2 * u(rng), 1.2 * u(rng), h};
            test::ReferenceResult ref;
            bad += paths.check(x, "crossing by " + std::to_string(depth), &ref);
            *blockedPoints += ref.fraction < 0.999;
        }
    }
    return bad;
}

TEST(ExactClip, OccludersCrossingTheReceiverPlaneByLessThanARoundingUnit) {
    int chordTrees = 0, blocked = 0, bad = 0;
    // Floor at z = 0: depths from a subnormal to 2^-52, decimal residues of both signs.
    const std::vector<double> depths0{0x1p-1070,       0x1p-60, 0x1p-55, 0x1p-52,
                                      0.1 * 3 - 0.3,    // 5.55e-17: below
                                      0.3 - 0.1 * 3,    // above (a near-touch)
                                      1.1 - 1.0 - 0.1,  // 8.3e-17
                                      0.7 - 0.6 - 0.1};
    bad += crossingConfigurations(0, depths0, test::scaled(320), 6, 1, &chordTrees, &blocked);
    // Floor at z = 0.7 (not dyadic): the vertex 1 to 4 ulps below (and above) the floor's value.
    const double h = 0.7;
    std::vector<double> depthsH;
    for (int k = 1; k <= 4; ++k) {
        depthsH.push_back(h - ulps(h, k, -1));
        depthsH.push_back(h - ulps(h, k, 2));
    }
    bad += crossingConfigurations(h, depthsH, test::scaled(320), 6, 2, &chordTrees, &blocked);
    EXPECT_EQ(bad, 0);
    EXPECT_GT(chordTrees, test::scaled(320) / 2);  // the chords were exercised
    EXPECT_GT(blocked, test::scaled(640));         // and so was the occlusion
}

TEST(ExactClip, OccludersCrossingTheLightPlaneByLessThanARoundingUnit) {
    // A triangle hanging from above the light (behind it: the light faces down), one or two
    // vertices a hair beyond the light's plane.
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1, 1);
    const std::vector<double> beyond{0x1p-60,       0x1p-52,          2.0 * 0x1p-52,
                                     0.1 * 3 - 0.3, -(0.1 * 3 - 0.3), 1e-300};
    int bad = 0, chordTrees = 0, blocked = 0;
    for (int i = 0; i < test::scaled(240); ++i) {
        const double d = beyond[i % beyond.size()];
        const bool two = (i / beyond.size()) % 2 == 1;
        Polygons p = frame(0);
        const Vec3 a{0.5 * u(rng), 0.5 * u(rng), 2 + d};
        const Vec3 b{0.5 * u(rng), 0.5 * u(rng), two ? 2 + d : 1.2 + 0.5 * std::fabs(u(rng))};
        const Vec3 c{0.5 * u(rng), 0.5 * u(rng), 1.2 + 0.5 * std::fabs(u(rng))};
        if (vis::length(vis::cross(b - a, c - a)) < 0.05) continue;
        std::vector<Vec3> tri{a, b, c};
        if (i % 2) std::swap(tri[1], tri[2]);
        p.add(tri);
        const Scene s = p.finish();
        Paths paths(s);
        chordTrees += hasChord(paths.complete());
        for (int k = 0; k < 6; ++k) {
            test::ReferenceResult ref;
            bad += paths.check({1.5 * u(rng), 1.5 * u(rng), 0}, "beyond the light", &ref);
            blocked += ref.fraction < 0.999;
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(chordTrees, test::scaled(240) / 8);  // the chords were exercised
    EXPECT_GT(blocked, test::scaled(240));
}

// A random rotation (unit quaternion from three uniforms), as a row-major 3x3 matrix.
std::array<Vec3, 3> randomRotation(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0, 1);
    const double u1 = u(rng), u2 = u(rng) * 2 * M_PI, u3 = u(rng) * 2 * M_PI;
    const double a = std::sqrt(1 - u1) * std::sin(u2), b = std::sqrt(1 - u1) * std::cos(u2);
    const double c = std::sqrt(u1) * std::sin(u3), w = std::sqrt(u1) * std::cos(u3);
    return {Vec3{1 - 2 * (b * b + c * c), 2 * (a * b - c * w), 2 * (a * c + b * w)},
            Vec3{2 * (a * b + c * w), 1 - 2 * (a * a + c * c), 2 * (b * c - a * w)},
            Vec3{2 * (a * c - b * w), 2 * (b * c + a * w), 1 - 2 * (a * a + b * b)}};
}

// A floor triangle (face 0), a light triangle two units above it facing down (face 1), and what
// is added after them, all moved by one random rotation and translation in doubles (`moved`) or
// left in place: moved, contacts with the floor or the light's plane become hair crossings and
// hair gaps of either sign.
class PlacedScene {
  public:
    PlacedScene(std::mt19937_64& rng, bool moved) : r_(randomRotation(rng)), moved_(moved) {
        std::uniform_real_distribution<double> u(-1, 1);
        t_ = {100 * u(rng), 100 * u(rng), 100 * u(rng)};
        add({{-3, -3, 0}, {3, -3, 0}, {0, 3, 0}});
        add({{-0.6, -0.4, 2}, {0, 0.6, 2}, {0.6, -0.4, 2}}, true);
    }
    Vec3 place(const Vec3& v) const {
        return moved_ ? Vec3{vis::dot(r_[0], v), vis::dot(r_[1], v), vis::dot(r_[2], v)} + t_ : v;
    }
    void add(std::vector<Vec3> pts, bool emissive = false) {
        for (Vec3& v : pts) v = place(v);
        p_.add(pts, emissive);
    }
    Scene finish() { return p_.finish(); }

  private:
    std::array<Vec3, 3> r_;
    Vec3 t_;
    bool moved_;
    Polygons p_;
};

TEST(ExactClip, TransformedModelsStandingOnAFloor) {
    // A floor triangle, a light triangle, a box (no bottom face) and a leaning plank standing on
    // the floor, the whole scene rotated and translated in doubles: the contacts become hair
    // crossings and hair gaps of either sign.
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0, chordTrees = 0, blocked = 0;
    for (int i = 0; i < test::scaled(60); ++i) {
        PlacedScene p(rng, true);
        const double x0 = -0.4 + 0.1 * u(rng), x1 = 0.3 + 0.1 * u(rng), y0 = -0.3, y1 = 0.2;
        const double top = 0.6 + 0.2 * u(rng);
        const Vec3 c[8] = {{x0, y0, 0},   {x1, y0, 0},   {x1, y1, 0},   {x0, y1, 0},
                           {x0, y0, top}, {x1, y0, top}, {x1, y1, top}, {x0, y1, top}};
        const int quads[5][4] = {
            {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
        for (const auto& q : quads) {
            p.add({c[q[0]], c[q[1]], c[q[2]]});
            p.add({c[q[0]], c[q[2]], c[q[3]]});
        }
        p.add({{0.8, -0.5, 0}, {1.0, 0.5, 0}, {0.4, 0.1, 1.2}});  // a plank on its edge
        const Scene s = p.finish();
        Paths paths(s);
        chordTrees += hasChord(paths.complete());
        std::vector<Vec3> floor;
        for (uint32_t v : s.mesh.faces[0]) floor.push_back(s.mesh.vertices[v]);
        for (int k = 0; k < 8; ++k) {
            test::ReferenceResult ref;
            bad += paths.check(test::randomCombination(floor, rng, 0.05), "transformed", &ref);
            blocked += ref.fraction < 0.999;
        }
        // Points rounded from the box's contact with the floor: a corner (two sides' planes
        // within some ulps of x), a point of each bottom edge, and one of the plank's edge.
        const double t = 0.5 + 0.4 * u(rng);
        const Vec3 contacts[] = {c[i % 4],
                                 c[0] + (c[1] - c[0]) * t,
                                 c[1] + (c[2] - c[1]) * t,
                                 c[2] + (c[3] - c[2]) * t,
                                 c[3] + (c[0] - c[3]) * t,
                                 Vec3{0.8, -0.5, 0} + Vec3{0.2, 1.0, 0} * t};
        for (const int k : {i % 6, (i + 3) % 6})  // two of them per scene, in turn
            bad += paths.check(p.place(contacts[k]), "transformed, on a contact line");
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(chordTrees, 0);
    EXPECT_GT(blocked, test::scaled(60));
}

// A wall crossing the floor (its lower part below it) or standing on it (its bottom edge in the
// floor's plane), upright or leaning, the scene rotated and translated in doubles, and points
// rounded from the line where the wall meets the floor: x then lies within some ulps of the
// wall's chord or bottom edge and off the floor's plane by a rounding, so that the plane through
// x and that line is mostly rounding and turns through the light, which straddles the wall. Its
// sides and the fragments it cuts must still be the exact reference's, on every path (the trees
// store the chord).
TEST(ExactClip, TransformedContactLinesOfAWallMatchTheExactReference) {
    std::mt19937_64 rng(13);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0, chordTrees = 0, split = 0;
    for (int i = 0; i < test::scaled(48); ++i) {
        PlacedScene p(rng, true);
        // Crossing: from z = -0.5 to 1; standing: from 0 to 1. Leaning: y grows with z, through
        // y = 0 at z = 0 either way.
        const bool crossing = i % 2 == 0, leaning = (i / 2) % 2 == 1;
        const double bottom = crossing ? -0.5 : 0, lean = leaning ? 0.5 : 0;
        std::vector<Vec3> wall{
            {-1, lean * bottom, bottom}, {1, lean * bottom, bottom}, {1, lean, 1}, {-1, lean, 1}};
        if ((i / 4) % 2 == 1) std::reverse(wall.begin(), wall.end());
        p.add({wall[0], wall[1], wall[2]});
        p.add({wall[0], wall[2], wall[3]});
        const Scene s = p.finish();
        Paths paths(s);
        chordTrees += hasChord(paths.complete());
        for (int k = 0; k < 6; ++k) {
            const Vec3 onLine{0.9 * u(rng), 0, 0};  // where the wall meets z = 0
            test::ReferenceResult ref;
            bad += paths.check(p.place(onLine), "near a wall's contact line", &ref);
            split += ref.fraction > 0.05 && ref.fraction < 0.95;
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(chordTrees, test::scaled(48) / 4);
    EXPECT_GT(split, test::scaled(48));  // the wall's plane cut the light
}

// Sliver receivers: a triangle some 1e-8 to 1e-12 wide whose plane, seen at 80 degrees from the
// floor, cuts the light; the scene rotated in doubles, so that the plane's rounded normal is
// mostly rounding. The light clipped to the receiver's front (and everything after it) must
// still be the exact reference's.
TEST(ExactClip, SliverReceiversCutTheLightExactly) {
    std::mt19937_64 rng(5);
    int bad = 0, cut = 0;
    for (int r = 0; r < test::scaled(8); ++r) {
        const std::array<Vec3, 3> R = randomRotation(rng);
        auto rotated = [&](const Vec3& v) {
            return Vec3{vis::dot(R[0], v), vis::dot(R[1], v), vis::dot(R[2], v)};
        };
        for (double width : {1e-8, 1e-10, 1e-12}) {
            const double theta = 80 * M_PI / 180;
            Polygons p;
            p.add({rotated({0, -1, 0}), rotated({0, 1, 0}),
                   rotated({width * std::cos(theta), 0.3, width * std::sin(theta)})});
            p.add({rotated({-0.5, -0.5, 2}), rotated({-0.5, 0.5, 2}), rotated({0.5, 0.5, 2}),
                   rotated({0.5, -0.5, 2})},
                  true);
            p.add({rotated({-0.3, -0.3, 1}), rotated({0.3, -0.3, 1}), rotated({0.0, 0.3, 1.2})});
            const Scene s = p.finish();
            Paths paths(s);
            for (double y : {-0.5, 0.0, 0.25}) {
                test::ReferenceResult ref;
                bad += paths.check(rotated({0, y, 0}), "sliver receiver", &ref);
                cut += ref.unoccludedFormFactor > 0 && ref.fraction < 0.5;
            }
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(cut, test::scaled(8) * 3);  // the receiver's plane cut the light
}

// A wall standing on the floor along y = 0 (its bottom edge exactly in the floor's plane), both
// windings, the light straddling its plane or beside it; points exactly on the contact line and a
// dyadic hair to either side. The contract: a segment that touches the wall only at its end point
// x is not blocked, so on the line the wall blocks nothing; the reference says the same (it skips
// occluders in a plane through x).
TEST(ExactClip, ContactLinesAnswerTheContractOnEveryPath) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0, onLine = 0, contactAnswers = 0;
    for (bool reversed : {false, true}) {
        for (double lightX : {0.0, 0.75}) {
            for (bool atEdge : {false, true}) {
                Polygons p;
                // The floor [-2, 2] x [y0, 2] at z = 0: with atEdge the wall stands on its edge.
                const double y0 = atEdge ? 0 : -2;
                p.add({{-2, y0, 0}, {2, y0, 0}, {2, 2, 0}, {-2, 2, 0}});
                p.add({{lightX - 0.5, -0.5, 2},
                       {lightX - 0.5, 0.5, 2},
                       {lightX + 0.5, 0.5, 2},
                       {lightX + 0.5, -0.5, 2}},
                      true);
                std::vector<Vec3> wall{{-1, 0, 0}, {1, 0, 0}, {1, 0, 1}, {-1, 0, 1}};
                if (reversed) std::reverse(wall.begin(), wall.end());
                p.add(wall);
                const Scene s = p.finish();
                Paths paths(s);
                vis::FromPointQuery q;
                for (int k = 0; k < test::scaled(40); ++k) {
                    const double t = std::ldexp(std::round(std::ldexp(u(rng), 20)), -20);
                    for (double dy : {0.0, 0x1p-30, -0x1p-30, 0x1p-50}) {
                        if (atEdge && dy < 0) continue;  // off the receiver
                        bad += paths.check({t, dy, 0}, "contact line");
                        if (dy == 0) {
                            ++onLine;
                            q.run(s.mesh, paths.complete(), {t, 0, 0});
                            contactAnswers += q.answeredOnContact();
                        }
                    }
                }
            }
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(onLine, 0);
    EXPECT_EQ(contactAnswers, onLine);  // each point on the line took the contact rule
}

// The one approximation left: FPQuery's constructed fragment vertices whose sign the filter cannot
// certify count as on the plane (polygon_clip.h splitConstructed). Its stress case: x close to L's
// plane (a wall receiver reaching up to the light's height) and occluders just below the light, so
// that the planes through x and their edges are nearly parallel to L. The fragments must still
// match the exact reference to 1e-9 of L's area.
TEST(ExactClip, SnapRuleHoldsWithXNearTheLightPlane) {
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0, compared = 0, blocked = 0;
    for (int i = 0; i < test::scaled(40); ++i) {
        Polygons p;
        // The receiver: a wall at x = 1 facing -x, up to z = 2.5.
        p.add({{1, -2, 0}, {1, -2, 2.5}, {1, 2, 2.5}, {1, 2, 0}});
        p.add({{-0.5, -0.5, 2}, {-0.5, 0.5, 2}, {0.5, 0.5, 2}, {0.5, -0.5, 2}}, true);
        for (int k = 0; k < 4; ++k) {
            const double z = 2 - std::ldexp(1.0, -(4 + static_cast<int>(rng() % 20)));
            const Vec3 c{0.4 * u(rng), 0.4 * u(rng), z};
            p.add({c, c + Vec3{0.3, 0.05 * u(rng), 1e-3 * u(rng)},
                   c + Vec3{0.05 * u(rng), 0.3, 1e-3 * u(rng)}});
        }
        const Scene s = p.finish();
        Paths paths(s);
        for (int k = 0; k < 6; ++k) {
            const double eps = std::ldexp(1.0, -(8 + static_cast<int>(rng() % 30)));
            test::ReferenceResult ref;
            bad += paths.check({1, 1.5 * u(rng), 2 - eps}, "x near the light plane", &ref);
            blocked += ref.fraction > 1e-9 && ref.fraction < 0.999;
            ++compared;
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(blocked, compared / 4);
}

// Foliage: sixty loose leaves between the floor and the light, some touching the floor or the
// light's plane (hair crossings once the scene is rotated and translated in doubles), some pairs
// sharing an edge. Each point's query clips the leaves one by one (Algorithm 1) against many
// occluders at once: in the order of their solid angle, each piece only against the leaves its
// pyramid may meet (FromPointQuery::cullFor), and a leaf that blocks none of a piece leaves it
// whole.
TEST(ExactClip, ManyLeavesMatchTheExactReference) {
    std::mt19937_64 rng(17);
    std::uniform_real_distribution<double> u(-1, 1);
    int bad = 0, compared = 0, penumbra = 0, manyOccluders = 0;
    vis::FromPointQuery direct;
    for (int i = 0; i < test::scaled(12); ++i) {
        const bool transformed = i % 2 == 1;
        PlacedScene p(rng, transformed);
        Vec3 last[3];
        for (int k = 0; k < 60; ++k) {
            Vec3 c{0.5 * u(rng), 0.5 * u(rng), 1 + 0.8 * u(rng)};
            if (k % 5 == 0) c.z = 0.1;  // standing on the floor
            if (k % 7 == 0) c.z = 1.9;  // reaching the light's plane
            Vec3 a = c + Vec3{0.25 * u(rng), 0.25 * u(rng), 0.1 * u(rng)};
            Vec3 b = c + Vec3{0.25 * u(rng), 0.25 * u(rng), 0.1 * u(rng)};
            Vec3 d = c + Vec3{0.25 * u(rng), 0.25 * u(rng), 0.1 * u(rng)};
            if (k % 5 == 0) a.z = 0;
            if (k % 7 == 0) a.z = 2;
            if (k % 3 == 2) {  // shares an edge with the previous leaf
                a = last[1];
                b = last[2];
            }
            if (vis::length(vis::cross(b - a, d - a)) < 1e-3) continue;
            p.add({a, b, d});
            last[0] = a, last[1] = b, last[2] = d;
        }
        const Scene s = p.finish();
        Paths paths(s);
        const vis::BoxTree faces = test::faceBoxTree(s.mesh);
        std::vector<Vec3> floor;
        for (uint32_t v : s.mesh.faces[0]) floor.push_back(s.mesh.vertices[v]);
        for (int k = 0; k < 8; ++k) {
            const Vec3 x = p.place({0.8 * u(rng), 0.8 * u(rng), 0});
            test::ReferenceResult ref;
            bad += paths.check(x, transformed ? "leaves, transformed" : "leaves", &ref);
            penumbra += ref.fraction > 1e-9 && ref.fraction < 0.999;
            ++compared;
            direct.runDirect(s.mesh, 0, 1, x, faces);
            manyOccluders += direct.deferredActive() >= 16;
        }
    }
    EXPECT_EQ(bad, 0);
    EXPECT_GT(penumbra, compared / 3);
    EXPECT_GT(manyOccluders, compared / 3);  // the culled clip was exercised
}

}  // namespace
}  // namespace penumbra
