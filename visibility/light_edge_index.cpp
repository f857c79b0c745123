#include "visibility/light_edge_index.h"

#include <algorithm>

#include "visibility/face_plane.h"
#include "visibility/light_silhouette_edges.h"

namespace penumbra::vis {

LightEdgeIndex::LightEdgeIndex(const PolygonMesh& mesh, const MeshEdges& edges, uint32_t lightFace,
                               const ParallelLoops& loops)
    : light_(lightFace), vertexCount_(mesh.vertices.size()) {
    // Each vertex's side of L's plane (exact), then each face's from its vertices'.
    const PlaneOrient lightPlane = facePlane(mesh, lightFace).orient();
    std::vector<Sign> vertexSide(mesh.vertices.size());
    loops.run(mesh.vertices.size(), 8192, [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v) vertexSide[v] = lightPlane.sign(mesh.vertices[v]);
    });
    sides_.resize(mesh.faces.size(), Side::Behind);
    std::vector<Bounds3> acrossBoxes(mesh.faces.size());
    loops.run(mesh.faces.size(), 8192, [&](size_t begin, size_t end) {
        for (size_t f = begin; f < end; ++f) {
            const auto& ids = mesh.faces[f];
            if (ids.size() < 3) continue;
            bool front = false, behind = false;
            for (uint32_t v : ids) {
                front = front || vertexSide[v] == Sign::Positive;
                behind = behind || vertexSide[v] == Sign::Negative;
            }
            sides_[f] = !front ? Side::Behind : behind ? Side::Across : Side::Front;
            if (sides_[f] != Side::Across) continue;
            for (uint32_t v : ids) acrossBoxes[f].add(mesh.vertices[v]);
        }
    });
    for (Side s : sides_) acrossCount_ += s == Side::Across;
    if (acrossCount_ > 0) acrossFaces_ = BoxTree(acrossBoxes, {}, loops);

    const LightSilhouetteEdges set(mesh, edges, lightFace, loops);
    share_ = set.share();
    open_ = set.open();
    // S_L's edges in the edge table's order: each chunk of the table counted (edges, uses),
    // the counts summed into offsets, then each chunk copied to its place.
    constexpr size_t kChunk = 16384;
    const size_t chunks = (edges.size() + kChunk - 1) / kChunk;
    std::vector<size_t> edgeAt(chunks + 1, 0), useAt(chunks + 1, 0);
    loops.run(chunks, 1, [&](size_t begin, size_t end) {
        for (size_t c = begin; c < end; ++c)
            for (size_t e = c * kChunk; e < std::min(edges.size(), (c + 1) * kChunk); ++e) {
                if (!set.contains(e)) continue;
                ++edgeAt[c + 1];
                useAt[c + 1] += edges.uses(e).size();
            }
    });
    for (size_t c = 0; c < chunks; ++c) {
        edgeAt[c + 1] += edgeAt[c];
        useAt[c + 1] += useAt[c];
    }
    edges_.resize(edgeAt[chunks]);
    begin_.resize(edges_.size() + 1);
    uses_.resize(useAt[chunks]);
    begin_[edges_.size()] = static_cast<uint32_t>(uses_.size());
    std::vector<Bounds3> boxes(edges_.size());
    loops.run(chunks, 1, [&](size_t begin, size_t end) {
        for (size_t c = begin; c < end; ++c) {
            size_t i = edgeAt[c], u = useAt[c];
            for (size_t e = c * kChunk; e < std::min(edges.size(), (c + 1) * kChunk); ++e) {
                if (!set.contains(e)) continue;
                const MeshEdges::Edge& edge = edges.edge(e);
                edges_[i] = edge;
                begin_[i] = static_cast<uint32_t>(u);
                for (const MeshEdges::Use& use : edges.uses(e)) uses_[u++] = use;
                boxes[i].add(mesh.vertices[edge.lo]);
                boxes[i].add(mesh.vertices[edge.hi]);
                ++i;
            }
        }
    });
    edgeBoxes_ = BoxTree(boxes, {}, loops);
}

}  // namespace penumbra::vis
