#include "app/viewer/loaded_scene.h"

#include "app/cli/commands.h"

namespace penumbra::viewer {

std::shared_ptr<LoadedScene> loadScene(const std::filesystem::path& path) {
    auto s = std::make_shared<LoadedScene>();
    s->path = path;
    s->scene = cli::loadSceneFile(path);
    s->bounds = s->scene.mesh.bounds();
    s->bvh = std::make_unique<EmbreeScene>(s->scene.mesh);
    s->store = std::make_unique<VisibilityStore>(s->scene, s->bvh.get());
    return s;
}

}  // namespace penumbra::viewer
