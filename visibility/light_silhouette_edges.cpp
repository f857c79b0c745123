#include "visibility/light_silhouette_edges.h"

#include "visibility/face_plane.h"

namespace penumbra::vis {

namespace light_silhouette_detail {

// How a face's plane sees the light's vertices: all strictly in front, all strictly behind, or
// neither (mixed signs or a zero).
enum class Facing : uint8_t { Unknown, Front, Back, Mixed };

Facing facing(const PolygonMesh& mesh, uint32_t face, uint32_t light) {
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
                                           uint32_t lightFace)
    : light_(lightFace), kept_(edges.size(), true) {
    using light_silhouette_detail::Facing;
    // Each face's facing, taken when one of its edges first asks (faces with only open edges
    // never do).
    std::vector<Facing> facing(mesh.faces.size(), Facing::Unknown);
    auto facingOf = [&](uint32_t f) {
        if (facing[f] == Facing::Unknown)
            facing[f] = light_silhouette_detail::facing(mesh, f, light_);
        return facing[f];
    };
    for (size_t e = 0; e < edges.size(); ++e) {
        if (!edges.manifold(e)) {
            ++open_;
            ++size_;
            continue;
        }
        const auto u = edges.uses(e);
        const Facing a = facingOf(u[0].face), b = facingOf(u[1].face);
        if (a != Facing::Mixed && a == b) {
            kept_[e] = false;
        } else {
            ++size_;
        }
    }
}

}  // namespace penumbra::vis
