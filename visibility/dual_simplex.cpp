#include "visibility/dual_simplex.h"

#include <cmath>
#include <limits>
#include <utility>

namespace penumbra::vis {

DualSimplexResult solveDualSimplex(std::span<const double> M, size_t m, size_t n,
                                   std::span<const double> rhs, double muBound, double stopAt) {
    DualSimplexWorkspace ws;
    DualSimplexResult res;
    solveDualSimplex(M, m, n, rhs, muBound, stopAt, ws, res);
    return res;
}

void solveDualSimplex(std::span<const double> M, size_t m, size_t n, std::span<const double> rhs,
                      double muBound, double stopAt, DualSimplexWorkspace& ws,
                      DualSimplexResult& res) {
    // Condensed (Tucker) tableau: one row per basic variable, one column per non-basic one; the
    // identity block of the basic slacks is not stored. Variables are numbered as in the full
    // tableau: 0..m-1 mu, m tau, m+1..m+n+1 the slacks of rows 0..n (row n: the bound on sum mu).
    // Pivots are Jordan exchanges: the arithmetic on every stored entry is that of the full
    // tableau. Ties in the ratio test go to the basic variable of smallest number (Bland).
    const size_t rows = n + 1;
    const size_t cols = m + 1;  // non-basic variables; the right-hand side is kept apart
    const size_t tauVar = m;
    std::vector<double>& T = ws.tableau;
    std::vector<double>& b = ws.b;
    std::vector<double>& obj = ws.obj;
    T.assign(rows * cols, 0.0);
    b.assign(rows, 0.0);
    obj.assign(cols, 0.0);
    auto at = [&](size_t r, size_t c) -> double& { return T[r * cols + c]; };
    for (size_t g = 0; g < n; ++g) {
        for (size_t k = 0; k < m; ++k) at(g, k) = M[k * n + g];
        at(g, tauVar) = 1;
        b[g] = rhs[g];
    }
    for (size_t k = 0; k < m; ++k) at(n, k) = 1;
    b[n] = muBound;
    double value = 0;  // the objective reached (tau)
    obj[tauVar] = -1;  // reduced costs of the non-basic variables
    std::vector<size_t>& basic = ws.basic;
    std::vector<size_t>& nonbasic = ws.nonbasic;
    basic.resize(rows);
    nonbasic.resize(cols);
    for (size_t r = 0; r < rows; ++r) basic[r] = m + 1 + r;
    for (size_t c = 0; c < cols; ++c) nonbasic[c] = c;

    constexpr double kTol = 1e-12;
    res.stoppedEarly = false;
    const size_t maxIter = 50 * (rows + m + 1 + rows + 1);
    size_t iter = 0;
    constexpr size_t kDegenerateLimit = 8;
    size_t degenerateRun = 0;
    for (; iter < maxIter; ++iter) {
        if (value >= stopAt) {
            res.stoppedEarly = true;
            break;
        }
        // Dantzig's rule (the most negative reduced cost) while pivots make progress; after a
        // run of degenerate pivots, Bland's rule, which cannot cycle.
        const bool bland = degenerateRun >= kDegenerateLimit;
        size_t enter = cols;
        for (size_t c = 0; c < cols; ++c) {
            if (!(obj[c] < -kTol)) continue;
            if (enter == cols || (bland ? nonbasic[c] < nonbasic[enter] : obj[c] < obj[enter]))
                enter = c;
        }
        if (enter == cols) break;  // optimal
        size_t leave = rows;
        double best = std::numeric_limits<double>::infinity();
        for (size_t r = 0; r < rows; ++r) {
            const double a = at(r, enter);
            if (a > kTol) {
                const double ratio = b[r] / a;
                if (ratio < best - 1e-15 ||
                    (ratio <= best + 1e-15 && leave < rows && basic[r] < basic[leave])) {
                    best = ratio;
                    leave = r;
                }
            }
        }
        if (leave == rows) break;  // unbounded cannot happen with the mu bound; stop safely
        // Jordan exchange of basic[leave] and nonbasic[enter]. The leaving variable's column was
        // the unit vector of row `leave`: it becomes column `enter`.
        const double piv = at(leave, enter);
        double* pivotRow = &T[leave * cols];
        for (size_t c = 0; c < cols; ++c) pivotRow[c] /= piv;
        b[leave] /= piv;
        pivotRow[enter] = 1 / piv;
        for (size_t r = 0; r < rows; ++r) {
            if (r == leave) continue;
            double* row = &T[r * cols];
            const double f = row[enter];
            if (f == 0) continue;
            for (size_t c = 0; c < cols; ++c) row[c] -= f * pivotRow[c];
            row[enter] = 0 - f * pivotRow[enter];
            b[r] -= f * b[leave];
            if (b[r] < 0 && b[r] > -1e-13) b[r] = 0;
        }
        const double f = obj[enter];
        for (size_t c = 0; c < cols; ++c) obj[c] -= f * pivotRow[c];
        obj[enter] = 0 - f * pivotRow[enter];
        const double before = value;
        value -= f * b[leave];
        degenerateRun = value > before ? 0 : degenerateRun + 1;
        std::swap(basic[leave], nonbasic[enter]);
    }
    res.iterationLimit = iter == maxIter;
    res.tau = value;
    res.mu.assign(m, 0.0);
    for (size_t r = 0; r < rows; ++r)
        if (basic[r] < m) res.mu[basic[r]] = std::fmax(0.0, b[r]);
    // Primal values: the reduced costs of the generator slacks (zero while basic).
    double sum = 0;
    res.primal.assign(n, 0.0);
    for (size_t c = 0; c < cols; ++c) {
        const size_t v = nonbasic[c];
        if (v >= m + 1 && v < m + 1 + n) res.primal[v - m - 1] = std::fmax(0.0, obj[c]);
    }
    for (double v : res.primal) sum += v;
    if (sum > 0)
        for (double& v : res.primal) v /= sum;
    else
        res.primal.clear();
}

}  // namespace penumbra::vis
