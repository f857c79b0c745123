#include "visibility/line_polytope.h"

#include <gmpxx.h>

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <optional>
#include <unordered_map>

#include "visibility/dual_simplex.h"
#include "visibility/exact_orient.h"
#include "visibility/plucker.h"
#include "visibility/polygon_clip.h"

namespace penumbra::vis {
namespace {

constexpr double kUnit = DBL_EPSILON;  // 2^-52, twice the unit roundoff: generous bounds

WitnessMask strictPositive(const HyperplaneRow& r) {
    return r.certainNonNegative & ~r.certainNonPositive;
}
WitnessMask strictNegative(const HyperplaneRow& r) {
    return r.certainNonPositive & ~r.certainNonNegative;
}

// A deterministic low-discrepancy point in a convex polygon: fan triangle chosen by area, then a
// uniform point of that triangle (square-root warp).
Vec3 pointInPolygon(std::span<const Vec3> p, double u, double v, double w) {
    std::vector<double> cum;
    double total = 0;
    for (size_t i = 1; i + 1 < p.size(); ++i) {
        total += length(cross(p[i] - p[0], p[i + 1] - p[0]));
        cum.push_back(total);
    }
    size_t t = 0;
    while (t + 1 < cum.size() && u * total > cum[t]) ++t;
    const double su = std::sqrt(v);
    const double a = 1 - su, b = su * (1 - w), c = su * w;
    return p[0] * a + p[t + 1] * b + p[t + 2] * c;
}

double radicalInverse(uint32_t i, uint32_t base) {
    double inv = 1.0 / base, f = inv, r = 0;
    for (; i > 0; i /= base, f *= inv) r += f * (i % base);
    return r;
}

// Rigorous check of the certificate: for every generator g,
//   sign*h[g] - sum_k mu_k * sign_k * row_k[g] >= 0
// with the rounding of this very evaluation and the error of every entry accounted for.
bool verifyCertificate(std::span<const Constraint> path, const HyperplaneRow& h, int sign,
                       std::span<const double> mu) {
    const size_t n = h.value.size();
    const double gamma = static_cast<double>(path.size() + 3) * kUnit;
    for (size_t g = 0; g < n; ++g) {
        double r = sign * h.value[g];
        double bound = h.error[g];
        double absSum = std::fabs(r);
        for (size_t k = 0; k < path.size(); ++k) {
            if (mu[k] == 0) continue;
            const double t = mu[k] * (path[k].sign * path[k].row->value[g]);
            r -= t;
            bound += mu[k] * path[k].row->error[g];
            absSum += std::fabs(t);
        }
        if (absSum > 0) bound += gamma * absSum + 1e-300;
        if (!(r >= bound)) return false;
    }
    return true;
}

// The row restricted to the sub-polygon of B with vertices w[0..2] (weights over B's vertices),
// into `out` (its vectors keep their capacity).
void restrictRowInto(const HyperplaneRow& row, const PieceWeights& w, size_t nB, size_t nL,
                     HyperplaneRow& out) {
    out.restricted = true;
    out.value.assign(w.size() * nL, 0.0);
    out.error.assign(w.size() * nL, 0.0);
    const double gamma = static_cast<double>(nB + 2) * kUnit;
    for (size_t k = 0; k < w.size(); ++k)
        for (size_t j = 0; j < nL; ++j) {
            double v = 0, e = 0, a = 0;
            for (size_t i = 0; i < nB; ++i) {
                const double wi = (*w[k])[i];
                if (wi == 0) continue;
                const double t = wi * row.value[i * nL + j];
                v += t;
                e += wi * row.error[i * nL + j];
                a += std::fabs(t);
            }
            if (a > 0) e += gamma * a + 1e-300;
            out.value[k * nL + j] = v;
            out.error[k * nL + j] = e;
        }
}

// The multipliers m with sum_q m_q a[q][g] = c[g] on s = a.size() independent generators, chosen
// greedily in the order of `tight`; empty where no s of them are independent. Exact (rationals).
std::optional<std::vector<mpq_class>> solveOnTight(
    const std::vector<std::vector<mpq_class>>& a, const std::vector<mpq_class>& c,
    const std::vector<std::pair<double, size_t>>& tight) {
    const size_t s = a.size();
    // Solve sum_q m_q a[q][g] = c[g] on s independent tight generators (Gaussian elimination in
    // rationals, choosing generators greedily), then verify m >= 0 and every residual >= 0.
    std::vector<std::vector<mpq_class>> sys;  // rows: [a[0][g] .. a[s-1][g] | c[g]]
    for (const auto& [res, g] : tight) {
        if (sys.size() == s) break;
        std::vector<mpq_class> row(s + 1);
        for (size_t q = 0; q < s; ++q) row[q] = a[q][g];
        row[s] = c[g];
        // Reduce against the rows chosen so far (each has a pivot column).
        for (size_t r = 0; r < sys.size(); ++r) {
            size_t p = 0;
            while (p < s && sgn(sys[r][p]) == 0) ++p;
            if (p == s || sgn(row[p]) == 0) continue;
            const mpq_class f = row[p] / sys[r][p];
            for (size_t q = 0; q <= s; ++q) row[q] -= f * sys[r][q];
        }
        bool independent = false;
        for (size_t q = 0; q < s; ++q) independent |= sgn(row[q]) != 0;
        if (independent) sys.push_back(std::move(row));
    }
    if (sys.size() != s) return std::nullopt;
    // Back-substitute: bring the system to reduced echelon form.
    std::vector<size_t> pivot(s);
    for (size_t r = 0; r < s; ++r) {
        size_t p = 0;
        while (p < s && sgn(sys[r][p]) == 0) ++p;
        pivot[r] = p;
    }
    for (size_t r = s; r-- > 0;) {
        const mpq_class d = sys[r][pivot[r]];
        for (size_t q = 0; q <= s; ++q) sys[r][q] /= d;
        for (size_t o = 0; o < s; ++o) {
            if (o == r || sgn(sys[o][pivot[r]]) == 0) continue;
            const mpq_class f = sys[o][pivot[r]];
            for (size_t q = 0; q <= s; ++q) sys[o][q] -= f * sys[r][q];
        }
    }
    std::vector<mpq_class> m(s);
    for (size_t r = 0; r < s; ++r) {
        if (pivot[r] >= s) return std::nullopt;
        m[pivot[r]] = sys[r][s];
    }
    return m;
}

}  // namespace

struct LinePolytopeSpace::ExactCache {
    std::unordered_map<const HyperplaneRow*, std::vector<mpq_class>> rows;
};

LinePolytopeSpace::~LinePolytopeSpace() = default;

LinePolytopeSpace::LinePolytopeSpace(std::span<const Vec3> receiver, std::span<const Vec3> light)
    : exact_(std::make_unique<ExactCache>()),
      b_(receiver.begin(), receiver.end()),
      l_(light.begin(), light.end()) {
    probes_ = b_;
    probes_.insert(probes_.end(), l_.begin(), l_.end());
    samples_.reserve(kSampleWitnesses);
    for (uint32_t s = 0; s < kSampleWitnesses; ++s) {
        const uint32_t i = s + 1;
        samples_.push_back(
            {pointInPolygon(b_, radicalInverse(i, 2), radicalInverse(i, 3), radicalInverse(i, 5)),
             pointInPolygon(l_, radicalInverse(i, 7), radicalInverse(i, 11),
                            radicalInverse(i, 13))});
    }
}

WitnessMask LinePolytopeSpace::allWitnesses() const {
    WitnessMask m;
    for (size_t g = 0; g < std::min(generatorCount(), kGeneratorWitnesses); ++g) m.set(g);
    for (size_t s = 0; s < samples_.size(); ++s) m.set(kGeneratorWitnesses + s);
    return m;
}

HyperplaneRow LinePolytopeSpace::row(const EdgeLine& edge) const {
    const size_t n = generatorCount();
    HyperplaneRow r;
    r.edge = edge;
    r.value.resize(n);
    r.error.resize(n);
    double maxAbs = 0;
    // A chord's side at generator (b_i, l_j) is pi1(b_i) pi2(l_j) - pi1(l_j) pi2(b_i): the
    // planes are evaluated once per vertex, not once per generator.
    const bool chord = edge.kind == EdgeLine::Kind::Planes;
    std::array<std::vector<BoundedValue>, 4> at;  // pi1 and pi2 at B's, then at L's vertices
    if (chord) {
        for (const Vec3& p : b_) {
            at[0].push_back(edge.first.value(p));
            at[1].push_back(edge.second.value(p));
        }
        for (const Vec3& p : l_) {
            at[2].push_back(edge.first.value(p));
            at[3].push_back(edge.second.value(p));
        }
    }
    for (size_t i = 0; i < b_.size(); ++i)
        for (size_t j = 0; j < l_.size(); ++j) {
            BoundedValue v;
            if (chord) {
                v = differenceOfProducts(at[0][i], at[3][j], at[2][j], at[1][i]);
                if (!v.certain()) v = roundedExact(sideExact(b_[i], l_[j], edge));
            } else {
                v = sideValue(b_[i], l_[j], edge);
            }
            const size_t g = i * l_.size() + j;
            r.value[g] = v.value;
            r.error[g] = v.error;
            maxAbs = std::max(maxAbs, std::fabs(v.value));
            if (g < kGeneratorWitnesses && v.certain()) {
                if (v.value >= 0) r.certainNonNegative.set(g);
                if (v.value <= 0) r.certainNonPositive.set(g);
            }
        }
    for (size_t s = 0; s < samples_.size(); ++s) {
        const std::optional<Sign> sg =
            sideSignFiltered(samples_[s].first, samples_[s].second, edge);
        if (!sg) continue;
        if (*sg == Sign::Positive) r.certainNonNegative.set(kGeneratorWitnesses + s);
        if (*sg == Sign::Negative) r.certainNonPositive.set(kGeneratorWitnesses + s);
    }
    if (maxAbs > 0) {
        int exp = 0;
        std::frexp(maxAbs, &exp);
        r.scaleExp = exp;
        for (size_t g = 0; g < n; ++g) {  // scaling by a power of two is exact
            r.value[g] = std::ldexp(r.value[g], -exp);
            r.error[g] = std::ldexp(r.error[g], -exp);
        }
    }
    return r;
}

bool LinePolytopeSpace::certifyNonNegative(std::span<const Constraint> path, const HyperplaneRow& h,
                                           int sign, PolytopeStats& stats,
                                           std::vector<double>* witness) const {
    const size_t n = h.value.size();
    const size_t m = path.size();
    LpScratch& lp = lp_;
    std::vector<double>& mu = lp.mu;
    mu.assign(m, 0.0);
    if (verifyCertificate(path, h, sign, mu)) return true;  // every generator already >= 0
    if (m == 0) return false;
    double cmin = INFINITY;
    for (size_t g = 0; g < n; ++g) cmin = std::min(cmin, sign * h.value[g]);
    std::vector<double>& M = lp.matrix;
    std::vector<double>& rhs = lp.rhs;
    M.resize(m * n);
    rhs.resize(n);
    for (size_t k = 0; k < m; ++k)
        for (size_t g = 0; g < n; ++g) M[k * n + g] = path[k].sign * path[k].row->value[g];
    for (size_t g = 0; g < n; ++g) rhs[g] = sign * h.value[g] - cmin;
    ++stats.lpSolves;
    // Run until the bound t = cmin + tau clears zero with some margin, or to optimality.
    DualSimplexResult& res = lp.result;
    solveDualSimplex(M, m, n, rhs, 1e8, -cmin + 1e-6, lp.workspace, res);
    if (verifyCertificate(path, h, sign, res.mu)) return true;
    if (cmin + res.tau >= -1e-9) {  // the LP believes it: a zero margin the doubles cannot see
        if (certifyExactly(path, h, sign, res.mu)) {
            ++stats.exactCertificates;
            return true;
        }
        ++stats.uncertain;
    }
    if (witness) *witness = res.primal;
    return false;
}

const auto& LinePolytopeSpace::exactRow(const HyperplaneRow& r) const {
    // The row's exact values, as scaled in the LP: one per generator (b_i, l_j).
    const size_t n = r.value.size();
    auto it = exact_->rows.find(&r);
    if (it != exact_->rows.end()) return it->second;
    std::vector<mpq_class> v(n);
    if (r.edge.kind == EdgeLine::Kind::Planes) {
        // pi1(b_i) pi2(l_j) - pi1(l_j) pi2(b_i): each plane exactly once per vertex.
        const PlaneOrient &p1 = r.edge.first, &p2 = r.edge.second;
        std::vector<mpq_class> b1, b2, l1, l2;
        for (const Vec3& p : b_) {
            b1.push_back(orientExact(p1.a, p1.b, p1.c, p));
            b2.push_back(orientExact(p2.a, p2.b, p2.c, p));
        }
        for (const Vec3& p : l_) {
            l1.push_back(orientExact(p1.a, p1.b, p1.c, p));
            l2.push_back(orientExact(p2.a, p2.b, p2.c, p));
        }
        for (size_t i = 0; i < b_.size(); ++i)
            for (size_t j = 0; j < l_.size(); ++j)
                v[i * l_.size() + j] = b1[i] * l2[j] - l1[j] * b2[i];
    } else {
        for (size_t i = 0; i < b_.size(); ++i)
            for (size_t j = 0; j < l_.size(); ++j)
                v[i * l_.size() + j] = sideExact(b_[i], l_[j], r.edge);
    }
    return exact_->rows.emplace(&r, std::move(v)).first->second;
}

bool LinePolytopeSpace::certifyExactly(std::span<const Constraint> path, const HyperplaneRow& h,
                                       int sign, std::span<const double> mu) const {
    if (h.restricted) return false;
    const size_t n = h.value.size();
    // Support of the multipliers: the half-spaces the certificate combines.
    double muMax = 0;
    for (double v : mu) muMax = std::max(muMax, v);
    std::vector<size_t> support;
    for (size_t k = 0; k < mu.size(); ++k)
        if (mu[k] > 1e-12 * muMax) support.push_back(k);
    if (support.empty() || support.size() > 5) return false;
    // Exact rows, as scaled in the LP: the multipliers are then comparable to mu.
    const std::vector<mpq_class>& hx = exactRow(h);
    std::vector<const std::vector<mpq_class>*> ax;
    for (size_t k : support) {
        if (path[k].row->restricted) return false;
        ax.push_back(&exactRow(*path[k].row));
    }
    auto scaled = [](const mpq_class& v, int exp) {
        mpq_class r = v;
        if (exp > 0) mpq_div_2exp(r.get_mpq_t(), r.get_mpq_t(), static_cast<mp_bitcnt_t>(exp));
        if (exp < 0) mpq_mul_2exp(r.get_mpq_t(), r.get_mpq_t(), static_cast<mp_bitcnt_t>(-exp));
        return r;
    };
    const size_t s = support.size();
    std::vector<mpq_class> c(n);
    std::vector<std::vector<mpq_class>> a(s, std::vector<mpq_class>(n));
    for (size_t g = 0; g < n; ++g) {
        c[g] = scaled(hx[g], h.scaleExp) * sign;
        for (size_t q = 0; q < s; ++q)
            a[q][g] = scaled((*ax[q])[g], path[support[q]].row->scaleExp) * path[support[q]].sign;
    }
    // Tight generators (r_g ~ 0 in double), most tight first.
    std::vector<std::pair<double, size_t>> tight;
    for (size_t g = 0; g < n; ++g) {
        double r = sign * h.value[g];
        for (size_t q = 0; q < s; ++q)
            r -= mu[support[q]] * path[support[q]].sign * path[support[q]].row->value[g];
        tight.push_back({std::fabs(r), g});
    }
    std::sort(tight.begin(), tight.end());
    const std::optional<std::vector<mpq_class>> multipliers = solveOnTight(a, c, tight);
    if (!multipliers) return false;
    const std::vector<mpq_class>& m = *multipliers;
    for (const mpq_class& v : m)
        if (sgn(v) < 0) return false;
    for (size_t g = 0; g < n; ++g) {
        mpq_class r = c[g];
        for (size_t q = 0; q < s; ++q) r -= m[q] * a[q][g];
        if (sgn(r) < 0) return false;
    }
    return true;
}

Side LinePolytopeSpace::classify(std::span<const Constraint> path, const WitnessMask& inside,
                                 const HyperplaneRow& h, PolytopeStats& stats,
                                 RelaxationPoints* points) const {
    if (points != nullptr) points->known = {false, false};
    // The hyperplane of an edge already on the path (occluders sharing an edge, or collinear
    // edges): the polytope lies on the known side of it. Decided exactly, with no linear program:
    // the rounded rows of the same hyperplane cannot certify a zero margin.
    for (const Constraint& c : path) {
        int same = 0;
        if (sameLine(c.row->edge, h.edge, probes_, same))
            return same * c.sign > 0 ? Side::Positive : Side::Negative;
    }
    // A failed certificate of sign s leaves the program's primal point: a point of the relaxation
    // on the side -s of h (RelaxationPoints).
    auto certify = [&](int sign) {
        const size_t k = sign > 0 ? 0 : 1;
        std::vector<double>* witness = points != nullptr ? &points->onSide[k] : nullptr;
        if (witness != nullptr) witness->clear();
        const bool ok = certifyNonNegative(path, h, sign, stats, witness);
        if (points != nullptr && !ok) points->known[k] = true;
        return ok;
    };
    const bool hasPos = (inside & strictPositive(h)).any();
    const bool hasNeg = (inside & strictNegative(h)).any();
    if (hasPos && hasNeg) return Side::Mixed;
    if (!hasNeg) {
        if (certify(+1)) return Side::Positive;
        if (hasPos) return Side::Mixed;
        return certify(-1) ? Side::Negative : Side::Mixed;
    }
    return certify(-1) ? Side::Negative : Side::Mixed;
}

bool LinePolytopeSpace::provablyNoRealLine(std::span<const Constraint> path,
                                           const WitnessMask& inside, const HyperplaneRow& h,
                                           int side, int maxLevels, PolytopeStats& stats,
                                           const RelaxationPoints* points) const {
    // A generator strictly on that side is a real line there.
    ++stats.realLineTests;
    if ((inside & (side > 0 ? strictPositive(h) : strictNegative(h))).any() ||
        findRealLine(path, inside, h, side, {})) {
        ++stats.realLineWitness;
        return false;
    }
    const size_t nB = b_.size(), nL = l_.size();
    {
        // The relaxation's point on that side: from classify's failed certificate when it ran
        // one (the same program), else solved here.
        const size_t k = side < 0 ? 0 : 1;  // RelaxationPoints' index of `side`
        std::vector<double> solved;
        const std::vector<double>* primal = nullptr;
        if (points != nullptr && points->known[k]) {
            primal = &points->onSide[k];
        } else {
            if (certifyNonNegative(path, h, -side, stats, &solved)) {
                ++stats.realLineProofs;  // even the relaxation has nothing there
                return true;
            }
            primal = &solved;
        }
        if (!primal->empty()) {
            Vec3 b{};
            for (size_t i = 0; i < nB; ++i)
                for (size_t j = 0; j < nL; ++j) b += b_[i] * (*primal)[i * nL + j];
            if (findRealLine(path, {}, h, side, std::span<const Vec3>(&b, 1))) {
                ++stats.realLineWitness;
                return false;
            }
        }
    }
    std::vector<double> corner[3];
    for (size_t i = 1; i + 1 < nB; ++i) {  // fan triangles of B cover B
        for (std::vector<double>& c : corner) c.assign(nB, 0.0);
        corner[0][0] = 1;
        corner[1][i] = 1;
        corner[2][i + 1] = 1;
        const PieceWeights w = {&corner[0], &corner[1], &corner[2]};
        if (!provePieceEmpty(path, h, side, w, maxLevels, stats)) return false;
    }
    ++stats.realLineProofs;
    return true;
}

bool LinePolytopeSpace::findRealLine(std::span<const Constraint> path, const WitnessMask& inside,
                                     const HyperplaneRow& h, int side,
                                     std::span<const Vec3> extraPoints) const {
    constexpr size_t kMaxPoints = 12;
    std::vector<Vec3> points(extraPoints.begin(), extraPoints.end());
    for (size_t s = 0; s < samples_.size() && points.size() < kMaxPoints / 2; ++s)
        if (inside.test(kGeneratorWitnesses + s)) points.push_back(samples_[s].first);
    for (size_t g = 0; g < std::min(generatorCount(), kGeneratorWitnesses); ++g)
        if (inside.test(g) && points.size() < kMaxPoints) points.push_back(b_[g / l_.size()]);
    Vec3 centroid{};
    for (const Vec3& p : b_) centroid += p / static_cast<double>(b_.size());
    points.push_back(centroid);
    for (const Vec3& p : b_) points.push_back(p);
    for (const Vec3& p : b_) points.push_back((p + centroid) * 0.5);
    std::vector<Vec3>& poly = scratch_.poly;
    std::vector<Vec3>& positive = scratch_.positive;
    std::vector<Vec3>& negative = scratch_.negative;
    for (const Vec3& x : points) {
        // Lines through x: their side of edge (a, c) is the side of their L-point against the
        // plane through x, a, c (orient3d(x, y, a, c) == orient3d(x, a, c, y)).
        poly.assign(l_.begin(), l_.end());
        auto keep = [&](const HyperplaneRow& row, int s) {
            if (row.edge.kind == EdgeLine::Kind::Points)
                clipConvexInto(poly, OrientedPlane{x, row.edge.p, row.edge.q}, positive, negative);
            else
                clipConvexInto(poly, EdgePlane(x, row.edge), positive, negative);
            std::swap(poly, s > 0 ? positive : negative);
            return poly.size() >= 3;
        };
        bool ok = keep(h, side);
        // Deepest half-spaces first: they are the narrowest, so a point whose lines miss the
        // polytope is usually rejected after a few clips.
        for (size_t k = path.size(); ok && k-- > 0;) ok = keep(*path[k].row, path[k].sign);
        if (ok) return true;
    }
    return false;
}

bool LinePolytopeSpace::provePieceEmpty(std::span<const Constraint> path, const HyperplaneRow& h,
                                        int side, const PieceWeights& w, int levelsLeft,
                                        PolytopeStats& stats) const {
    const size_t nB = b_.size(), nL = l_.size();
    double bary[3] = {0, 0, 0};  // where the relaxation's point lies, as weights of the corners
    {
        // The restricted rows are needed only for this one program: one scratch serves every
        // level of the recursion.
        std::vector<HyperplaneRow>& rows = scratch_.rows;
        std::vector<Constraint>& sub = scratch_.sub;
        if (rows.size() < path.size()) rows.resize(path.size());
        sub.resize(path.size());
        for (size_t k = 0; k < path.size(); ++k) {
            restrictRowInto(*path[k].row, w, nB, nL, rows[k]);
            sub[k] = {&rows[k], path[k].sign};
        }
        restrictRowInto(h, w, nB, nL, scratch_.h);
        // No line of the piece strictly on `side`: min over the piece of (-side) * h >= 0.
        std::vector<double>& primal = scratch_.piecePrimal;
        primal.clear();
        if (certifyNonNegative(sub, scratch_.h, -side, stats, &primal)) return true;
        for (size_t k = 0; k < 3 && !primal.empty(); ++k)
            for (size_t j = 0; j < nL; ++j) bary[k] += primal[k * nL + j];
    }
    if (levelsLeft <= 0) return false;
    std::vector<double> mids[3];  // the edges' midpoints: dyadic weights, exact
    for (size_t e = 0; e < 3; ++e) {
        mids[e].resize(nB);
        for (size_t i = 0; i < nB; ++i) mids[e][i] = 0.5 * ((*w[e])[i] + (*w[(e + 1) % 3])[i]);
    }
    const std::vector<double>*m01 = &mids[0], *m12 = &mids[1], *m20 = &mids[2];
    const PieceWeights pieces[4] = {
        {w[0], m01, m20}, {m01, w[1], m12}, {m20, m12, w[2]}, {m01, m12, m20}};
    // The sub-piece holding the relaxation's point first: when the proof fails it usually fails
    // there, before programs are spent on the others.
    int first = 3;
    for (int k = 0; k < 3; ++k)
        if (bary[k] >= 0.5) first = k;
    const int order[4][4] = {{0, 1, 2, 3}, {1, 0, 2, 3}, {2, 0, 1, 3}, {3, 0, 1, 2}};
    for (int i : order[first])
        if (!provePieceEmpty(path, h, side, pieces[i], levelsLeft - 1, stats)) return false;
    return true;
}

}  // namespace penumbra::vis
