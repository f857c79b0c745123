// LinePolytopeSpace (visibility/line_polytope.h): its rows against exact orient3d signs, its
// certificates against brute force (every sampled real line of a polytope it certifies to lie on
// one side of a hyperplane must lie on that side; a side it proves to hold no real line must
// hold none of the sampled ones), and hand-made cases whose answer is derived below.
//
// Hand-derived geometry used throughout: B = [0,1]^2 at z = 0, L = [0,1]^2 at z = 4, and edge
// lines along y at height 2, E(c) through (c, -10, 2) -> (c, 10, 2). For the line from
// b = (bx, by, 0) to l = (lx, ly, 4), with d = l - b and a = p - b,
//   orient3d(b, l, p, q) = det[d, a, q - p] = 20 (4 a_x - 2 d_x) = 80 (c - (bx + lx) / 2),
// so its side against E(c) is the sign of c - xmid, xmid = (bx + lx) / 2 the line's x at z = 2:
// positive for the lines passing E(c) on the -x side. Reversing E(c) flips every sign.
#include "visibility/line_polytope.h"

#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <numbers>
#include <random>
#include <vector>

#include "tests/support/random_points.h"
#include "tests/support/test_scale.h"

namespace penumbra {
namespace {

using vis::Constraint;
using vis::EdgeLine;
using vis::HyperplaneRow;
using vis::LinePolytopeSpace;
using vis::PlaneOrient;
using vis::PolytopeStats;
using vis::Side;
using vis::Vec3;
using vis::WitnessMask;

std::vector<Vec3> square(double z) { return {{0, 0, z}, {1, 0, z}, {1, 1, z}, {0, 1, z}}; }

// E(c), directed +y (or -y when `reversed`), through points other than the defaults when asked.
EdgeLine alongY(double c, bool reversed = false, double y0 = -10, double y1 = 10) {
    const Vec3 p{c, y0, 2}, q{c, y1, 2};
    return reversed ? EdgeLine::through(q, p) : EdgeLine::through(p, q);
}

int sideOf(const Vec3& b, const Vec3& l, const EdgeLine& e) {
    return vis::toInt(vis::sideSign(b, l, e));
}

// A problem over one space: rows live as long as the space (it caches exact rows by address).
struct Problem {
    LinePolytopeSpace space;
    std::deque<HyperplaneRow> rows;
    std::vector<Constraint> path;
    WitnessMask inside;
    PolytopeStats stats;

    Problem(std::span<const Vec3> b, std::span<const Vec3> l)
        : space(b, l), inside(space.allWitnesses()) {}
    const HyperplaneRow& row(const EdgeLine& e) {
        rows.push_back(space.row(e));
        return rows.back();
    }
    // Adds the half-space sign * side >= 0, narrowing the witnesses as the tree builder does.
    void constrain(const EdgeLine& e, int sign) {
        const HyperplaneRow& r = row(e);
        path.push_back({&r, sign});
        inside &= sign > 0 ? r.certainNonNegative : r.certainNonPositive;
    }
    Side classify(const EdgeLine& e) {
        const HyperplaneRow& h = row(e);
        return space.classify(path, inside, h, stats);
    }
    bool noRealLine(const EdgeLine& e, int side) {
        const HyperplaneRow& h = row(e);
        return space.provablyNoRealLine(path, inside, h, side, 3, stats);
    }
};

// ---- rows -----------------------------------------------------------------------------------

// Every generator (b_i, l_j), g = i |L| + j, gets the exact side of its line: hand-derived values
// for E(0.5) (including exact zeros), and the meet of the planes z = 2 and x = 0.5 directed +y is
// the same line as E(0.5), so its row has the same signs.
TEST(LinePolytope, RowsHoldTheExactSideOfEveryGeneratorLine) {
    const std::vector<Vec3> b = square(0), l = square(4);
    LinePolytopeSpace space(b, l);
    ASSERT_EQ(space.generatorCount(), 16u);
    const HyperplaneRow points = space.row(alongY(0.5));
    // Plane z = 2 with normal +z, plane x = 0.5 with normal +x: they meet along +z x +x = +y.
    const PlaneOrient zPlane({0, 0, 2}, {1, 0, 2}, {0, 1, 2});
    const PlaneOrient xPlane({0.5, 0, 0}, {0.5, 1, 0}, {0.5, 0, 1});
    const HyperplaneRow chord = space.row(EdgeLine::meet(zPlane, xPlane));
    for (const HyperplaneRow* r : {&points, &chord}) {
        ASSERT_EQ(r->value.size(), 16u);
        double maxAbs = 0;
        for (size_t g = 0; g < 16; ++g) {
            const Vec3 &bi = b[g / 4], &lj = l[g % 4];
            const double xmid = (bi.x + lj.x) / 2;
            const int expected = xmid < 0.5 ? 1 : (xmid > 0.5 ? -1 : 0);
            EXPECT_EQ(vis::toInt(vis::BoundedValue{r->value[g], 0}.sign()), expected)
                << "generator " << g << (r == &chord ? " (chord)" : "");
            if (expected == 0) {
                EXPECT_EQ(r->error[g], 0) << "an exact zero stays exact";
            }
            EXPECT_TRUE((vis::BoundedValue{r->value[g], r->error[g]}.certain()))
                << "generator " << g << ": the sign is not certain";
            // The witness bits of generator lines are never wrong.
            if (r->certainNonNegative.test(g)) {
                EXPECT_GE(expected, 0) << "generator " << g;
            }
            if (r->certainNonPositive.test(g)) {
                EXPECT_LE(expected, 0) << "generator " << g;
            }
            if (expected > 0) {
                EXPECT_TRUE(r->certainNonNegative.test(g)) << "generator " << g;
            }
            if (expected < 0) {
                EXPECT_TRUE(r->certainNonPositive.test(g)) << "generator " << g;
            }
            maxAbs = std::max(maxAbs, std::fabs(r->value[g]));
        }
        // Scaled by a power of two into [0.5, 1).
        EXPECT_GE(maxAbs, 0.5);
        EXPECT_LT(maxAbs, 1.0);
    }
    // 80 (c - xmid) is 40 at the generator (b_0, l_0) (xmid = 0): the scale is 2^-6.
    EXPECT_EQ(points.scaleExp, 6);
    EXPECT_EQ(points.value[0], 40.0 / 64);
}

// Random polygons and edges of both kinds: each generator's value has the exact sign of
// orient3d (or of the pencil difference for a chord), and the generator witness bits agree.
TEST(LinePolytope, RowSignsMatchExactPredicatesOnRandomInput) {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(-1.5, 1.5), h(1, 3);
    int zeros = 0;
    for (int t = 0; t < test::scaled(200); ++t) {
        const std::vector<Vec3> b = {{u(rng), u(rng), 0}, {u(rng), u(rng), 0}, {u(rng), u(rng), 0}};
        const std::vector<Vec3> l = {
            {u(rng), u(rng), 4}, {u(rng), u(rng), 4}, {u(rng), u(rng), 4}, {u(rng), u(rng), 4}};
        LinePolytopeSpace space(b, l);
        const Vec3 p{u(rng), u(rng), h(rng)};
        // Every other edge passes through a vertex of B: exact zeros at its generators.
        const Vec3 q = t % 2 ? b[0] + (l[1] - b[0]) * 0.5 : Vec3{u(rng), u(rng), h(rng)};
        const EdgeLine edges[2] = {
            EdgeLine::through(p, q),
            EdgeLine::meet(PlaneOrient(p, {u(rng), u(rng), h(rng)}, {u(rng), u(rng), h(rng)}),
                           PlaneOrient(q, {u(rng), u(rng), h(rng)}, {u(rng), u(rng), h(rng)}))};
        for (const EdgeLine& e : edges) {
            const HyperplaneRow r = space.row(e);
            for (size_t g = 0; g < space.generatorCount(); ++g) {
                const int exact = sideOf(b[g / l.size()], l[g % l.size()], e);
                zeros += exact == 0;
                EXPECT_EQ(vis::toInt(vis::BoundedValue{r.value[g], 0}.sign()), exact)
                    << "trial " << t << " generator " << g;
                if (r.certainNonNegative.test(g)) {
                    EXPECT_GE(exact, 0);
                }
                if (r.certainNonPositive.test(g)) {
                    EXPECT_LE(exact, 0);
                }
            }
        }
    }
    EXPECT_GT(zeros, 0);  // exact zeros were among the cases
}

// ---- classification: hand-made cases --------------------------------------------------------

TEST(LinePolytope, ClassifiesHandMadeCasesWithoutAPath) {
    const std::vector<Vec3> b = square(0), l = square(4);
    Problem p(b, l);
    // Every line has xmid in [0, 1].
    EXPECT_EQ(p.classify(alongY(5)), Side::Positive);        // 5 - xmid > 0
    EXPECT_EQ(p.classify(alongY(5, true)), Side::Negative);  // reversed
    EXPECT_EQ(p.classify(alongY(-3)), Side::Negative);       // -3 - xmid < 0
    EXPECT_EQ(p.classify(alongY(1)), Side::Positive);        // 1 - xmid >= 0, zero when touching
    EXPECT_EQ(p.classify(alongY(0)), Side::Negative);        // 0 - xmid <= 0
    EXPECT_EQ(p.classify(alongY(0.5)), Side::Mixed);         // both signs occur
    EXPECT_EQ(p.classify(alongY(0.5, true)), Side::Mixed);
    // An edge line across the shaft in another direction: the line x = y at z = 2 (lines from
    // (0,1,0) to (0,1,4) pass on one side, from (1,0,0) to (1,0,4) on the other).
    EXPECT_EQ(p.classify(EdgeLine::through({-5, -5, 2}, {5, 5, 2})), Side::Mixed);
}

TEST(LinePolytope, ClassifiesHandMadeCasesOnAPath) {
    const std::vector<Vec3> b = square(0), l = square(4);
    {
        Problem p(b, l);
        p.constrain(alongY(0.5), +1);                        // the lines with xmid <= 0.5
        EXPECT_EQ(p.classify(alongY(0.7)), Side::Positive);  // 0.7 - xmid >= 0.2
        EXPECT_EQ(p.classify(alongY(0.7, true)), Side::Negative);
        EXPECT_EQ(p.classify(alongY(0.3)), Side::Mixed);  // xmid 0 and xmid 0.5 both there
        // The path's own line, through other points, either way round: the known side.
        EXPECT_EQ(p.classify(alongY(0.5, false, 3, 7)), Side::Positive);
        EXPECT_EQ(p.classify(alongY(0.5, true, -4, 3)), Side::Negative);
        // The same line as the meet of two planes (no shared description with the path's row):
        // the margin is exactly zero, a certificate in doubles cannot see it; it must still be
        // certified.
        const PlaneOrient zPlane({0, 0, 2}, {1, 0, 2}, {0, 1, 2});
        const PlaneOrient xPlane({0.5, 0, 0}, {0.5, 1, 0}, {0.5, 0, 1});
        EXPECT_EQ(p.classify(EdgeLine::meet(zPlane, xPlane)), Side::Positive);
        EXPECT_EQ(p.classify(EdgeLine::meet(xPlane, zPlane)), Side::Negative);
        EXPECT_GT(p.stats.lpSolves, 0u);
    }
    {
        Problem p(b, l);
        p.constrain(alongY(0.5), -1);                        // xmid >= 0.5
        EXPECT_EQ(p.classify(alongY(0.3)), Side::Negative);  // 0.3 - xmid <= -0.2
        EXPECT_EQ(p.classify(alongY(0.8)), Side::Mixed);
    }
    {
        // Two half-spaces together: xmid <= 0.6 and xmid >= 0.4 leaves a slab; E(0.2) and E(0.8)
        // lie on either side of all of it.
        Problem p(b, l);
        p.constrain(alongY(0.6), +1);
        p.constrain(alongY(0.4), -1);
        EXPECT_EQ(p.classify(alongY(0.2)), Side::Negative);
        EXPECT_EQ(p.classify(alongY(0.8)), Side::Positive);
        EXPECT_EQ(p.classify(alongY(0.5)), Side::Mixed);
    }
}

TEST(LinePolytope, ProvesNoRealLineOnlyWhereThereIsNone) {
    const std::vector<Vec3> b = square(0), l = square(4);
    Problem p(b, l);
    EXPECT_TRUE(p.noRealLine(alongY(5), -1));  // every line is strictly positive
    EXPECT_FALSE(p.noRealLine(alongY(5), +1));
    EXPECT_TRUE(p.noRealLine(alongY(1), -1));  // touching: none strictly negative
    EXPECT_FALSE(p.noRealLine(alongY(1), +1));
    EXPECT_FALSE(p.noRealLine(alongY(0.5), -1));  // lines on both sides
    EXPECT_FALSE(p.noRealLine(alongY(0.5), +1));
    p.constrain(alongY(0.5), +1);  // xmid <= 0.5
    EXPECT_TRUE(p.noRealLine(alongY(0.7), -1));
    EXPECT_FALSE(p.noRealLine(alongY(0.3), -1));  // xmid in (0.3, 0.5]
    EXPECT_FALSE(p.noRealLine(alongY(0.3), +1));  // xmid < 0.3
}

// ---- classification: brute force ------------------------------------------------------------

// A random convex polygon of k vertices around `centre`, in a plane tilted slightly from z.
std::vector<Vec3> randomPolygon(const Vec3& centre, size_t k, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> angle(0, 2 * std::numbers::pi), tilt(-0.3, 0.3),
        radius(0.5, 1.2);
    std::vector<double> a;
    while (true) {
        a.clear();
        for (size_t i = 0; i < k; ++i) a.push_back(angle(rng));
        std::sort(a.begin(), a.end());
        double minGap = a.front() + 2 * std::numbers::pi - a.back();
        for (size_t i = 1; i < k; ++i) minGap = std::min(minGap, a[i] - a[i - 1]);
        if (minGap > 0.3) break;
    }
    const double tx = tilt(rng), ty = tilt(rng), r = radius(rng);
    std::vector<Vec3> p;
    for (double t : a) {
        const double x = r * std::cos(t), y = r * std::sin(t);
        p.push_back(centre + Vec3{x, y, tx * x + ty * y});
    }
    return p;
}

// A point of the convex polygon: a vertex, a point of an edge, or an interior point.
Vec3 randomPointIn(std::span<const Vec3> poly, std::mt19937_64& rng) {
    switch (rng() % 4) {
        case 0:
            return poly[rng() % poly.size()];
        case 1: {
            const size_t i = rng() % poly.size();
            const double t = std::uniform_real_distribution<double>(0, 1)(rng);
            return poly[i] + (poly[(i + 1) % poly.size()] - poly[i]) * t;
        }
        default:
            return test::randomCombination(poly, rng, 0.0);
    }
}

EdgeLine randomEdge(std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(-1.5, 1.5), h(1, 3);
    auto point = [&]() { return Vec3{u(rng), u(rng), h(rng)}; };
    if (rng() % 3 == 0)
        return EdgeLine::meet(PlaneOrient(point(), point(), point()),
                              PlaneOrient(point(), point(), point()));
    return EdgeLine::through(point(), point());
}

// What brute force sees of a polytope and a hyperplane: sampled real lines in the closed
// polytope, and how many of them lie strictly on either side.
struct Seen {
    int inside = 0, positive = 0, negative = 0;
};

// The first line sampled is the anchor (y0, z0), which the path was built to hold.
Seen sample(std::span<const Vec3> b, std::span<const Vec3> l, std::span<const Constraint> path,
            const EdgeLine& h, const Vec3& y0, const Vec3& z0, int lines, std::mt19937_64& rng) {
    Seen s;
    for (int i = 0; i < lines; ++i) {
        const Vec3 y = i == 0 ? y0 : randomPointIn(b, rng), z = i == 0 ? z0 : randomPointIn(l, rng);
        bool in = true;
        for (const Constraint& c : path) in = in && c.sign * sideOf(y, z, c.row->edge) >= 0;
        if (!in) continue;
        ++s.inside;
        const int side = sideOf(y, z, h);
        s.positive += side > 0;
        s.negative += side < 0;
    }
    return s;
}

// Random B, L, paths and hyperplanes. The path's signs are those of a random real line (so the
// polytope holds at least that line). Every claim is checked against sampled real lines: a
// certified side holds every sampled line of the polytope, a side proven empty of real lines
// holds none. Without a path the classification is exact (the side is bilinear in the end
// points, so it has one sign on all lines iff it has that sign on the generators).
TEST(LinePolytope, CertificatesHoldForEverySampledLine) {
    std::mt19937_64 rng(7);
    int answers[3] = {0, 0, 0}, checkedLines = 0, mixedBothSides = 0;
    const int trials = test::scaled(600);
    for (int t = 0; t < trials; ++t) {
        const std::vector<Vec3> b = randomPolygon({0, 0, 0}, 3 + rng() % 3, rng);
        const std::vector<Vec3> l = randomPolygon({0.3, -0.2, 4}, 3 + rng() % 3, rng);
        Problem p(b, l);
        const size_t depth = rng() % 5;
        const Vec3 anchorB = randomPointIn(b, rng), anchorL = randomPointIn(l, rng);
        while (p.path.size() < depth) {
            const EdgeLine e = randomEdge(rng);
            const int s = sideOf(anchorB, anchorL, e);
            if (s != 0) p.constrain(e, s);
        }
        const EdgeLine h = randomEdge(rng);
        const HyperplaneRow& row = p.row(h);
        vis::RelaxationPoints relaxation;
        const Side side = p.space.classify(p.path, p.inside, row, p.stats, &relaxation);
        ++answers[vis::toInt(static_cast<vis::Sign>(side)) + 1];
        const Seen seen = sample(b, l, p.path, h, anchorB, anchorL, 400, rng);
        ASSERT_GT(seen.inside, 0) << "trial " << t << ": the anchor line is not in its polytope";
        const std::string where =
            "trial " + std::to_string(t) + ", path of " + std::to_string(p.path.size());
        if (side == Side::Positive) {
            EXPECT_EQ(seen.negative, 0) << where << ": certified Positive";
            checkedLines += seen.inside;
        } else if (side == Side::Negative) {
            EXPECT_EQ(seen.positive, 0) << where << ": certified Negative";
            checkedLines += seen.inside;
        } else {
            mixedBothSides += seen.positive > 0 && seen.negative > 0;
        }
        if (p.path.empty()) {
            int pos = 0, neg = 0;
            for (const Vec3& bi : b)
                for (const Vec3& lj : l) {
                    pos += sideOf(bi, lj, h) > 0;
                    neg += sideOf(bi, lj, h) < 0;
                }
            const Side exact =
                pos > 0 && neg > 0 ? Side::Mixed : (neg > 0 ? Side::Negative : Side::Positive);
            EXPECT_EQ(side, exact)
                << where << ": " << pos << " positive, " << neg << " negative generators";
        }
        if (side != Side::Mixed) continue;
        // The real-line test, as the builder runs it (with what classify left) and on its own.
        for (int s : {-1, +1}) {
            for (const vis::RelaxationPoints* points :
                 std::initializer_list<const vis::RelaxationPoints*>{&relaxation, nullptr}) {
                if (!p.space.provablyNoRealLine(p.path, p.inside, row, s, 3, p.stats, points))
                    continue;
                EXPECT_EQ(s > 0 ? seen.positive : seen.negative, 0)
                    << where << ": proven to hold no real line strictly on side " << s;
            }
        }
    }
    // Each answer occurred, and the certified ones were checked against real lines.
    EXPECT_GT(answers[0], trials / 20);
    EXPECT_GT(answers[1], trials / 20);
    EXPECT_GT(answers[2], trials / 20);
    EXPECT_GT(checkedLines, trials);
    EXPECT_GT(mixedBothSides, trials / 20);
}

// The real-line test where it matters: a Mixed relaxation (points of it on both sides of h) of
// which one side is proven to hold no real line. Paths as the builder makes them, from the edges
// of small triangles (the side of each edge a random line passes), h an edge of another one.
// Such proofs are rare in random input (about one Mixed answer in three hundred), so trials run
// until five have been found; each is checked against many sampled real lines of the polytope.
TEST(LinePolytope, RealLineProofsHoldForEverySampledLine) {
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> u(-1.2, 1.2), height(1, 3), d(-0.3, 0.3);
    auto triangle = [&]() {
        const Vec3 c{u(rng), u(rng), height(rng)};
        std::vector<Vec3> t;
        for (int k = 0; k < 3; ++k) t.push_back(c + Vec3{d(rng), d(rng), 0.3 * d(rng)});
        return t;
    };
    int proofs = 0, mixed = 0, trials = 0;
    for (; trials < 20000 && proofs < 5; ++trials) {
        const std::vector<Vec3> b = randomPolygon({0, 0, 0}, 3 + rng() % 3, rng);
        const std::vector<Vec3> l = randomPolygon({0.3, -0.2, 4}, 3 + rng() % 3, rng);
        Problem p(b, l);
        const Vec3 anchorB = randomPointIn(b, rng), anchorL = randomPointIn(l, rng);
        const std::vector<Vec3> occluder = triangle(), next = triangle();
        for (int e = 0; e < 3; ++e) {
            const EdgeLine edge = EdgeLine::through(occluder[e], occluder[(e + 1) % 3]);
            const int s = sideOf(anchorB, anchorL, edge);
            if (s != 0) p.constrain(edge, s);
        }
        for (int e = 0; e < 3; ++e) {
            const EdgeLine h = EdgeLine::through(next[e], next[(e + 1) % 3]);
            const HyperplaneRow& row = p.row(h);
            vis::RelaxationPoints relaxation;
            if (p.space.classify(p.path, p.inside, row, p.stats, &relaxation) != Side::Mixed)
                continue;
            ++mixed;
            for (int side : {-1, +1}) {
                if (!p.space.provablyNoRealLine(p.path, p.inside, row, side, 3, p.stats,
                                                &relaxation))
                    continue;
                ++proofs;
                // The same answer without classify's points (the program solved again).
                EXPECT_TRUE(p.space.provablyNoRealLine(p.path, p.inside, row, side, 3, p.stats));
                const Seen seen = sample(b, l, p.path, h, anchorB, anchorL, 20000, rng);
                EXPECT_GT(seen.inside, 1);
                EXPECT_EQ(side > 0 ? seen.positive : seen.negative, 0)
                    << "trial " << trials << " edge " << e << ": proven to hold no real line on "
                    << "side " << side << " of h";
            }
        }
    }
    EXPECT_EQ(proofs, 5) << "in " << trials << " trials, " << mixed << " Mixed answers";
}

}  // namespace
}  // namespace penumbra
