// tbbLoops: the visibility core's ParallelLoops (visibility/parallel_loops.h) run by oneTBB
// (parallel_for over a blocked range, parallel_invoke), on the caller's task arena.
#pragma once

#include "visibility/parallel_loops.h"

namespace penumbra {

vis::ParallelLoops tbbLoops();

}  // namespace penumbra
