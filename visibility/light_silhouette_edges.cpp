#include "visibility/light_silhouette_edges.h"

#include "visibility/face_plane.h"

namespace penumbra::vis {

namespace light_silhouette_detail {

// How a face's plane sees the light's vertices: all strictly in front, all strictly behind, or
// neither (mixed signs or a zero; a face of fewer than 3 vertices, which has no plane).
enum class Facing : uint8_t { Front, Back, Mixed };

Facing facing(const PolygonMesh& mesh, uint32_t face, uint32_t light) {
    if (mesh.faces[face].size() < 3) return Facing::Mixed;
    const FacePlane plane = facePlane(mesh, face);
    bool front = true, back = true;
    for (uint32_t v : mesh.faces[light]) {
        const Sign s = plane.side(mesh.vertices[v]);
        front = front && s == Sign::Positive;
        back = back && s == Sign::Negative;
        if (!front && !back) return Facing::Mixed;
    }
    return front ? Facing::Front : Facing::Back;
}

}  // namespace light_silhouette_detail

LightSilhouetteEdges::LightSilhouetteEdges(const PolygonMesh& mesh, const MeshEdges& edges,
                                           uint32_t lightFace, const ParallelLoops& loops)
    : light_(lightFace), kept_(edges.size(), 1) {
    using light_silhouette_detail::Facing;
    // Each face's facing (a face whose edges are all open is never asked: computed anyway, a few
    // orient3d each), then each edge's decision from its faces'.
    std::vector<Facing> facing(mesh.faces.size());
    loops.run(mesh.faces.size(), 4096, [&](size_t begin, size_t end) {
        for (size_t f = begin; f < end; ++f)
            facing[f] = light_silhouette_detail::facing(mesh, static_cast<uint32_t>(f), light_);
    });
    loops.run(edges.size(), 4096, [&](size_t begin, size_t end) {
        for (size_t e = begin; e < end; ++e) {
            if (!edges.manifold(e)) continue;
            const auto u = edges.uses(e);
            const Facing a = facing[u[0].face], b = facing[u[1].face];
            if (a != Facing::Mixed && a == b) kept_[e] = 0;
        }
    });
    for (size_t e = 0; e < edges.size(); ++e) {
        size_ += kept_[e];
        open_ += !edges.manifold(e);
    }
}

}  // namespace penumbra::vis
