// A small dense simplex for the one linear program the line polytopes need, solved in double.
//
// The program (the dual of "minimise c . lambda over a polytope given by generators and
// half-spaces", see line_polytope.h):
//
//     maximise tau  subject to  sum_k mu_k M[k][g] + tau <= rhs[g]  for every generator g,
//                               mu >= 0, tau >= 0, sum_k mu_k <= muBound,
//
// with rhs >= 0, so the origin is feasible and no phase 1 is needed. Dantzig's rule
// (most negative reduced cost), switching to Bland's rule after a run of degenerate pivots (no
// cycling on the heavy degeneracy these programs have). The answer is approximate: callers never
// trust it, they verify the multipliers mu as a certificate with rigorous error bounds
// (line_polytope.cpp) and take the conservative branch when that fails.
#pragma once

#include <span>
#include <vector>

namespace penumbra::vis {

struct DualSimplexResult {
    std::vector<double> mu;      // multipliers (>= 0)
    double tau = 0;              // objective reached
    std::vector<double> primal;  // the primal point lambda (normalised to sum 1; may be empty)
    bool stoppedEarly = false;   // tau reached stopAt before optimality
    bool iterationLimit = false;
};

// Reusable storage of solveDualSimplex: a caller that solves many programs keeps one, and after
// warm-up a solve allocates nothing.
struct DualSimplexWorkspace {
    std::vector<double> tableau, b, obj;
    std::vector<size_t> basic, nonbasic;
};

// M is row-major, rows = mu variables (m of them), columns = generators (n). Stops as soon as
// tau >= stopAt (the caller's certificate threshold).
DualSimplexResult solveDualSimplex(std::span<const double> M, size_t m, size_t n,
                                   std::span<const double> rhs, double muBound, double stopAt);
// The same into `result` (its vectors keep their capacity), with `ws` as scratch.
void solveDualSimplex(std::span<const double> M, size_t m, size_t n, std::span<const double> rhs,
                      double muBound, double stopAt, DualSimplexWorkspace& ws,
                      DualSimplexResult& result);

}  // namespace penumbra::vis
