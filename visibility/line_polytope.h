// Polytopes of lines in P^5, held as inequalities over the generators of the stabbing polytope.
//
// The lines stabbing two convex polygons B and L are exactly the real points of the cone spanned
// by the |B| x |L| vertex-pair lines g_ij = pi(b_i, l_j): pi(b, l) is bilinear in (b, l), so the
// line through b = sum a_i b_i and l = sum c_j l_j is sum a_i c_j g_ij. Every polytope of the
// history tree is that cone cut by the half-spaces on its path, so a point of it is a weight vector
// lambda >= 0 over the generators (sum 1) with row_k . lambda >= 0 for each path half-space, where
// row_k[g] = side(g, edge_k) = orient3d(b_i, l_j, edge_k): exact input-point predicates. No vertex
// enumeration, no constructed points in P^5, and nothing special about non-simple polytopes
// (many hyperplanes through one vertex).
//
// Classification of a polytope against a hyperplane h (the only decision the tree builder makes):
//   Positive  certified: min over the polytope of h . lambda >= 0, by LP duality: multipliers
//             mu >= 0 with h[g] - sum_k mu_k row_k[g] >= 0 for every g, checked with rigorous
//             error bounds (the multipliers come from a double simplex, dual_simplex.h, and are
//             never trusted unchecked);
//   Negative  certified likewise for -h;
//   Mixed     otherwise: also whenever neither certificate verifies. An extra split is harmless,
//             a wrong label is not, so uncertainty always becomes a split.
// The polytope here is a relaxation (it also holds non-real points of P^5), so "Positive" for it
// implies "Positive" for its real lines. The real-line (Plücker quadric) test goes further: it
// proves that one side of a Mixed split holds no real line, by the same certificate on the
// relaxations of sub-polygons of B (the relaxation of lines through a small piece of B tends to
// the exact set of real lines as the piece shrinks: lines through one point form a linear space
// inside the quadric). Unproven means "may hold real lines": the split is kept.
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "visibility/dual_simplex.h"
#include "visibility/edge_line.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

// Witness lines: real lines known per polytope by a bit mask. Bits 0..63 are the first 64
// generators (vertex-pair lines, exact signs); bits 64.. are sample lines between points spread
// over B and L (their signs come from the floating-point filter; an uncertain sign sets neither
// bit). Witnesses only ever *prove* that a polytope has lines on both sides of a hyperplane, the
// answer that costs a split: a witness that is slightly wrong can cost an extra node, never a
// wrong label.
inline constexpr size_t kGeneratorWitnesses = 64;
inline constexpr size_t kSampleWitnesses = 192;
using WitnessMask = std::bitset<kGeneratorWitnesses + kSampleWitnesses>;

// A hyperplane of P^5 (the lines meeting one oriented edge), evaluated at the generators.
// Values are scaled by a power of two (exact) so the largest magnitude is in [0.5, 1).
struct HyperplaneRow {
    std::vector<double> value;
    std::vector<double> error;  // rigorous bound per entry; 0 for exact values (exact zeros too)
    WitnessMask certainNonNegative;  // witness lines certainly on the closed positive side
    WitnessMask certainNonPositive;  // witness lines certainly on the closed negative side
    EdgeLine edge;                   // the oriented edge line whose hyperplane this is
    int scaleExp = 0;                // value = exact * 2^-scaleExp
    bool restricted = false;         // rows of a sub-polygon of B (no exact fallback for these)
};

// One half-space on a polytope's path: sign * row . lambda >= 0.
struct Constraint {
    const HyperplaneRow* row = nullptr;
    int sign = 1;
};

// A triangle inside B as the weights of its three corners over B's vertices (each sums to 1).
using PieceWeights = std::array<const std::vector<double>*, 3>;

enum class Side : int8_t { Negative = -1, Mixed = 0, Positive = 1 };

// What classify learns about the relaxation besides its answer: a failed certificate for the
// sign s leaves the program's primal point, a point of the relaxation on the side -s of h (weights
// over the generators, summing to 1; empty when the program gave none). provablyNoRealLine needs
// exactly that program for the side -s, so it takes the point instead of solving it again.
struct RelaxationPoints {
    std::array<std::vector<double>, 2> onSide;  // [0]: side -1, [1]: side +1
    std::array<bool, 2> known{false, false};    // whether classify ran that program
};

struct PolytopeStats {
    uint64_t lpSolves = 0;
    uint64_t uncertain = 0;  // an LP said one-sided but no certificate verified (took the split)
    uint64_t exactCertificates = 0;  // certificates that needed the exact rational fallback
    uint64_t realLineTests = 0;      // provablyNoRealLine calls
    uint64_t realLineWitness = 0;    // ... answered by a witness line (cheap "may hold lines")
    uint64_t realLineProofs = 0;     // ... proven empty
};

class LinePolytopeSpace {
  public:
    // B and L: the receiver's and the light's vertices (convex polygons).
    LinePolytopeSpace(std::span<const Vec3> receiver, std::span<const Vec3> light);
    ~LinePolytopeSpace();
    LinePolytopeSpace(const LinePolytopeSpace&) = delete;
    LinePolytopeSpace& operator=(const LinePolytopeSpace&) = delete;

    size_t generatorCount() const { return b_.size() * l_.size(); }
    // All witness lines (generators and samples).
    WitnessMask allWitnesses() const;

    // The hyperplane of lines meeting the oriented edge line (exact signs per generator).
    HyperplaneRow row(const EdgeLine& edge) const;

    // Which side of h the polytope {path} lies on. `inside` is the mask of witness lines that lie
    // in the polytope: they make most Mixed answers free of any linear program.
    // `points`, when given, receives the relaxation's points left by failed certificates.
    Side classify(std::span<const Constraint> path, const WitnessMask& inside,
                  const HyperplaneRow& h, PolytopeStats& stats,
                  RelaxationPoints* points = nullptr) const;

    // True only if it is proven that no real line lies in {path} strictly on the `side` of h.
    // `points`: what classify left for the same path and h (saves a program), or nullptr.
    bool provablyNoRealLine(std::span<const Constraint> path, const WitnessMask& inside,
                            const HyperplaneRow& h, int side, int maxLevels, PolytopeStats& stats,
                            const RelaxationPoints* points = nullptr) const;

  private:
    // Looks for a real line in {path} strictly on `side` of h (a witness, not a proof): for a few
    // points b of B (those of witness lines inside the polytope first), the lines through b that
    // satisfy every half-space form a convex part of L (the from-point query's clipping);
    // non-empty means found.
    bool findRealLine(std::span<const Constraint> path, const WitnessMask& inside,
                      const HyperplaneRow& h, int side, std::span<const Vec3> extraPoints) const;
    // Certified: min over {path} of sign * h . lambda >= 0 (the rows may be restricted to a piece).
    bool certifyNonNegative(std::span<const Constraint> path, const HyperplaneRow& h, int sign,
                            PolytopeStats& stats, std::vector<double>* witness) const;
    // True only if it is proven that no line through the piece lies in {path} strictly on
    // `side` (the relaxation of the piece, subdivided up to levelsLeft more times).
    bool provePieceEmpty(std::span<const Constraint> path, const HyperplaneRow& h, int side,
                         const PieceWeights& weights, int levelsLeft, PolytopeStats& stats) const;

    // Exact fallback of the certificate when the rounded one fails with a zero margin (touching
    // occluders make the optimum exactly zero): the multipliers are re-solved in rational
    // arithmetic on the tight generators and verified exactly.
    bool certifyExactly(std::span<const Constraint> path, const HyperplaneRow& h, int sign,
                        std::span<const double> mu) const;
    struct ExactCache;
    // A row's exact values (cached in exact_).
    const auto& exactRow(const HyperplaneRow& r) const;  // (rationals: line_polytope.cpp)
    std::unique_ptr<ExactCache> exact_;                  // exact row values, computed on demand

    std::vector<Vec3> b_, l_;
    std::vector<Vec3> probes_;                    // B's and L's vertices (sameLine's probes)
    std::vector<std::pair<Vec3, Vec3>> samples_;  // sample lines (point on B, point on L)

    // Storage of the linear programs, reused from one to the next (no allocation per program).
    // Mutable scratch like exact_: a LinePolytopeSpace belongs to one tree build on one thread.
    struct LpScratch {
        std::vector<double> mu, matrix, rhs;
        DualSimplexWorkspace workspace;
        DualSimplexResult result;
    };
    mutable LpScratch lp_;
    // Reused by findRealLine (the clipped light) and provePieceEmpty (the rows restricted to a
    // piece of B), same ownership as lp_.
    struct Scratch {
        std::vector<Vec3> poly, positive, negative;
        std::vector<HyperplaneRow> rows;
        std::vector<Constraint> sub;
        HyperplaneRow h;
        std::vector<double> piecePrimal;
    };
    mutable Scratch scratch_;
};

}  // namespace penumbra::vis
