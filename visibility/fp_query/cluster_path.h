// Face groups on the direct path (FromPointQuery::runDirect with face_clusters.h): a group of
// faces that x certainly sees all one way, whose box lies strictly in front of B's and L's
// planes, enters the boundary chain by its boundary instead of face by face; the cells' lines
// are tested against its faces through the face hierarchy. A cell that needs Algorithm 1
// dissolves the groups (their faces activated one by one).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/face_clusters.h"
#include "visibility/fp_query/work_budget.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

struct QueryParts;

class ClusterPath {
  public:
    // A group taken whole: its node of the face hierarchy, the group, and the side x sees it from.
    struct Used {
        uint32_t node = 0, cluster = 0;
        int side = 0;
    };

    explicit ClusterPath(QueryParts& q) : q_(q) {}

    void reset() {
        clusters_ = nullptr;
        faces_ = nullptr;
        used_.clear();
        exactSides_ = 0;
        dissolved_ = false;
        recentHits_.fill({0, 0});
        recentNext_ = 0;
    }
    // The run's candidates (QueryRun::candidates): the faces of `faces` whose box may meet the
    // pyramid, but those of the groups taken whole (used()); false when the work limit stopped
    // the walk.
    bool find(const BoxTree& faces, const FaceClusters& clusters);
    // Groups are taken whole and not dissolved.
    bool active() const { return !used_.empty() && !dissolved_; }
    // This run walked with groups (find), whether or not it took any.
    bool walked() const { return clusters_ != nullptr; }
    const FaceClusters& clusters() const { return *clusters_; }
    const BoxTree& faces() const { return *faces_; }
    const std::vector<Used>& used() const { return used_; }
    // Of the used groups, those decided by every face's exact side, not the cone test.
    uint32_t usedByExactSides() const { return exactSides_; }
    // A cell that needs Algorithm 1: every face of the used groups activated, once per run.
    void dissolve();
    // Whether the line through y (LineTests::linePlanes, set by the caller) crosses a face of the
    // used groups, the last few that hid a cell first.
    bool lineBlocked(const Vec3& y);
    // Each face of the used groups whose box is not certainly off the line held by `planes`
    // passed to visit(face, side) until it returns true (then true; also when the work limit
    // stops the walk).
    template <class Visit>
    bool facesOnLine(const std::vector<PlaneOrient>& planes, WorkBudget& budget, Visit&& visit);
    // Leaves out the used groups `out` selects (no longer used for the line walks); returns how
    // many.
    template <class Out>
    uint32_t leaveOut(Out&& out);

  private:
    struct Walk;
    bool walk(uint32_t node, const Walk& w);
    // A group whose cone test is not certain (near x, the test's usual answer) and that holds
    // kExactFacingMax faces or fewer: +1 or -1 when x lies strictly on that side of every one of
    // `faces` (exact signs), else 0. Such a group enters the chain by its boundary, as a group
    // the cone test decides, instead of activating its faces one by one.
    static constexpr size_t kExactFacingMax = 64;
    int exactFacing(std::span<const uint32_t> faces);

    QueryParts& q_;
    const FaceClusters* clusters_ = nullptr;
    const BoxTree* faces_ = nullptr;
    std::vector<Used> used_;
    bool dissolved_ = false;
    uint32_t exactSides_ = 0;
    // Per node of the face hierarchy, the run that stamped it (a used group or a node above one)
    // with the group's side (0 above one).
    std::vector<uint32_t> nodeStamp_;
    std::vector<int8_t> nodeSide_;
    uint32_t nodeRun_ = 0;
    // The last group faces that hid a cell (face, side): tried before the walk.
    static constexpr uint32_t kRecentHits = 8;
    std::array<std::pair<uint32_t, int>, kRecentHits> recentHits_{};
    uint32_t recentNext_ = 0;
};

template <class Visit>
bool ClusterPath::facesOnLine(const std::vector<PlaneOrient>& planes, WorkBudget& budget,
                              Visit&& visit) {
    // Down the stamped nodes to the used groups, and through each group's nodes, with the line's
    // planes (a face on the line is on no plane's strictly negative side).
    const BoxTree& t = *faces_;
    std::array<PlaneBoxCull, 4> cullPlanes;
    const std::span<const PlaneBoxCull> cull = t.cullPlanes(planes, cullPlanes);
    auto off = [&](const Bounds3& b) { return BoxTree::outsideOne(cull, b); };
    // Each entry: a node and the side of the group it lies in (0: above the used groups).
    std::pair<uint32_t, int> stack[160];
    int top = 0;
    if (nodeStamp_[0] == nodeRun_) stack[top++] = {0, 0};
    while (top > 0) {
        auto [node, side] = stack[--top];
        if (side == 0) {
            if (nodeStamp_[node] != nodeRun_) continue;
            side = nodeSide_[node];
        }
        if (!budget.spend()) return true;
        if (off(t.nodeBox(node))) continue;
        if (t.isLeaf(node)) {
            if (side == 0) continue;  // (a leaf above a group: cannot be)
            for (uint32_t face : t.nodeItems(node))
                if (!off(t.itemBox(face)) && visit(face, side)) return true;
            continue;
        }
        stack[top++] = {t.rightChild(node), side};
        stack[top++] = {node + 1, side};
    }
    return false;
}

template <class Out>
uint32_t ClusterPath::leaveOut(Out&& out) {
    size_t kept = 0;
    uint32_t left = 0;
    for (const Used& c : used_) {
        if (out(c)) {
            nodeStamp_[c.node] = nodeRun_ - 1;  // (no longer a used group for the line walks)
            ++left;
            continue;
        }
        used_[kept++] = c;
    }
    used_.resize(kept);
    return left;
}

}  // namespace penumbra::vis
