#include "visibility/fp_query/chain_cells.h"

#include <algorithm>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

void ChainCells::prepare(size_t edges, bool crossings) {
    crossings_ = crossings;
    if (crossings_ && sideRef_.size() < edges) {
        sideRef_.resize(edges);
        sideY_.resize(edges);
        stampRef_.resize(edges, 0);
        stampY_.resize(edges, 0);
    }
    bounds_.clear();
}

void ChainCells::cut(std::span<const Vec3> poly, size_t depth, size_t level, uint32_t refInside) {
    QueryRun& r = q_.run;
    const ChainBuild& chain = q_.chain;
    r.budget.enter(WorkStage::CutCells);
    const size_t boundsAtEntry = bounds_.size();
    if (level == 0) {  // a part of L the walk kept: any chain edge may lie between it and the last
        crossLevel_ = 0;
        crossIndex_ = 0;
    }
    if (wholeTriedAt_.size() <= level) wholeTriedAt_.resize(level + 1);
    const size_t listSize = lists_[level].size();
    wholeTriedAt_[level] = level == 0 ? SIZE_MAX : wholeTriedAt_[level - 1];
    // The ref point strictly inside this cell (refInside names it): the cell is decided from it
    // for free (no new point, no count); else from a new point where the list has halved since
    // the last try on the path. A new point that does not decide the cell becomes the ref, inside.
    uint32_t inside = refHere(refInside) ? refSerial_ : 0;
    if (crossings_ && level > 0 && listSize <= kWholeMax && listSize > 1) {
        if (inside != 0) {
            r.budget.enter(WorkStage::LabelCells);
            if (decideWholeFromRef(poly, level)) return;
        } else if (2 * listSize <= wholeTriedAt_[level]) {
            wholeTriedAt_[level] = listSize;
            const uint32_t before = refSerial_;
            if (decideWhole(poly, level)) return;
            if (refSerial_ != before) inside = refSerial_;
        }
        r.budget.enter(WorkStage::CutCells);
    }
    for (size_t i = 0; i < lists_[level].size(); ++i) {
        if (!r.budget.spend()) return;
        const ChainBuild::Edge& e = chain[lists_[level][i]];
        SplitOutcome outcome = q_.active.splitByRef(e.ref, poly, r.partsAt(depth), r.light());
        if (outcome == SplitOutcome::OnPlane) {  // a cell of zero area
            bounds_.resize(boundsAtEntry);
            return;
        }
        if (outcome != SplitOutcome::Split) {
            const Sign side = outcome == SplitOutcome::Positive ? Sign::Positive : Sign::Negative;
            bounds_.push_back({e.ref, side, lists_[level][i]});
            // The ref stays inside where it lies strictly on the cell's side of this bound.
            if (inside != 0 && refSide(lists_[level][i]) != side) inside = 0;
            if (r.budget.reached()) return;
            continue;
        }
        // Two cells: each takes the rest of the list but the edges whose segment lies on the
        // other side of this plane (closed; exact signs of the segment's input end points).
        const SplitParts& parts = r.partsAt(depth);
        const std::span<const Vec3> sides[2] = {parts.positive(), parts.negative()};
        if (lists_.size() <= level + 1) lists_.resize(level + 2);
        if (sides_.size() <= level) sides_.resize(level + 1);
        // Per remaining edge, the sides its segment reaches (bit 0: positive, bit 1: negative),
        // taken once for both cells.
        std::vector<uint8_t>& reach = sides_[level];
        reach.clear();
        const std::vector<uint32_t>& list = lists_[level];
        const bool within = q_.active.withRefPlane(e.ref, [&](const auto& plane) {
            for (size_t j = i + 1; j < list.size(); ++j) {
                const ChainBuild::Edge& f = chain[list[j]];
                uint8_t sides = 3;
                if (f.segment) {
                    if (!r.budget.spend(2)) return false;
                    const Sign sa = exactSign(plane, f.a), sb = exactSign(plane, f.b);
                    sides = static_cast<uint8_t>(
                        (sa == Sign::Positive || sb == Sign::Positive ? 1 : 0) |
                        (sa == Sign::Negative || sb == Sign::Negative ? 2 : 0));
                }
                reach.push_back(sides);
            }
            return true;
        });
        if (!within) return;
        for (int k = 0; k < 2; ++k) {
            const Sign side = k == 0 ? Sign::Positive : Sign::Negative;
            std::vector<uint32_t>& next = lists_[level + 1];
            next.clear();
            for (size_t j = i + 1; j < lists_[level].size(); ++j)
                if ((sides_[level][j - i - 1] & (1 << k)) != 0) next.push_back(lists_[level][j]);
            if (k == 1 && (crossLevel_ == kNoLevel || level < crossLevel_)) {
                // The next cell is on the other side of this split from the last counted one.
                crossLevel_ = level;
                crossIndex_ = i;
            }
            bounds_.push_back({e.ref, side, lists_[level][i]});
            // (A ref taken in the positive cell is not in the negative one.)
            const uint32_t childInside =
                refHere(inside) && refSide(lists_[level][i]) == side ? inside : 0;
            if (r.budget.reached()) return;
            cut(sides[k], depth + 1, level + 1, childInside);
            bounds_.pop_back();
            if (r.budget.reached()) return;
        }
        bounds_.resize(boundsAtEntry);
        return;
    }
    classify(poly, depth, inside);
    bounds_.resize(boundsAtEntry);
}

void ChainCells::classify(std::span<const Vec3> poly, size_t depth, uint32_t refInside) {
    QueryRun& r = q_.run;
    ChainCounts& counts = q_.chain.counts();
    r.budget.enter(WorkStage::LabelCells);
    ++counts.cells;
    if (poly.size() < 3) return;
    if (refHere(refInside)) {  // c is constant on the open cell, and the ref lies in it
        ++counts.refLabels;
        if (refCount_ == 0) r.fragments.add(poly);
        return;
    }
    Vec3 y;
    const bool certified = certifiedPoint(poly, y);
    if (r.budget.reached()) return;
    if (!certified) {
        ++counts.fallbacks;
        if (q_.silhouettes.active()) q_.silhouettes.activateRest();
        if (q_.clusters.active()) q_.clusters.dissolve();
        if (q_.edges.active()) q_.edges.activateNear(poly);
        if (r.budget.reached()) return;
        q_.clip.clip(poly, depth);
        return;
    }
    if (crossings_) {
        // c(y) from the last counted cell's, else from the line; the cell is seen where it is 0.
        std::optional<int> c;
        if (haveRef_) {
            c = countByCrossings(y);
            if (c) ++counts.crossingLabels;
        }
        if (!c && !r.budget.reached()) c = q_.lines.countLine(y);
        if (r.budget.reached()) return;
        if (c && *c >= 0) {
            takeRef(y, *c, kNoLevel);
            if (*c == 0) r.fragments.add(poly);
            return;
        }
        haveRef_ = false;  // (a negative count cannot be: tested on the line instead)
    }
    if (q_.lines.lineBlocked(y) || r.budget.reached()) return;
    r.fragments.add(poly);
}

bool ChainCells::certifiedPoint(std::span<const Vec3> poly, Vec3& y) {
    QueryRun& r = q_.run;
    y = Vec3{};
    for (const Vec3& v : poly) y += v;
    y = y / static_cast<double>(poly.size());
    bool certified = true;
    for (const PlaneOrient& h : r.cone()) {
        if (!r.budget.spend()) return false;
        if (exactSign(h, y) != Sign::Positive) certified = false;
    }
    if (certified && q_.chain.chordsOnBLeftOut()) {
        if (!r.budget.spend()) return false;
        certified = r.pair.frontB().orient.sign(y) == Sign::Positive;
    }
    if (crossings_) nextYStamp();
    for (size_t k = 0; certified && k < bounds_.size(); ++k) {
        if (!r.budget.spend()) return false;
        const Sign s = q_.active.refSign(bounds_[k].ref, y);
        certified = s == bounds_[k].side;
        if (crossings_) {  // the side of y the crossings count needs too (countByCrossings)
            sideY_[bounds_[k].edge] = static_cast<int8_t>(s);
            stampY_[bounds_[k].edge] = yStamp_;
        }
    }
    return certified;
}

void ChainCells::takeRef(const Vec3& y, int count, size_t level) {
    haveRef_ = true;
    if (++refSerial_ == 0) refSerial_ = 1;  // (0 names no ref)
    refY_ = y;
    refCount_ = count;
    // The chain edges' sides taken at y are now the ref's.
    std::swap(sideRef_, sideY_);
    std::swap(stampRef_, stampY_);
    refStamp_ = yStamp_;
    crossLevel_ = level;
    crossIndex_ = 0;
}

void ChainCells::nextYStamp() {
    if (++yStamp_ == 0) {  // wrapped: no stale stamp may match
        std::fill(stampRef_.begin(), stampRef_.end(), 0);
        std::fill(stampY_.begin(), stampY_.end(), 0);
        yStamp_ = 1;
    }
}

Sign ChainCells::refSide(uint32_t idx) {
    if (stampRef_[idx] != refStamp_) {  // (not taken yet at the ref: one plane test)
        q_.run.budget.spend();
        sideRef_[idx] = static_cast<int8_t>(q_.active.refSign(q_.chain[idx].ref, refY_));
        stampRef_[idx] = refStamp_;
    }
    return static_cast<Sign>(sideRef_[idx]);
}

bool ChainCells::decideWholeFromRef(std::span<const Vec3> poly, size_t level) {
    // decideWhole's bounds from the ref point, which lies strictly inside this cell (the cell's
    // bounds and the cone, by exact signs taken when it was certified in a cell holding this
    // one and on the way down to it), with its count: no new point, no count, and its sides
    // mostly taken already.
    if (poly.size() < 3) return false;
    const ChainBuild& chain = q_.chain;
    if (chordLeft(level)) return false;
    int down = 0, up = 0;
    for (uint32_t idx : lists_[level]) {
        const Sign s = refSide(idx);
        if (q_.run.budget.reached()) return true;
        addJumps(chain[idx].jump, s, down, up);
    }
    // The path from the ref to any later cell point inside this cell lies in it.
    crossLevel_ = level;
    crossIndex_ = 0;
    return decidedBy(poly, refCount_, down, up);
}

bool ChainCells::chordLeft(size_t level) const {
    const ChainBuild& chain = q_.chain;
    if (!chain.hasChords()) return false;
    for (uint32_t idx : lists_[level])
        if (!chain[idx].segment) return true;
    return false;
}

void ChainCells::addJumps(int jump, Sign s, int& down, int& up) {
    const int toNegative = jump, toPositive = -jump;
    if (s != Sign::Negative) {  // may leave the positive side (or the plane)
        down += std::max(0, -toNegative);
        up += std::max(0, toNegative);
    }
    if (s != Sign::Positive) {
        down += std::max(0, -toPositive);
        up += std::max(0, toPositive);
    }
}

bool ChainCells::decidedBy(std::span<const Vec3> poly, int c, int down, int up) {
    if (c > down) {
        ++q_.chain.counts().cells;
        ++q_.chain.counts().hiddenWhole;
        return true;
    }
    if (c == 0 && up == 0) {
        ++q_.chain.counts().cells;
        ++q_.chain.counts().seenWhole;
        q_.run.fragments.add(poly);
        return true;
    }
    return false;
}

bool ChainCells::decideWhole(std::span<const Vec3> poly, size_t level) {
    QueryRun& r = q_.run;
    const ChainBuild& chain = q_.chain;
    // Exact, with crossings_ (c changes only across the chain's segments, by their weights):
    // every point z of the open cell is reached from y along the segment y -> z inside the
    // (convex) cell, which crosses each chain segment at most once, and only those left in this
    // level's list can meet the cell (the others were put on one side of a plane bounding it).
    // Leaving y's side of an edge's plane changes c by +jump from its positive side and -jump
    // from its negative side; so c(z) lies between c(y) - down and c(y) + up, the sums of the
    // decreases and increases the list's edges could bring (an edge whose plane holds y counts
    // both ways). c >= 1 on the whole cell when c(y) > down; c = 0 on it when c(y) = 0 and
    // up = 0 (c is never negative). y is certified as a leaf's point is; the sides are exact.
    r.budget.enter(WorkStage::LabelCells);
    if (poly.size() < 3) return false;
    if (chordLeft(level)) return false;  // it may cut the cell: its jump is not known
    Vec3 y;
    const bool certified = certifiedPoint(poly, y);
    if (r.budget.reached()) return true;
    if (!certified) return false;
    std::optional<int> c;
    if (haveRef_) c = countByCrossings(y);
    if (!c && !r.budget.reached()) c = q_.lines.countLine(y);
    if (r.budget.reached()) return true;
    if (!c || *c < 0) return false;
    int down = 0, up = 0;
    for (uint32_t idx : lists_[level]) {
        const ChainBuild::Edge& e = chain[idx];
        Sign s;
        if (stampY_[idx] == yStamp_) {
            s = static_cast<Sign>(sideY_[idx]);
        } else {
            if (!r.budget.spend()) return true;
            s = q_.active.refSign(e.ref, y);
            sideY_[idx] = static_cast<int8_t>(s);
            stampY_[idx] = yStamp_;
        }
        addJumps(e.jump, s, down, up);
    }
    // y is the ref from now on; the path from it to any later cell point inside this cell lies
    // in this cell, which only this level's list may cross.
    takeRef(y, *c, level);
    return decidedBy(poly, *c, down, up);
}

std::optional<int> ChainCells::countByCrossings(const Vec3& y) {
    QueryRun& r = q_.run;
    const Vec3& x = r.x;
    const PlaneOrient& frontB = r.pair.frontB().orient;
    // As y moves to y' along the segment between them (inside L), the line from x sweeps the
    // triangle (x, y, y'), and c changes by an edge's weight exactly where the triangle's
    // interior meets the edge's segment (an edge of weight 0 changes nothing; the chain holds
    // every edge of nonzero weight that may meet the cone over L). Exact: orient3d signs at the
    // input end points, x, and the two sample points; any zero where it could matter (the
    // triangle touches an edge, or an end point lies in its plane) gives up.
    if (crossLevel_ == kNoLevel) return std::nullopt;
    int c = refCount_;
    const std::vector<uint32_t>& list = lists_[crossLevel_];
    // Whether the triangle (x, ref, y) lies in the closed half-space in front of B's plane
    // (exact signs; asked only when an edge cut by that plane crosses it: 0 = not yet known).
    int triangleInFront = 0;
    // The triangle's plane, formed at the first edge whose plane separates the two points.
    PlaneOrient triangle;
    bool haveTriangle = false;
    for (size_t j = crossIndex_; j < list.size(); ++j) {
        const ChainBuild::Edge& e = q_.chain[list[j]];
        const uint32_t idx = list[j];
        Sign s0;
        if (stampRef_[idx] == refStamp_) {
            s0 = static_cast<Sign>(sideRef_[idx]);
        } else {
            if (!r.budget.spend()) return std::nullopt;
            s0 = q_.active.refSign(e.ref, refY_);
        }
        Sign s1;
        if (stampY_[idx] == yStamp_) {  // a bound of y's cell: taken when it was certified
            s1 = static_cast<Sign>(sideY_[idx]);
        } else {
            if (!r.budget.spend()) return std::nullopt;
            s1 = q_.active.refSign(e.ref, y);
            sideY_[idx] = static_cast<int8_t>(s1);  // the ref's own side if y becomes the ref
            stampY_[idx] = yStamp_;
        }
        if (s0 == s1 && s0 != Sign::Zero) continue;  // both strictly on one side of its plane
        // A chord's plane between them: the path may cross the chord, by an unknown jump.
        if (!e.segment) return std::nullopt;
        // (Counted as the five signs the test decides, two of them known already: s0 and s1.)
        if (!r.budget.spend(5)) return std::nullopt;
        if (!haveTriangle) {
            triangle = PlaneOrient(x, refY_, y);
            haveTriangle = true;
        }
        const Sign qa = exactSign(triangle, e.a), qb = exactSign(triangle, e.b);
        if (qa == qb && qa != Sign::Zero) continue;  // the segment misses the triangle's plane
        if (qa == Sign::Zero || qb == Sign::Zero) return std::nullopt;
        // The segment's line against the triangle's three sides: orient3d(a, b, x, ref) and
        // orient3d(a, b, y, x) are the edge's plane (x, a, b) at the ref and at y, an even and
        // an odd permutation of it: s0 and -s1, exactly.
        const Sign t0 = s0, t1 = orientSign(e.a, e.b, refY_, y), t2 = -s1;
        if ((t0 == -t1 && t0 != Sign::Zero) || (t1 == -t2 && t1 != Sign::Zero) ||
            (t2 == -t0 && t2 != Sign::Zero))
            continue;  // it passes beside the triangle
        if (t0 == Sign::Zero || t1 == Sign::Zero || t2 == Sign::Zero) return std::nullopt;
        // Through the interior: then y and y' are strictly on either side of the edge's plane.
        if (s0 == Sign::Zero || s1 == Sign::Zero || s0 == s1) return std::nullopt;
        // An edge cut by B's plane bounds its occluder only in front of that plane: the crossing
        // counts where the triangle lies there (x, the ref and y on its closed front side: a
        // rendered x is often a rounding behind it), else the line decides.
        if (e.behindB) {
            if (triangleInFront == 0) {
                if (!r.budget.spend(3)) return std::nullopt;
                const bool front = frontB.sign(x) != Sign::Negative &&
                                   frontB.sign(refY_) != Sign::Negative &&
                                   frontB.sign(y) != Sign::Negative;
                triangleInFront = front ? 1 : -1;
            }
            if (triangleInFront < 0) return std::nullopt;
        }
        c += s0 == Sign::Positive ? e.jump : -e.jump;
    }
    return c;
}

}  // namespace penumbra::vis
