#include "visibility/history_tree_builder.h"

#include <chrono>
#include <deque>

#include "visibility/clipped_occluder.h"
#include "visibility/line_polytope.h"
#include "visibility/pair_occluders.h"

namespace penumbra::vis {
namespace {

// Where a leaf hangs: a child slot of a node, or the root.
struct Slot {
    uint32_t node = UINT32_MAX;  // UINT32_MAX = the root slot
    int child = 0;
};

// Thrown inside the builder when BuildOptions::maxLpSolves is reached; caught below.
struct BudgetExceeded {};

class Builder {
  public:
    Builder(const PolygonMesh& mesh, uint32_t receiverFace, std::span<const Vec3> receiver,
            uint32_t light, const BuildOptions& options, BuildStats& stats)
        : mesh_(mesh),
          options_(options),
          stats_(stats),
          space_(receiver, polygon(mesh, light)),
          receiverPoints_(receiver.begin(), receiver.end()),
          lightPoints_(polygon(mesh, light)),
          receiverFace_(receiverFace),
          light_(light),
          receiverPlane_(facePlane(mesh, receiverFace).orient()),
          lightPlane_(facePlane(mesh, light).orient()) {}

    void insert(const Occluder& o) {
        edgeRows_.clear();
        edges_.clear();
        for (const auto& [a, b] : o.edges) {
            rowStore_.push_back(space_.row(edgeLine(mesh_, receiverFace_, light_, a, b)));
            edgeRows_.push_back(&rowStore_.back());
            edges_.push_back({a, b});
        }
        occluder_ = &o;
        // Its exact clip again (the gathering kept only the edges): the symbolic vertices of
        // occluderSideOf's cone culling.
        clip_.clip(mesh_, o.face, receiverPlane_, lightPlane_);
        walk(Slot{}, space_.allWitnesses());
        ++stats_.occludersInserted;
    }

    uint32_t root() const { return root_; }

    // Reachable nodes in depth-first order, root first.
    void emit(HistoryTree& tree) const {
        if (isLeaf(root_)) return;
        std::vector<uint32_t> order, remap(nodes_.size(), UINT32_MAX);
        std::vector<uint32_t> stack{root_};
        while (!stack.empty()) {
            const uint32_t n = stack.back();
            stack.pop_back();
            remap[n] = static_cast<uint32_t>(order.size());
            order.push_back(n);
            for (int c = 1; c >= 0; --c)
                if (!isLeaf(nodes_[n].child[c])) stack.push_back(nodes_[n].child[c]);
        }
        tree.nodes.resize(order.size());
        tree.nodeOccluder.resize(order.size());
        for (size_t i = 0; i < order.size(); ++i) {
            HistoryNode node = nodes_[order[i]];
            for (uint32_t& c : node.child)
                if (!isLeaf(c)) c = remap[c];
            tree.nodes[i] = node;
            tree.nodeOccluder[i] = nodeOccluder_[order[i]];
        }
    }

  private:
    static std::vector<Vec3> polygon(const PolygonMesh& mesh, uint32_t f) {
        std::vector<Vec3> p;
        for (uint32_t v : mesh.faces[f]) p.push_back(mesh.vertices[v]);
        return p;
    }
    uint32_t get(Slot s) const {
        return s.node == UINT32_MAX ? root_ : nodes_[s.node].child[s.child];
    }
    void set(Slot s, uint32_t v) {
        if (s.node == UINT32_MAX)
            root_ = v;
        else
            nodes_[s.node].child[s.child] = v;
    }

    // Walk the tree with the path of half-spaces; process every visible leaf.
    void walk(Slot s, const WitnessMask& inside) {
        const uint32_t v = get(s);
        if (v == kHiddenLeaf) return;
        if (v == kVisibleLeaf) {
            processLeaf(s, inside);
            return;
        }
        const HyperplaneRow* row = nodeRow_[v];
        // Line-space shaft culling: when every line meeting B (or L) and the occluder lies on one
        // closed side of this node's hyperplane, the other subtree holds no line the occluder can
        // block (its lines are strictly on the other side) and is not visited.
        const Sign occluderSide = occluderSideOf(row->edge);
        path_.push_back({row, +1});
        if (occluderSide != Sign::Negative) walk(Slot{v, 0}, inside & row->certainNonNegative);
        path_.back().sign = -1;
        if (occluderSide != Sign::Positive) walk(Slot{v, 1}, inside & row->certainNonPositive);
        path_.pop_back();
        mergeIfSameLeaves(s);
    }

    // Positive / Negative when all lines from B to the occluder, or all lines from the occluder
    // to L, lie on that closed side of edge (v0, v1)'s hyperplane (they span cones that contain
    // every line stabbing B, the occluder and L); Zero when neither is certain. Exact signs.
    Sign occluderSideOf(const EdgeLine& edge) const {
        // Over the clipped occluder's symbolic vertices (clipped_occluder.h lineSide): a side the
        // filter cannot certify gives up the culling for this edge (Zero), which only costs work.
        const ClippedOccluder& clip = clip_;
        auto coneSide = [&](std::span<const Vec3> points, bool fromPoints) {
            bool pos = true, neg = true;
            for (const Vec3& p : points)
                for (const ClippedOccluder::Vertex& v : clip.vertices()) {
                    const std::optional<Sign> s = clip.lineSide(v, p, fromPoints, edge);
                    if (!s) return Sign::Zero;
                    pos &= *s != Sign::Negative;
                    neg &= *s != Sign::Positive;
                    if (!pos && !neg) return Sign::Zero;
                }
            return pos ? Sign::Positive : (neg ? Sign::Negative : Sign::Zero);
        };
        const Sign fromB = coneSide(receiverPoints_, true);
        if (fromB != Sign::Zero) return fromB;
        return coneSide(lightPoints_, false);
    }

    void mergeIfSameLeaves(Slot s) {
        if (!options_.mergeLeaves) return;
        const uint32_t v = get(s);
        if (isLeaf(v)) return;
        const HistoryNode& n = nodes_[v];
        if (isLeaf(n.child[0]) && n.child[0] == n.child[1]) {
            set(s, n.child[0]);
            ++stats_.mergedLeaves;
        }
    }

    Side classify(const WitnessMask& inside, const HyperplaneRow& row) {
        ++stats_.classifications;
        Side c = space_.classify(path_, inside, row, polyStats_, &relaxation_);
        if (c == Side::Mixed && options_.quadricPruning) {
            const uint64_t lpsBefore = polyStats_.lpSolves;
            const auto t0 = std::chrono::steady_clock::now();
            struct Count {
                BuildStats& stats;
                uint64_t before;
                const PolytopeStats& poly;
                std::chrono::steady_clock::time_point t0;
                ~Count() {
                    stats.realLineLpSolves += poly.lpSolves - before;
                    stats.realLineSeconds +=
                        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
                            .count();
                }
            } count{stats_, lpsBefore, polyStats_, t0};
            if (space_.provablyNoRealLine(path_, inside, row, -1, kPruneLevels, polyStats_,
                                          &relaxation_)) {
                ++stats_.prunedSplits;
                c = Side::Positive;
            } else if (space_.provablyNoRealLine(path_, inside, row, +1, kPruneLevels, polyStats_,
                                                 &relaxation_)) {
                ++stats_.prunedSplits;
                c = Side::Negative;
            }
        }
        return c;
    }

    // Algorithm 1 for one visible leaf and the current occluder. A line is blocked iff it lies on
    // the same strict side (blockedSign, or either when 0) of every edge hyperplane.
    void processLeaf(Slot s, const WitnessMask& inside) {
        if (options_.cancel != nullptr && options_.cancel->load(std::memory_order_relaxed))
            throw BuildCancelled();
        if (options_.maxLpSolves != 0 && polyStats_.lpSolves > options_.maxLpSolves)
            throw BudgetExceeded{};
        const size_t k = edgeRows_.size();
        std::vector<Side> cls(k);
        bool anyPos = false, anyNeg = false;
        for (size_t i = 0; i < k; ++i) {
            cls[i] = classify(inside, *edgeRows_[i]);
            anyPos |= cls[i] == Side::Positive;
            anyNeg |= cls[i] == Side::Negative;
            // Entirely on the unblocked side of one edge: the occluder touches none of its lines.
            const int b = occluder_->blockedSign;
            if ((b > 0 && anyNeg) || (b < 0 && anyPos) || (b == 0 && anyPos && anyNeg)) return;
        }
        const size_t nodesBefore = nodes_.size();
        if (!splitChain(s, inside, 0, occluder_->blockedSign, cls, false) && options_.mergeLeaves) {
            // The occluder blocks no line of this leaf after all (an edge found further down the
            // chain leaves the blocked part empty): every node the chain made has only visible
            // leaves below it. They are the last ones made: drop them, the leaf stays visible.
            set(s, kVisibleLeaf);
            nodes_.resize(nodesBefore);
            nodeRow_.resize(nodesBefore);
            nodeOccluder_.resize(nodesBefore);
            ++stats_.mergedLeaves;
        }
    }

    // Splits the leaf at s by the occluder's edges from `start` on and labels the blocked part
    // hidden. Returns whether it made a hidden leaf. With leaf merging, a part of the chain that
    // blocks nothing is collapsed back to one visible leaf (the paper's sibling merge, applied to
    // the whole all-visible subtree at once).
    bool splitChain(Slot s, WitnessMask inside, size_t start, int sign, std::vector<Side> cls,
                    bool shrunk) {
        size_t pushed = 0;
        const Slot first = s;
        for (size_t i = start; i < cls.size(); ++i) {
            Side c = cls[i];
            if (c == Side::Mixed && shrunk) c = classify(inside, *edgeRows_[i]);
            const HyperplaneRow* row = edgeRows_[i];
            if (sign == 0) {
                if (c != Side::Mixed) {
                    sign = c == Side::Positive ? +1 : -1;
                    continue;
                }
                const uint32_t n = newNode(i);
                set(s, n);
                path_.push_back({row, +1});
                const bool pos =
                    splitChain(Slot{n, 0}, inside & row->certainNonNegative, i + 1, +1, cls, true);
                path_.back().sign = -1;
                const bool neg =
                    splitChain(Slot{n, 1}, inside & row->certainNonPositive, i + 1, -1, cls, true);
                path_.pop_back();
                for (; pushed > 0; --pushed) path_.pop_back();
                if (options_.mergeLeaves) {
                    if (!pos) nodes_[n].child[0] = kVisibleLeaf;
                    if (!neg) nodes_[n].child[1] = kVisibleLeaf;
                    if (!pos && !neg) set(first, kVisibleLeaf);
                }
                return pos || neg;
            }
            if (toInt(static_cast<Sign>(c)) == -sign) {  // this part is untouched
                for (; pushed > 0; --pushed) path_.pop_back();
                if (options_.mergeLeaves) set(first, kVisibleLeaf);
                return false;
            }
            if (c != Side::Mixed) continue;  // already on the blocked side of this edge
            const uint32_t n = newNode(i);
            set(s, n);
            s = Slot{n, sign > 0 ? 0 : 1};  // the other child stays a visible leaf
            path_.push_back({row, sign});
            ++pushed;
            inside &= sign > 0 ? row->certainNonNegative : row->certainNonPositive;
            shrunk = true;
        }
        set(s, kHiddenLeaf);
        for (; pushed > 0; --pushed) path_.pop_back();
        return true;
    }

    uint32_t newNode(size_t edge) {
        HistoryNode node;
        node.v0 = edges_[edge].first;
        node.v1 = edges_[edge].second;
        nodes_.push_back(node);
        nodeRow_.push_back(edgeRows_[edge]);
        nodeOccluder_.push_back(occluder_->face);
        return static_cast<uint32_t>(nodes_.size() - 1);
    }

    static constexpr int kPruneLevels = 3;

    const PolygonMesh& mesh_;
    const BuildOptions& options_;
    BuildStats& stats_;
    LinePolytopeSpace space_;
    std::vector<Vec3> receiverPoints_, lightPoints_;
    uint32_t receiverFace_, light_;
    PlaneOrient receiverPlane_, lightPlane_;
    ClippedOccluder clip_;  // of the occluder being inserted
    PolytopeStats polyStats_;
    RelaxationPoints relaxation_;  // what the last classification left for the real-line tests

    uint32_t root_ = kVisibleLeaf;
    std::vector<HistoryNode> nodes_;
    std::vector<const HyperplaneRow*> nodeRow_;
    std::vector<uint32_t> nodeOccluder_;
    std::deque<HyperplaneRow> rowStore_;  // stable addresses

    const Occluder* occluder_ = nullptr;
    std::vector<const HyperplaneRow*> edgeRows_;
    std::vector<std::pair<uint32_t, uint32_t>> edges_;
    std::vector<Constraint> path_;

  public:
    const PolytopeStats& polytopeStats() const { return polyStats_; }
};

}  // namespace

HistoryTree buildHistoryTree(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                             const BuildOptions& options, std::span<const uint32_t> candidates,
                             BuildStats* statsOut, std::span<const Vec3> receiverPatch) {
    const auto t0 = std::chrono::steady_clock::now();
    BuildStats stats;
    HistoryTree tree;
    tree.receiver = receiver;
    tree.light = light;
    tree.meshVertexCount = static_cast<uint32_t>(mesh.vertices.size());
    std::vector<Vec3> region(receiverPatch.begin(), receiverPatch.end());
    if (region.empty())
        for (uint32_t v : mesh.faces[receiver]) region.push_back(mesh.vertices[v]);
    const PairOccluders occ = gatherOccluders(mesh, receiver, light, candidates, region);
    if (occ.backFacing) {
        tree.kind = PairKind::BackFacing;
        tree.why = reasons::kBackFacing;
    } else if (occ.occluders.empty()) {
        tree.kind = PairKind::FullyVisible;
        tree.why = reasons::kNoOccluder;
    } else {
        stats.occludersInShaft = static_cast<uint32_t>(occ.occluders.size());
        Builder builder(mesh, receiver, region, light, options, stats);
        size_t inserting = 0;
        try {
            for (; inserting < occ.occluders.size(); ++inserting) {
                // Recorded first: an occluder the budget interrupts has nodes too (and is also
                // deferred), and the contact rule must know it.
                tree.occluders.push_back(occ.occluders[inserting].face);
                builder.insert(occ.occluders[inserting]);
                if (builder.root() == kHiddenLeaf) break;
            }
        } catch (const BudgetExceeded&) {
            // The budget stopped the insertion of occluder `inserting` between two leaves: the
            // leaves it has processed are right for it, the others not yet. Deferring it with the
            // rest is exact: the query clips every visible fragment against it again, which
            // changes nothing where it has already been accounted for.
            stats.budgetExceeded = true;
        }
        stats.lpSolves = builder.polytopeStats().lpSolves;
        stats.uncertain = builder.polytopeStats().uncertain;
        stats.realLineTests = builder.polytopeStats().realLineTests;
        stats.realLineWitness = builder.polytopeStats().realLineWitness;
        stats.exactCertificates = builder.polytopeStats().exactCertificates;
        if (stats.budgetExceeded && builder.root() != kHiddenLeaf)
            for (size_t i = inserting; i < occ.occluders.size(); ++i)
                tree.deferred.push_back({occ.occluders[i].face, {}});
        stats.occludersDeferred = static_cast<uint32_t>(tree.deferred.size());
        if (tree.partial()) {
            tree.kind = PairKind::Penumbra;
            tree.why = reasons::kPartial;
            builder.emit(tree);  // (no node when the budget ran out on the first occluder)
        } else if (builder.root() == kVisibleLeaf) {
            tree.kind = PairKind::FullyVisible;
            tree.why = reasons::kBlockNothing;
        } else if (builder.root() == kHiddenLeaf) {
            tree.kind = PairKind::FullyHidden;
            tree.why = stats.occludersInserted == 1 ? reasons::kSingleBlocksAll
                                                    : reasons::kTogetherBlockAll;
        } else {
            tree.kind = PairKind::Penumbra;
            tree.why = reasons::kPenumbra;
            builder.emit(tree);
        }
        prepareForQueries(mesh, tree, receiverPatch);
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (statsOut) *statsOut = stats;
    return tree;
}

}  // namespace penumbra::vis
