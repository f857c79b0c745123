#include "engine/scene/scene.h"

#include <optional>

#include "engine/scene/face_uv.h"

namespace penumbra {

const Material& Scene::material(uint32_t face) const {
    static const Material kDefault{};
    const int32_t m = face < faceMaterial.size() ? faceMaterial[face] : -1;
    return m >= 0 ? materials[static_cast<size_t>(m)] : kDefault;
}

Vec3 Scene::kdAt(uint32_t face, const Vec3& x) const {
    const Material& m = material(face);
    if (!m.kdMap.present() || static_cast<size_t>(m.kdMap.image) >= textures.size()) return m.kd;
    const std::optional<Uv> uv = faceUvAt(*this, face, x);
    if (!uv) return m.kd;
    const Vec3 t = sampleTexture(textures[static_cast<size_t>(m.kdMap.image)], m.kdMap, *uv);
    return {m.kd.x * t.x, m.kd.y * t.y, m.kd.z * t.z};
}

void Scene::collectLights() {
    lights.clear();
    for (uint32_t f = 0; f < faceCount(); ++f)
        if (material(f).isEmissive()) lights.push_back(f);
}

}  // namespace penumbra
