#include "engine/precompute/moved_light_trees.h"

#include <algorithm>
#include <vector>

#include "engine/precompute/visibility_store.h"
#include "engine/raytrace/embree_scene.h"

namespace penumbra {

KeptTrees keepTreesPastLightMove(const VisibilityStore& before, const EmbreeScene& bvhBefore,
                                 VisibilityStore& after, const EmbreeScene& bvhAfter,
                                 std::span<const uint32_t> movedFaces) {
    KeptTrees out;
    const vis::PolygonMesh& meshBefore = before.scene().mesh;
    const vis::PolygonMesh& meshAfter = after.scene().mesh;
    if (meshBefore.faces.size() != meshAfter.faces.size()) {
        out.noneBecause = "the scenes have different faces";
        return out;
    }
    const vis::BuildOptions& a = before.options().build;
    const vis::BuildOptions& b = after.options().build;
    if (a.maxLpSolves != b.maxLpSolves || a.mergeLeaves != b.mergeLeaves ||
        a.quadricPruning != b.quadricPruning) {
        out.noneBecause = "the stores build their trees with different options";
        return out;
    }
    if (before.layout().maxPatchDiameter() != after.layout().maxPatchDiameter()) {
        out.noneBecause =
            "the light moved the scene's bounds, which every receiver's patches follow";
        return out;
    }
    const auto moved = [&](uint32_t face) {
        return std::find(movedFaces.begin(), movedFaces.end(), face) != movedFaces.end();
    };
    for (uint32_t f = 0; f < meshBefore.faces.size(); ++f) {
        if (moved(f)) continue;
        const std::vector<uint32_t>& a = meshBefore.faces[f];
        const std::vector<uint32_t>& b = meshAfter.faces[f];
        bool same = a == b;
        for (size_t i = 0; same && i < a.size(); ++i)
            same = meshBefore.vertices[a[i]] == meshAfter.vertices[b[i]];
        if (!same) {
            out.noneBecause = "face " + std::to_string(f) + "'s vertices changed with the move";
            return out;
        }
    }
    const auto vertexCount = static_cast<uint32_t>(meshAfter.vertices.size());
    before.forEach([&](const PairKey& key, const PairRecord& record) {
        if (PatchLayout::refineLevel(key) != 0 || moved(key.receiver) || moved(key.lightFace))
            return;
        const std::vector<Vec3> region = before.layout().region(key);
        for (uint32_t face : movedFaces)
            if (bvhBefore.mayCutShaft(face, region, key.lightFace) ||
                bvhAfter.mayCutShaft(face, region, key.lightFace))
                return;
        PairRecord copy = record;
        // Its vertex numbers name the same points in the moved mesh, which may hold more (a moved
        // light given vertices of its own): the count a visibility file checks is the new mesh's.
        copy.tree.meshVertexCount = vertexCount;
        if (after.insert(key, std::move(copy))) ++out.kept;
    });
    return out;
}

}  // namespace penumbra
