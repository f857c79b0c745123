#include "visibility/light_edge_index.h"

#include "visibility/face_plane.h"
#include "visibility/light_silhouette_edges.h"

namespace penumbra::vis {

LightEdgeIndex::LightEdgeIndex(const PolygonMesh& mesh, const MeshEdges& edges, uint32_t lightFace)
    : light_(lightFace), vertexCount_(mesh.vertices.size()) {
    // Each vertex's side of L's plane (exact), then each face's from its vertices'.
    const PlaneOrient lightPlane = facePlane(mesh, lightFace).orient();
    std::vector<Sign> vertexSide(mesh.vertices.size());
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
        vertexSide[v] = lightPlane.sign(mesh.vertices[v]);
    sides_.resize(mesh.faces.size(), Side::Behind);
    std::vector<Bounds3> acrossBoxes(mesh.faces.size());
    for (size_t f = 0; f < mesh.faces.size(); ++f) {
        const auto& ids = mesh.faces[f];
        if (ids.size() < 3) continue;
        bool front = false, behind = false;
        for (uint32_t v : ids) {
            front = front || vertexSide[v] == Sign::Positive;
            behind = behind || vertexSide[v] == Sign::Negative;
        }
        sides_[f] = !front ? Side::Behind : behind ? Side::Across : Side::Front;
        if (sides_[f] != Side::Across) continue;
        ++acrossCount_;
        for (uint32_t v : ids) acrossBoxes[f].add(mesh.vertices[v]);
    }
    if (acrossCount_ > 0) acrossFaces_ = BoxTree(acrossBoxes);

    const LightSilhouetteEdges set(mesh, edges, lightFace);
    share_ = set.share();
    open_ = set.open();
    std::vector<Bounds3> boxes;
    edges_.reserve(set.size());
    begin_.reserve(set.size() + 1);
    boxes.reserve(set.size());
    for (size_t e = 0; e < edges.size(); ++e) {
        if (!set.contains(e)) continue;
        const MeshEdges::Edge& edge = edges.edge(e);
        edges_.push_back(edge);
        begin_.push_back(static_cast<uint32_t>(uses_.size()));
        for (const MeshEdges::Use& u : edges.uses(e)) uses_.push_back(u);
        Bounds3 box;
        box.add(mesh.vertices[edge.lo]);
        box.add(mesh.vertices[edge.hi]);
        boxes.push_back(box);
    }
    begin_.push_back(static_cast<uint32_t>(uses_.size()));
    edgeBoxes_ = BoxTree(boxes);
}

}  // namespace penumbra::vis
