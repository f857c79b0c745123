#include "engine/scene/scene.h"

namespace penumbra {

const Material& Scene::material(uint32_t face) const {
    static const Material kDefault{};
    const int32_t m = face < faceMaterial.size() ? faceMaterial[face] : -1;
    return m >= 0 ? materials[static_cast<size_t>(m)] : kDefault;
}

void Scene::collectLights() {
    lights.clear();
    for (uint32_t f = 0; f < faceCount(); ++f)
        if (material(f).isEmissive()) lights.push_back(f);
}

}  // namespace penumbra
