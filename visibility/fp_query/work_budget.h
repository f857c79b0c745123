// The work limit of a from-point query (FromPointQuery) and the stages its work is counted by:
// which stage a query was in when it reached its work limit (FromPointQuery::limitStage), counted
// by the renderer and printed in its effects summary.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace penumbra::vis {

enum class WorkStage : uint8_t {
    Walk,               // the history tree's walk
    FindOccluders,      // the occluders in the pyramid from x over L (a hierarchy query)
    ActivateOccluders,  // each clipped to the region between B and L, its planes through x
    BuildChain,         // the boundary chain: the edges that do not cancel
    CutCells,           // L cut into the chain's cells
    LabelCells,         // each cell seen or hidden
    ClipOccluders,      // Algorithm 1: L's pieces clipped occluder by occluder
};
inline constexpr size_t kWorkStages = 7;

constexpr const char* toString(WorkStage stage) {
    switch (stage) {
        case WorkStage::Walk:
            return "tree walk";
        case WorkStage::FindOccluders:
            return "finding occluders";
        case WorkStage::ActivateOccluders:
            return "activating occluders";
        case WorkStage::BuildChain:
            return "boundary chain";
        case WorkStage::CutCells:
            return "cutting cells";
        case WorkStage::LabelCells:
            return "labelling cells";
        case WorkStage::ClipOccluders:
            return "clipping occluder by occluder";
    }
    return "?";
}

// One run's work, in plane tests (a node's test, or an occluder's edge against a fragment) and
// hierarchy nodes visited, by the stage it was spent in, against a limit (0 = none). A run that
// reaches the limit stops and reports it; the caller answers the point otherwise. Counts, not
// seconds: deterministic.
class WorkBudget {
  public:
    void setLimit(uint64_t planeTests) { limit_ = planeTests; }
    uint64_t limit() const { return limit_; }
    // A new run: nothing spent, in the walk.
    void reset() {
        work_ = 0;
        stageWork_.fill(0);
        reached_ = false;
        stage_ = limitStage_ = WorkStage::Walk;
    }
    // The stage the next work is counted in.
    void enter(WorkStage stage) { stage_ = stage; }
    // Counts `tests` plane tests (or hierarchy nodes visited); false once the limit is reached
    // (the run then unwinds).
    bool spend(uint64_t tests = 1) {
        work_ += tests;
        stageWork_[static_cast<size_t>(stage_)] += tests;
        if (limit_ != 0 && work_ > limit_) {
            if (!reached_) limitStage_ = stage_;
            reached_ = true;
        }
        return !reached_;
    }
    // What is left of the limit, for a hierarchy query's own budget (0 = no limit: unbounded).
    uint64_t left() const { return limit_ == 0 ? 0 : (work_ < limit_ ? limit_ - work_ : 1); }
    bool reached() const { return reached_; }
    uint64_t work() const { return work_; }
    // The stage the run was in when it reached the limit (when reached()).
    WorkStage limitStage() const { return limitStage_; }
    // The run's work by stage (indexed by WorkStage; the sum is work()).
    const std::array<uint64_t, kWorkStages>& stageWork() const { return stageWork_; }

  private:
    uint64_t limit_ = 0, work_ = 0;
    bool reached_ = false;
    WorkStage stage_ = WorkStage::Walk, limitStage_ = WorkStage::Walk;
    std::array<uint64_t, kWorkStages> stageWork_{};
};

}  // namespace penumbra::vis
