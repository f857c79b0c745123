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

namespace dual_simplex_detail {

// The condensed tableau of solveDualSimplex (rows x cols, row-major) and the bookkeeping of its
// pivots, over the caller's workspace.
struct Tableau {
    DualSimplexWorkspace& ws;
    size_t rows, cols;
    double value = 0;  // the objective reached (tau)
    double& at(size_t r, size_t c) { return ws.tableau[r * cols + c]; }
};

void setUp(Tableau& t, std::span<const double> M, size_t m, size_t n, std::span<const double> rhs,
           double muBound) {
    DualSimplexWorkspace& ws = t.ws;
    const size_t tauVar = m;
    ws.tableau.assign(t.rows * t.cols, 0.0);
    ws.b.assign(t.rows, 0.0);
    ws.obj.assign(t.cols, 0.0);
    for (size_t g = 0; g < n; ++g) {
        for (size_t k = 0; k < m; ++k) t.at(g, k) = M[k * n + g];
        t.at(g, tauVar) = 1;
        ws.b[g] = rhs[g];
    }
    for (size_t k = 0; k < m; ++k) t.at(n, k) = 1;
    ws.b[n] = muBound;
    ws.obj[tauVar] = -1;  // reduced costs of the non-basic variables
    ws.basic.resize(t.rows);
    ws.nonbasic.resize(t.cols);
    for (size_t r = 0; r < t.rows; ++r) ws.basic[r] = m + 1 + r;
    for (size_t c = 0; c < t.cols; ++c) ws.nonbasic[c] = c;
}

constexpr double kTol = 1e-12;

// The entering column: Dantzig's rule (the most negative reduced cost), or Bland's (the variable
// of smallest number) when `bland`; cols where none is negative (optimal).
size_t entering(const Tableau& t, bool bland) {
    const std::vector<double>& obj = t.ws.obj;
    const std::vector<size_t>& nonbasic = t.ws.nonbasic;
    size_t enter = t.cols;
    for (size_t c = 0; c < t.cols; ++c) {
        if (!(obj[c] < -kTol)) continue;
        if (enter == t.cols || (bland ? nonbasic[c] < nonbasic[enter] : obj[c] < obj[enter]))
            enter = c;
    }
    return enter;
}

// The leaving row by the ratio test, ties to the basic variable of smallest number (Bland); rows
// where none bounds the entering column.
size_t leaving(Tableau& t, size_t enter) {
    size_t leave = t.rows;
    double best = std::numeric_limits<double>::infinity();
    for (size_t r = 0; r < t.rows; ++r) {
        const double a = t.at(r, enter);
        if (a > kTol) {
            const double ratio = t.ws.b[r] / a;
            if (ratio < best - 1e-15 ||
                (ratio <= best + 1e-15 && leave < t.rows && t.ws.basic[r] < t.ws.basic[leave])) {
                best = ratio;
                leave = r;
            }
        }
    }
    return leave;
}

// Jordan exchange of basic[leave] and nonbasic[enter]. The leaving variable's column was the unit
// vector of row `leave`: it becomes column `enter`. Returns the objective's change.
double exchange(Tableau& t, size_t leave, size_t enter) {
    std::vector<double>& T = t.ws.tableau;
    std::vector<double>& b = t.ws.b;
    std::vector<double>& obj = t.ws.obj;
    const size_t cols = t.cols;
    const double piv = t.at(leave, enter);
    double* pivotRow = &T[leave * cols];
    for (size_t c = 0; c < cols; ++c) pivotRow[c] /= piv;
    b[leave] /= piv;
    pivotRow[enter] = 1 / piv;
    for (size_t r = 0; r < t.rows; ++r) {
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
    std::swap(t.ws.basic[leave], t.ws.nonbasic[enter]);
    return f * b[leave];
}

// The multipliers (basic mu), and the primal values: the reduced costs of the generator slacks
// (zero while basic), normalised to sum 1 (none where they sum to 0).
void readResult(const Tableau& t, size_t m, size_t n, DualSimplexResult& res) {
    const DualSimplexWorkspace& ws = t.ws;
    res.tau = t.value;
    res.mu.assign(m, 0.0);
    for (size_t r = 0; r < t.rows; ++r)
        if (ws.basic[r] < m) res.mu[ws.basic[r]] = std::fmax(0.0, ws.b[r]);
    double sum = 0;
    res.primal.assign(n, 0.0);
    for (size_t c = 0; c < t.cols; ++c) {
        const size_t v = ws.nonbasic[c];
        if (v >= m + 1 && v < m + 1 + n) res.primal[v - m - 1] = std::fmax(0.0, ws.obj[c]);
    }
    for (double v : res.primal) sum += v;
    if (sum > 0)
        for (double& v : res.primal) v /= sum;
    else
        res.primal.clear();
}

}  // namespace dual_simplex_detail

void solveDualSimplex(std::span<const double> M, size_t m, size_t n, std::span<const double> rhs,
                      double muBound, double stopAt, DualSimplexWorkspace& ws,
                      DualSimplexResult& res) {
    // Condensed (Tucker) tableau: one row per basic variable, one column per non-basic one; the
    // identity block of the basic slacks is not stored. Variables are numbered as in the full
    // tableau: 0..m-1 mu, m tau, m+1..m+n+1 the slacks of rows 0..n (row n: the bound on sum mu).
    // Pivots are Jordan exchanges: the arithmetic on every stored entry is that of the full
    // tableau. Ties in the ratio test go to the basic variable of smallest number (Bland).
    using namespace dual_simplex_detail;
    // Non-basic variables: m + 1 columns; the right-hand side is kept apart.
    Tableau t{ws, n + 1, m + 1};
    setUp(t, M, m, n, rhs, muBound);
    res.stoppedEarly = false;
    const size_t maxIter = 50 * (t.rows + m + 1 + t.rows + 1);
    size_t iter = 0;
    constexpr size_t kDegenerateLimit = 8;
    size_t degenerateRun = 0;
    for (; iter < maxIter; ++iter) {
        if (t.value >= stopAt) {
            res.stoppedEarly = true;
            break;
        }
        // Dantzig's rule while pivots make progress; after a run of degenerate pivots, Bland's
        // rule, which cannot cycle.
        const size_t enter = entering(t, degenerateRun >= kDegenerateLimit);
        if (enter == t.cols) break;  // optimal
        const size_t leave = leaving(t, enter);
        if (leave == t.rows) break;  // unbounded cannot happen with the mu bound; stop safely
        const double before = t.value;
        t.value -= exchange(t, leave, enter);
        degenerateRun = t.value > before ? 0 : degenerateRun + 1;
    }
    res.iterationLimit = iter == maxIter;
    readResult(t, m, n, res);
}

}  // namespace penumbra::vis
