#include "engine/scene/scene.h"

#include <optional>

#include "engine/scene/face_uv.h"

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
