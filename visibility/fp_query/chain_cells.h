// The boundary chain's evaluation (boundary_chain.h): L cut by the planes through x and the
// chain's edges (chain_build.h) into cells no chain edge crosses, each kept or dropped whole by
// one certified line: its count c(y) of occluders crossed, from the last counted cell's by the
// chain edges between them (countByCrossings), else on the line (LineTests).
//
// What is exact here. c(y), the number of active occluders the line from x through y crosses, is
// constant on any open convex set of lines from x that no boundary-chain edge meets
// (boundary_chain.h). L is cut by the planes through x and the chain's edges, each only where its
// segment may meet the cell, into cells; every decision that drops an edge for a cell (the cell
// on one side of its plane, or the segment outside one of the cell's bounding planes) is recorded
// as a bounding plane of the cell or made by exact signs of input points. A cell is then decided
// by one line: a point y (the rounded centroid of its vertices, a double) is certified strictly
// inside every bounding plane of the cell by exact orient3d signs, so c(y) is the cell's value,
// and the line through y is tested exactly against each occluder (closed: a line along an edge
// that cancels still sees c >= 1 on both sides of it). Where y cannot be certified (a cell
// thinner than the rounding of its centroid), the cell is clipped by Algorithm 1 instead. A cell
// cut from one whose point did not decide it, and that holds that point (its exact signs against
// the planes on the way down, each strictly on the cell's side), takes that point and its count:
// no new point, no count (decideWholeFromRef, classify). The cells' vertices are rounded
// constructions, as the fragments of Algorithm 1 are (polygon_clip.h splitConstructed); no label
// depends on them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

class ChainCells {
  public:
    explicit ChainCells(QueryParts& q) : q_(q) {}

    void reset() {
        crossings_ = false;
        haveRef_ = false;
        crossLevel_ = kNoLevel;
    }
    // The chain's edges (indices into ChainBuild::edges()) in the order L is cut by them (the
    // list of level 0, filled by ChainBuild).
    std::vector<uint32_t>& root() {
        if (lists_.empty()) lists_.resize(1);
        return lists_[0];
    }
    // A chain of `edges` was built; `crossings`: its cells may be labelled by crossings.
    void prepare(size_t edges, bool crossings);
    // `poly` cut by the chain's edges (those in the list of `level`) into cells, each labelled;
    // the visible ones go to the run's fragments. `refInside`: the serial of the ref point when
    // it is known to lie strictly inside `poly`'s cell (0: not known).
    void cut(std::span<const Vec3> poly, size_t depth, size_t level, uint32_t refInside = 0);

  private:
    // A cell no edge left in its list cuts: labelled from the ref inside it where there is one
    // (c(ref), no test), else by its own certified point.
    void classify(std::span<const Vec3> poly, size_t depth, uint32_t refInside);
    // A cell of the chain's cutting, before it is cut further: labelled by its point y as a leaf
    // is, and decided whole where the edges left to cut it cannot change the answer (c(y) above
    // what crossing them all could take away: hidden; c(y) = 0 and none can add: seen). True:
    // decided (or the work limit reached), nothing more to cut.
    bool decideWhole(std::span<const Vec3> poly, size_t level);
    // decideWhole from the ref point, known to lie strictly inside the cell: its count and its
    // sides, no new point (a cell the ref's own try could not decide is often decided once it is
    // cut: fewer edges are left to take the count away).
    bool decideWholeFromRef(std::span<const Vec3> poly, size_t level);
    // Whether a chord (whose jump is not known) is left in the list of `level`.
    bool chordLeft(size_t level) const;
    // What crossing an edge of weight `jump` from side `s` of its plane can add to and take away
    // from c, summed into up and down; and the cell decided by them from a point counted c.
    static void addJumps(int jump, Sign s, int& down, int& up);
    bool decidedBy(std::span<const Vec3> poly, int c, int down, int up);
    // The ref point's side of chain edge idx's plane (exact; taken once per ref).
    Sign refSide(uint32_t idx);
    // Whether `serial` names the current ref (a cell's refInside).
    bool refHere(uint32_t serial) const { return haveRef_ && serial != 0 && serial == refSerial_; }
    // A cell's point y, the rounded centroid of `poly` (a cell the chain cut), and whether it is
    // certified strictly inside the cone and every bound of the cell (exact signs), so that c(y)
    // is the cell's value; with crossings, the sides of y taken on the way are kept in sideY_
    // (a new yStamp_). False also when the work limit is reached.
    bool certifiedPoint(std::span<const Vec3> poly, Vec3& y);
    // Advances yStamp_ (every cached side of the previous y becomes stale).
    void nextYStamp();
    // y, counted c(y) = count, becomes the point later cells are counted from (countByCrossings);
    // `level`: the chain level whose list (from its first edge) holds every edge that may lie
    // between y and the next cell point, or kNoLevel when the next split sets it.
    void takeRef(const Vec3& y, int count, size_t level);
    // c(y) from the last counted cell's, by the chain edges whose segments cross the triangle
    // (x, that cell's point, y). Empty where a sign is zero (the triangle touches an edge): the
    // caller then counts on the line.
    std::optional<int> countByCrossings(const Vec3& y);

    // Where cut tries decideWhole: a list of kWholeMax edges or fewer, half or less of the one
    // the last try on its path had (a try costs about as much as one more cut of the cell).
    static constexpr size_t kWholeMax = 64;
    static constexpr size_t kNoLevel = SIZE_MAX;

    QueryParts& q_;
    bool crossings_ = false;
    // Per recursion level, the chain edges that may cross the cell, and cut's scratch.
    std::vector<std::vector<uint32_t>> lists_;
    std::vector<std::vector<uint8_t>> sides_;
    std::vector<size_t> wholeTriedAt_;  // per level: the list size of the last try on its path
    // The cell's bounding planes so far (a chain edge's plane with the side the cell is on, and
    // the edge's index in the chain).
    struct Bound {
        uint32_t ref;
        Sign side;
        uint32_t edge;
    };
    std::vector<Bound> bounds_;
    // Labels by crossings: the last counted cell's point and count, and the shallowest chain
    // level (with the index of the edge that split it) passed since then: the path between the
    // two points lies in that level's cell, which only its list's edges from that index on may
    // cross.
    bool haveRef_ = false;
    // Advanced by each takeRef (never 0): a cell's refInside is valid while it names the ref.
    uint32_t refSerial_ = 0;
    Vec3 refY_;
    int refCount_ = 0;
    size_t crossLevel_ = kNoLevel, crossIndex_ = 0;
    // Per chain edge, the side of its plane the ref point lies on and the one the cell point
    // being counted lies on, each valid where its stamp is refStamp_ (yStamp_): a cell's sides
    // become the ref's when it is counted.
    std::vector<int8_t> sideRef_, sideY_;
    std::vector<uint32_t> stampRef_, stampY_;
    uint32_t refStamp_ = 0, yStamp_ = 0;
};

}  // namespace penumbra::vis
