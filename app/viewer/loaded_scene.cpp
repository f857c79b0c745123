#include "app/viewer/loaded_scene.h"

#include "engine/io/scene_loader.h"

namespace penumbra::viewer {

namespace loaded_scene_detail {

// The BVH and an empty store of s->scene.
void index(LoadedScene& s, const ExactOptions& exact) {
    s.bounds = s.scene.fileBounds();
    s.bvh = std::make_unique<EmbreeScene>(s.scene.mesh);
    VisibilityStore::Options storeOptions;
    exact.applyTo(storeOptions);
    s.store = std::make_unique<VisibilityStore>(s.scene, s.bvh.get(), storeOptions);
}

}  // namespace loaded_scene_detail

LightMove LoadedScene::lightMove(uint32_t light) const {
    return light < lightMoves.size() ? lightMoves[light] : LightMove{};
}

std::vector<PlacedLight> LoadedScene::movedLights() const {
    std::vector<PlacedLight> out;
    for (uint32_t i = 0; i < lightMoves.size() && i < scene.lights.size(); ++i) {
        const uint32_t face = scene.lights[i];
        if (lightMoves[i].isIdentity() || (scene.defaultLight && scene.defaultLight->face == face))
            continue;
        PlacedLight placed{i, {}};
        for (uint32_t v : scene.mesh.faces[face]) placed.vertices.push_back(scene.mesh.vertices[v]);
        out.push_back(std::move(placed));
    }
    return out;
}

std::shared_ptr<LoadedScene> withLightMoves(const LoadedScene& from, std::vector<LightMove> moves,
                                            const ExactOptions& exact, uint64_t version) {
    auto s = std::make_shared<LoadedScene>();
    s->path = from.path;
    s->asOpened = from.asOpened ? from.asOpened : std::make_shared<const Scene>(from.scene);
    s->scene = *s->asOpened;
    moves.resize(s->scene.lights.size());
    for (uint32_t i = 0; i < moves.size(); ++i)
        if (!moves[i].isIdentity()) moveLight(s->scene, i, moves[i]);
    std::vector<uint32_t> movedFaces;  // the lights whose move changed, before or now
    for (uint32_t i = 0; i < moves.size(); ++i)
        if (moves[i] != from.lightMove(i)) movedFaces.push_back(s->scene.lights[i]);
    s->lightMoves = std::move(moves);
    s->version = version;
    loaded_scene_detail::index(*s, exact);
    s->kept = keepTreesPastLightMove(*from.store, *from.bvh, *s->store, *s->bvh, movedFaces);
    return s;
}

std::shared_ptr<LoadedScene> loadScene(const std::filesystem::path& path, const ExactOptions& exact,
                                       const LoadOptions& load) {
    auto s = std::make_shared<LoadedScene>();
    s->path = path;
    s->scene = penumbra::loadScene(path, load);
    loaded_scene_detail::index(*s, exact);
    return s;
}

}  // namespace penumbra::viewer
