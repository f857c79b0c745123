#include "visibility/dual_simplex.h"

#include <cmath>
#include <limits>

namespace penumbra::vis {

DualSimplexResult solveDualSimplex(std::span<const double> M, size_t m, size_t n,
                                   std::span<const double> rhs, double muBound, double stopAt) {
    // Tableau: rows 0..n-1 the generator constraints, row n the bound on sum mu.
    // Columns: 0..m-1 mu, m tau, m+1..m+n+1 slacks, last = right-hand side.
    const size_t rows = n + 1;
    const size_t cols = m + 1 + rows + 1;
    const size_t rhsCol = cols - 1;
    const size_t tauCol = m;
    std::vector<double> T(rows * cols, 0.0);
    auto at = [&](size_t r, size_t c) -> double& { return T[r * cols + c]; };
    for (size_t g = 0; g < n; ++g) {
        for (size_t k = 0; k < m; ++k) at(g, k) = M[k * n + g];
        at(g, tauCol) = 1;
        at(g, m + 1 + g) = 1;
        at(g, rhsCol) = rhs[g];
    }
    for (size_t k = 0; k < m; ++k) at(n, k) = 1;
    at(n, m + 1 + n) = 1;
    at(n, rhsCol) = muBound;
    std::vector<double> obj(cols, 0.0);  // reduced costs; obj[rhsCol] = objective value
    obj[tauCol] = -1;
    std::vector<size_t> basis(rows);
    for (size_t r = 0; r < rows; ++r) basis[r] = m + 1 + r;

    constexpr double kTol = 1e-12;
    DualSimplexResult res;
    const size_t maxIter = 50 * (rows + cols);
    size_t iter = 0;
    for (; iter < maxIter; ++iter) {
        if (obj[rhsCol] >= stopAt) {
            res.stoppedEarly = true;
            break;
        }
        size_t enter = cols;
        for (size_t c = 0; c < rhsCol; ++c)
            if (obj[c] < -kTol) {
                enter = c;
                break;
            }
        if (enter == cols) break;  // optimal
        size_t leave = rows;
        double best = std::numeric_limits<double>::infinity();
        for (size_t r = 0; r < rows; ++r) {
            const double a = at(r, enter);
            if (a > kTol) {
                const double ratio = at(r, rhsCol) / a;
                if (ratio < best - 1e-15 || (ratio <= best + 1e-15 && leave < rows &&
                                              basis[r] < basis[leave])) {
                    best = ratio;
                    leave = r;
                }
            }
        }
        if (leave == rows) break;  // unbounded cannot happen with the mu bound; stop safely
        const double piv = at(leave, enter);
        for (size_t c = 0; c < cols; ++c) at(leave, c) /= piv;
        for (size_t r = 0; r < rows; ++r) {
            if (r == leave) continue;
            const double f = at(r, enter);
            if (f == 0) continue;
            for (size_t c = 0; c < cols; ++c) at(r, c) -= f * at(leave, c);
            if (at(r, rhsCol) < 0 && at(r, rhsCol) > -1e-13) at(r, rhsCol) = 0;
        }
        const double f = obj[enter];
        for (size_t c = 0; c < cols; ++c) obj[c] -= f * at(leave, c);
        basis[leave] = enter;
    }
    res.iterationLimit = iter == maxIter;
    res.tau = obj[rhsCol];
    res.mu.assign(m, 0.0);
    for (size_t r = 0; r < rows; ++r)
        if (basis[r] < m) res.mu[basis[r]] = std::fmax(0.0, at(r, rhsCol));
    // Primal values: the reduced costs of the generator slacks.
    double sum = 0;
    res.primal.assign(n, 0.0);
    for (size_t g = 0; g < n; ++g) {
        res.primal[g] = std::fmax(0.0, obj[m + 1 + g]);
        sum += res.primal[g];
    }
    if (sum > 0)
        for (double& v : res.primal) v /= sum;
    else
        res.primal.clear();
    return res;
}

}  // namespace penumbra::vis
