#include "app/viewer/point_inspection.h"

#include <chrono>
#include <tuple>

#include "visibility/pair_occluders.h"
#include "visibility/polygon_clip.h"

namespace penumbra::viewer {
namespace {

struct SideWalker {
    const vis::PolygonMesh& mesh;
    const vis::HistoryTree& tree;
    const Vec3& x;
    std::vector<PathStep>& out;

    void visit(uint32_t node, const std::vector<Vec3>& poly, uint32_t depth) {
        if (vis::isLeaf(node)) return;
        const vis::HistoryNode& n = tree.nodes[node];
        PathStep step;
        step.node = node;
        step.depth = depth;
        step.v0 = n.v0;
        step.v1 = n.v1;
        std::tie(step.a, step.b) = vis::edgeSegment(mesh, tree.receiver, tree.light, n.v0, n.v1);
        if (node < tree.nodeOccluder.size()) step.occluderFace = tree.nodeOccluder[node];
        const size_t index = out.size();
        out.push_back(step);
        std::vector<Vec3> pos, neg;
        vis::clipConvexInto(poly, vis::EdgePlane(x, tree.edgeLine(mesh, n)), pos, neg);
        if (pos.empty() && neg.empty()) {
            out[index].side = PathSide::InPlane;
            visit(n.child[0], poly, depth + 1);
            return;
        }
        out[index].side = !pos.empty() && !neg.empty() ? PathSide::Both
                          : !pos.empty()               ? PathSide::Positive
                                                       : PathSide::Negative;
        if (!pos.empty()) visit(n.child[0], pos, depth + 1);
        if (!neg.empty()) visit(n.child[1], neg, depth + 1);
    }
};

}  // namespace

const char* toString(PathSide side) {
    switch (side) {
        case PathSide::Positive:
            return "+";
        case PathSide::Negative:
            return "-";
        case PathSide::Both:
            return "both";
        case PathSide::InPlane:
            return "in plane (+)";
    }
    return "?";
}

std::vector<PathStep> pathSteps(const vis::PolygonMesh& mesh, const vis::HistoryTree& tree,
                                const Vec3& x) {
    std::vector<PathStep> out;
    if (tree.kind != vis::PairKind::Penumbra || tree.nodes.empty()) return out;
    // The same preconditions as fromPointQuery: x strictly in front of the light, the light
    // clipped to the receiver's front half-space.
    if (vis::facePlane(mesh, tree.light).side(x) != vis::Sign::Positive) return out;
    std::vector<Vec3> light;
    for (uint32_t v : mesh.faces[tree.light]) light.push_back(mesh.vertices[v]);
    const vis::FacePlane pb = vis::facePlane(mesh, tree.receiver);
    light = vis::clipConvexPositive(light, vis::OrientedPlane{pb.a, pb.b, pb.c});
    if (light.size() < 3) return out;
    SideWalker{mesh, tree, x, out}.visit(0, light, 0);
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
            li.key = store.keyAt(face, x, lightFace);
            li.treeWasBuilt = store.find(li.key) == nullptr;
        }
        const auto start = std::chrono::steady_clock::now();
        std::vector<LightAtPoint> r = queryPoint(store, face, x, k);
        li.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        li.result = std::move(r.front());
        if (lightFace != face) {
            li.tree = &store.getOrBuild(li.key).tree;  // already built by queryPoint
            li.steps = pathSteps(scene.mesh, *li.tree, x);
        }
        out.lights.push_back(std::move(li));
    }
    return out;
}

}  // namespace penumbra::viewer
