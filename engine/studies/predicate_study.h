// What exact predicates cost inside FPQuery: the same queries on the hard cases
// (makeHardCases()) with PredicateMode Filtered, AlwaysExact and Naive; time per query and the
// answers that differ from AlwaysExact's (the exact reference here; the test suite also checks
// Filtered against an exact CGAL reference).
// Also counted (not "wrong"): answers with another number of fragments than AlwaysExact's (a
// sliver more or less; Filtered decides rounded constructed vertices by its filter, so it may
// drop slivers that AlwaysExact's exact sign of the rounded vertex keeps).
// "Wrong" = the visible area differs from AlwaysExact's by more than 1e-9 of L's area, or the
// fragments overlap (their areas add up to more than L's) or leave L (a vertex off L's plane or
// outside one of its edges by more than 1e-9 relative).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "engine/studies/study_harness.h"

namespace penumbra {

struct PredicateModeResult {
    std::string mode;  // "filtered", "alwaysExact", "naive"
    double usPerQuery = 0, cpuUsPerQuery = 0;
    size_t wrong = 0;
    size_t otherCount = 0;  // another number of fragments than AlwaysExact
};

struct PredicateCaseResult {
    std::string name;
    size_t queries = 0;
    size_t wrong[3] = {};       // filtered, alwaysExact, naive
    size_t otherCount[3] = {};  // fragment count differs from AlwaysExact
    size_t naiveOtherThanFiltered = 0;
};

struct PredicateStudy {
    size_t queries = 0;
    int repeats = 1;
    size_t naiveOtherThanFiltered = 0;  // naive answers with another fragment count than Filtered
    PredicateModeResult modes[3];
    std::vector<PredicateCaseResult> cases;
};

// Points per penumbra patch: its vertices, its edge midpoints and random points (fixed seed) up
// to `pointsPerPatch`. Each mode's timing runs the queries `repeats` times. The totals go to
// `log` at the end.
PredicateStudy runPredicateStudy(int pointsPerPatch, int repeats, const StudyLog& log = {});

}  // namespace penumbra
