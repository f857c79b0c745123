#include "engine/scene/scene.h"

namespace penumbra {

const Material& Scene::material(uint32_t face) const {
    static const Material kDefault{};
    const int32_t m = face < faceMaterial.size() ? faceMaterial[face] : -1;
    return m >= 0 ? materials[static_cast<size_t>(m)] : kDefault;
}

vis::Bounds3 Scene::fileBounds() const {
    if (!defaultLight) return mesh.bounds();
    vis::Bounds3 b;
    for (uint32_t v = 0; v < defaultLight->firstVertex; ++v) b.add(mesh.vertices[v]);
    return b;
}

std::vector<std::string> Scene::loadNotices() const {
    std::vector<std::string> out;
    if (defaultLight) out.push_back(defaultLight->announcement(sourcePath));
    out.insert(out.end(), warnings.begin(), warnings.end());
    return out;
}

void Scene::collectLights() {
    lights.clear();
    for (uint32_t f = 0; f < faceCount(); ++f)
        if (material(f).isEmissive()) lights.push_back(f);
}

}  // namespace penumbra
