// WorkStage: the stages of a from-point query (FromPointQuery), for saying where its work went:
// which stage a query was in when it reached its work limit (FromPointQuery::limitStage), counted
// by the renderer and printed in its effects summary.
#pragma once

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

}  // namespace penumbra::vis
