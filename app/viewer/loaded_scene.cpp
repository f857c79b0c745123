#include "app/viewer/loaded_scene.h"

#include "engine/io/scene_loader.h"

namespace penumbra::viewer {

std::shared_ptr<LoadedScene> loadScene(const std::filesystem::path& path, const ExactOptions& exact,
                                       const LoadOptions& load) {
    auto s = std::make_shared<LoadedScene>();
    s->path = path;
    s->scene = penumbra::loadScene(path, load);
    s->bounds = s->scene.fileBounds();
    s->bvh = std::make_unique<EmbreeScene>(s->scene.mesh);
    VisibilityStore::Options storeOptions;
    exact.applyTo(storeOptions);
    s->store = std::make_unique<VisibilityStore>(s->scene, s->bvh.get(), storeOptions);
    return s;
}

}  // namespace penumbra::viewer
