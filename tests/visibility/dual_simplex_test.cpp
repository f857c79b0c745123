// The dual simplex of the line polytopes against an independent reference: the optimum of each
// small program found by enumerating every vertex of its feasible region (all choices of d tight
// constraints in d variables, solved by Gaussian elimination, kept when feasible).
#include "visibility/dual_simplex.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace penumbra::vis {
namespace {

// max tau s.t. sum_k mu_k M[k][g] + tau <= rhs[g], sum mu <= bound, mu >= 0, tau >= 0; variables
// x = (mu_0 .. mu_{m-1}, tau). Constraints as a . x <= c.
double bruteForceOptimum(const std::vector<double>& M, size_t m, size_t n,
                         const std::vector<double>& rhs, double bound) {
    const size_t d = m + 1;
    std::vector<std::vector<double>> a;
    std::vector<double> c;
    for (size_t g = 0; g < n; ++g) {
        std::vector<double> row(d);
        for (size_t k = 0; k < m; ++k) row[k] = M[k * n + g];
        row[m] = 1;
        a.push_back(row);
        c.push_back(rhs[g]);
    }
    a.push_back(std::vector<double>(d, 1.0));
    a.back()[m] = 0;
    c.push_back(bound);
    for (size_t i = 0; i < d; ++i) {
        std::vector<double> row(d, 0.0);
        row[i] = -1;
        a.push_back(row);
        c.push_back(0);
    }
    const size_t total = a.size();
    double best = -INFINITY;
    std::vector<size_t> pick(d);
    // Every d-subset of the constraints (in increasing index order).
    std::vector<bool> mask(total, false);
    std::fill(mask.begin(), mask.begin() + static_cast<long>(d), true);
    do {
        size_t t = 0;
        for (size_t i = 0; i < total; ++i)
            if (mask[i]) pick[t++] = i;
        // Solve a[pick] x = c[pick] with partial pivoting.
        std::vector<std::vector<double>> s(d, std::vector<double>(d + 1));
        for (size_t r = 0; r < d; ++r) {
            for (size_t j = 0; j < d; ++j) s[r][j] = a[pick[r]][j];
            s[r][d] = c[pick[r]];
        }
        bool singular = false;
        for (size_t col = 0; col < d && !singular; ++col) {
            size_t p = col;
            for (size_t r = col + 1; r < d; ++r)
                if (std::fabs(s[r][col]) > std::fabs(s[p][col])) p = r;
            if (std::fabs(s[p][col]) < 1e-12) {
                singular = true;
                break;
            }
            std::swap(s[p], s[col]);
            for (size_t r = 0; r < d; ++r) {
                if (r == col) continue;
                const double f = s[r][col] / s[col][col];
                for (size_t j = col; j <= d; ++j) s[r][j] -= f * s[col][j];
            }
        }
        if (singular) continue;
        std::vector<double> x(d);
        for (size_t r = 0; r < d; ++r) x[r] = s[r][d] / s[r][r];
        bool feasible = true;
        for (size_t i = 0; i < total && feasible; ++i) {
            double v = 0;
            for (size_t j = 0; j < d; ++j) v += a[i][j] * x[j];
            feasible = v <= c[i] + 1e-9 * (1 + std::fabs(c[i]));
        }
        if (feasible) best = std::max(best, x[m]);
    } while (std::prev_permutation(mask.begin(), mask.end()));
    return best;
}

TEST(DualSimplex, ReachesTheOptimumOfRandomAndDegeneratePrograms) {
    std::mt19937_64 rng(5);
    int degenerate = 0;
    for (int trial = 0; trial < 1500; ++trial) {
        const size_t m = 1 + rng() % 3, n = 2 + rng() % 6;
        const bool integral = trial % 2 == 0;  // small integers: ties and degenerate vertices
        std::uniform_real_distribution<double> u(-1, 1);
        std::vector<double> M(m * n), rhs(n);
        for (double& v : M)
            v = integral ? static_cast<double>(static_cast<int>(rng() % 5) - 2) : u(rng);
        for (double& v : rhs)
            v = integral ? static_cast<double>(rng() % 3) : std::fabs(u(rng)) * (rng() % 4 != 0);
        degenerate += std::count(rhs.begin(), rhs.end(), 0.0) > 0;
        const double bound = integral ? 4.0 : 10.0;
        const double expected = bruteForceOptimum(M, m, n, rhs, bound);
        const DualSimplexResult r = solveDualSimplex(M, m, n, rhs, bound, INFINITY);
        ASSERT_FALSE(r.iterationLimit) << "trial " << trial;
        EXPECT_NEAR(r.tau, expected, 1e-9 * (1 + std::fabs(expected))) << "trial " << trial;
        // The multipliers are feasible and reach tau.
        double sum = 0;
        for (double v : r.mu) {
            EXPECT_GE(v, 0);
            sum += v;
        }
        EXPECT_LE(sum, bound * (1 + 1e-12)) << "trial " << trial;
        for (size_t g = 0; g < n; ++g) {
            double lhs = r.tau;
            for (size_t k = 0; k < m; ++k) lhs += r.mu[k] * M[k * n + g];
            EXPECT_LE(lhs, rhs[g] + 1e-9) << "trial " << trial << " generator " << g;
        }
        // Stopping early: as soon as tau reaches the threshold, never below it.
        if (expected > 1e-6) {
            const DualSimplexResult early = solveDualSimplex(M, m, n, rhs, bound, expected * 0.5);
            EXPECT_GE(early.tau, expected * 0.5 - 1e-12) << "trial " << trial;
        }
        // The workspace form gives the same answer when reused across programs.
        DualSimplexWorkspace ws;
        DualSimplexResult again;
        solveDualSimplex(M, m, n, rhs, bound, INFINITY, ws, again);
        solveDualSimplex(M, m, n, rhs, bound, INFINITY, ws, again);
        EXPECT_EQ(again.tau, r.tau);
        EXPECT_EQ(again.mu, r.mu);
    }
    EXPECT_GT(degenerate, 300);
}

}  // namespace
}  // namespace penumbra::vis
