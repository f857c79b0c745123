#include "engine/precompute/scene_hash.h"

#include "engine/scene/hash64.h"

namespace penumbra {

uint64_t sceneHash(const Scene& scene, const VisibilityStore::Options& options) {
    Hash64 h;
    h.addU64(0x70656E756D627261ull);  // "penumbra": a domain tag
    h.addU32(kTreeBuilderRevision);
    h.addU64(scene.mesh.vertices.size());
    for (const Vec3& v : scene.mesh.vertices) {
        h.addDouble(v.x);
        h.addDouble(v.y);
        h.addDouble(v.z);
    }
    h.addU64(scene.mesh.faces.size());
    for (const auto& face : scene.mesh.faces) {
        h.addU64(face.size());
        for (uint32_t v : face) h.addU32(v);
    }
    h.addU64(scene.lights.size());
    for (uint32_t light : scene.lights) h.addU32(light);
    h.addU32(options.build.mergeLeaves ? 1 : 0);
    h.addU32(options.build.quadricPruning ? 1 : 0);
    h.addU64(options.build.maxLpSolves);  // decides where a tree stops (partial trees)
    h.addDouble(options.patchFraction);
    return h.value();
}

}  // namespace penumbra
