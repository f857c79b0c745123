// LoadedScene: a scene with what the viewer computes on it (the Embree BVH for picking and the
// VisibilityStore of history trees). Shared (std::shared_ptr) between the UI thread and the
// background tasks, so that a task still running when another scene is opened keeps its scene
// alive until it ends.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

#include "engine/io/load_options.h"
#include "engine/precompute/moved_light_trees.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/exact_options.h"
#include "engine/scene/light_move.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

struct LoadedScene {
    std::filesystem::path path;
    Scene scene;
    vis::Bounds3 bounds;
    std::unique_ptr<EmbreeScene> bvh;
    std::unique_ptr<VisibilityStore> store;
    // The lights the viewer moved (engine/scene/light_move.h): each version of the scene is a new
    // LoadedScene (its own BVH and an empty store: every tree of the version before is stale), made
    // from the scene as the file gave it (`asOpened`: null until the first move, then shared by
    // every version) with one move per light from there (identity: not moved), so that dragging a
    // light never accumulates rounding. `version`: 0 as opened, one more per move. `kept`: the
    // trees of the version before that this one's store took over (those the move left true:
    // engine/precompute/moved_light_trees.h), the rest are stale.
    std::shared_ptr<const Scene> asOpened;
    std::vector<LightMove> lightMoves;
    uint64_t version = 0;
    KeptTrees kept;

    // The move of light `light` (identity when it was not moved).
    LightMove lightMove(uint32_t light) const;
    // The moved lights at their vertices, for a saved view ("moved_lights"), the default light
    // left out (its corners are saved moved).
    std::vector<PlacedLight> movedLights() const;
};

// Loads the file (engine/io/scene_loader.h: errors as SceneError; repairs as warnings in
// scene.warnings, or errors in strict mode; the default light for a scene without any, as
// `load` says) and builds the BVH and an empty store whose trees follow `exact` (the build
// budget).
std::shared_ptr<LoadedScene> loadScene(const std::filesystem::path& path, const ExactOptions& exact,
                                       const LoadOptions& load = LoadOptions::forCommands());

// The next version of `from` with its lights moved by `moves` (one per light, or fewer: the rest
// not moved), each from where the file put it: the scene, its BVH and a store (the build budget of
// `exact`) holding the trees of `from` that the lights whose move changed leave true (`kept`),
// numbered `version`. Throws SceneError for a move the contract refuses
// (light_move.h). Costs a scene copy and a BVH build: run it off the UI thread.
std::shared_ptr<LoadedScene> withLightMoves(const LoadedScene& from, std::vector<LightMove> moves,
                                            const ExactOptions& exact, uint64_t version);

}  // namespace penumbra::viewer
