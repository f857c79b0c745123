// The content hash that ties precomputed history trees to the scene and the settings that shaped
// them: a visibility file made for another scene, or with other build options or patch size, is
// stale and must be recomputed. In engine/precompute/ beside VisibilityStore, whose options it
// hashes (the scene room below knows nothing of the precompute).
#pragma once

#include <cstdint>

#include "engine/precompute/visibility_store.h"
#include "engine/scene/scene.h"

namespace penumbra {

// Bump when the history-tree builder changes the trees it makes for the same input (files made by
// an older builder then read as stale).
// 2: build budget. 3: hull culling, shadow order, collapsed chains, partial trees.
inline constexpr uint32_t kTreeBuilderRevision = 3;

// 64-bit hash (engine/scene/hash64.h) over: the vertices (bit patterns of the doubles, so any
// change, even one ulp, changes it), the faces (vertex counts and indices), which faces are lights
// (in order), the build options that change trees (mergeLeaves, quadricPruning, maxLpSolves), the
// patch fraction (bit pattern) and kTreeBuilderRevision. Materials, names, the camera and point
// lights do not shape the trees and are left out.
uint64_t sceneHash(const Scene& scene, const VisibilityStore::Options& options);

}  // namespace penumbra
