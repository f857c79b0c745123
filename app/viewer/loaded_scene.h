// LoadedScene: a scene with what the viewer computes on it (the Embree BVH for picking and the
// VisibilityStore of history trees). Shared (std::shared_ptr) between the UI thread and the
// background tasks, so that a task still running when another scene is opened keeps its scene
// alive until it ends.
#pragma once

#include <filesystem>
#include <memory>

#include "engine/io/load_options.h"
#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"
#include "engine/render/exact_options.h"
#include "engine/scene/scene.h"

namespace penumbra::viewer {

struct LoadedScene {
    std::filesystem::path path;
    Scene scene;
    vis::Bounds3 bounds;
    std::unique_ptr<EmbreeScene> bvh;
    std::unique_ptr<VisibilityStore> store;
};

// Loads the file (engine/io/scene_loader.h: errors as SceneError; repairs as warnings in
// scene.warnings, or errors in strict mode; the default light for a scene without any, as
// `load` says) and builds the BVH and an empty store whose trees follow `exact` (the build
// budget).
std::shared_ptr<LoadedScene> loadScene(const std::filesystem::path& path, const ExactOptions& exact,
                                       const LoadOptions& load = LoadOptions::forCommands());

}  // namespace penumbra::viewer
