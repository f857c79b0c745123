#include "engine/precompute/point_inspection.h"

#include <chrono>
#include <tuple>

#include "visibility/pair_occluders.h"

namespace penumbra {

std::vector<PathStep> pathSteps(const vis::PolygonMesh& mesh, const vis::HistoryTree& tree,
                                std::span<const vis::TraceStep> trace) {
    std::vector<PathStep> out;
    out.reserve(trace.size());
    for (const vis::TraceStep& t : trace) {
        const vis::HistoryNode& n = tree.nodes.at(t.node);
        PathStep step;
        step.node = t.node;
        step.depth = t.depth;
        step.side = t.side;
        step.v0 = n.v0;
        step.v1 = n.v1;
        std::tie(step.a, step.b) = vis::edgeSegment(mesh, tree.receiver, tree.light, n.v0, n.v1);
        if (t.node < tree.nodeOccluder.size()) step.occluderFace = tree.nodeOccluder[t.node];
        out.push_back(step);
    }
    return out;
}

PointInspection inspectPoint(VisibilityStore& store, uint32_t face, const Vec3& x) {
    const Scene& scene = store.scene();
    PointInspection out;
    out.face = face;
    out.point = x;
    out.normal = normalize(scene.mesh.faceAreaNormal(face));
    for (uint32_t k = 0; k < scene.lights.size(); ++k) {
        LightInspection li;
        const uint32_t lightFace = scene.lights[k];
        if (lightFace != face) {
            li.key = store.layout().keyAt(face, x, lightFace);
            li.treeWasBuilt = store.find(li.key) == nullptr;
        }
        const auto start = std::chrono::steady_clock::now();
        std::vector<LightAtPoint> r = queryPoint(store, face, x, k);
        li.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        li.result = std::move(r.front());
        if (lightFace != face) {
            li.tree = &store.getOrBuild(li.key).tree;  // already built by queryPoint
            li.steps = pathSteps(scene.mesh, *li.tree, li.result.trace);
        }
        out.lights.push_back(std::move(li));
    }
    return out;
}

std::optional<PointInspection> inspectPointDirect(const Scene& scene, const vis::BoxTree& faces,
                                                  uint32_t face, const Vec3& x, uint64_t workLimit,
                                                  const vis::FaceClusters* groups) {
    PointInspection out;
    out.face = face;
    out.point = x;
    out.normal = normalize(scene.mesh.faceAreaNormal(face));
    out.treesPending = true;
    for (uint32_t k = 0; k < scene.lights.size(); ++k) {
        LightInspection li;
        const auto start = std::chrono::steady_clock::now();
        std::vector<LightAtPoint> r = queryPointDirect(scene, faces, face, x, k, workLimit, groups);
        li.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (!r.front().complete) return std::nullopt;
        li.result = std::move(r.front());
        out.lights.push_back(std::move(li));
    }
    return out;
}

}  // namespace penumbra
