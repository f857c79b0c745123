// The contact rule of a from-point query: a segment from x that touches an occluder only at x is
// not blocked by it. A history tree's cells are closed sets of lines, so at a point x exactly on
// an occluder's contact with B they hold the limit of the neighbouring points instead; such a
// point (in the plane of an occluder that reaches B's plane: HistoryTree::contactPlanes), and one
// a rounding in front of B's plane next to such an occluder (nearContact), is answered from the
// pair's occluders directly.
#pragma once

#include <cstdint>
#include <vector>

#include "visibility/history_tree.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

class ContactRule {
  public:
    explicit ContactRule(QueryParts& q) : q_(q) {}

    // Whether x lies exactly in one of tree.contactPlanes.
    bool onContact(const HistoryTree& tree, const Vec3& x) const;
    // Whether x may lie strictly in front of B's plane with an inserted occluder that may meet
    // the sliver between x and B's plane that the lines from x to L cross behind x
    // (conservative: a box test against a rigorous bound of that sliver;
    // HistoryTree::contactBoxes). Prepares the pair.
    bool nearContact(const PolygonMesh& mesh, const HistoryTree& tree, const Vec3& x);
    // The candidates of a contact answer (QueryRun::candidates): the pair's occluders, inserted
    // and deferred, but those that certainly meet no segment from x to L.
    void gatherCandidates(const HistoryTree& tree);

  private:
    // nearContact's tests for a point x with b(x) at most bx.value + bx.error (B's orient3d
    // value): false only where no inserted occluder can meet the sliver; monotone in that bound.
    bool mayMeetSliver(const HistoryTree& tree, const Vec3& x, const BoundedValue& bx);

    QueryParts& q_;
    // Per vertex of L, a lower bound of B's plane's orient3d value there (for the pair of
    // generation lowGeneration_).
    std::vector<double> lightLow_;
    uint64_t lowGeneration_ = 0;
};

}  // namespace penumbra::vis
