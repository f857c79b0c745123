#include "visibility/fp_query/pair_setup.h"

#include "visibility/face_plane.h"

namespace penumbra::vis {

bool PairSetup::prepare(const PolygonMesh& mesh, uint32_t receiver, uint32_t light) {
    const auto& lightFace = mesh.faces[light];
    const auto& receiverFace = mesh.faces[receiver];
    bool same = mesh_ == &mesh && receiver_ == receiver && light_ == light &&
                lightPolygon_.size() == lightFace.size();
    for (size_t i = 0; same && i < lightFace.size(); ++i)
        same = lightPolygon_[i] == mesh.vertices[lightFace[i]];
    for (size_t i = 0; same && i < 3; ++i)
        same = receiverPlane_[i] == mesh.vertices[receiverFace[i]];
    if (same) return false;
    mesh_ = &mesh;
    receiver_ = receiver;
    light_ = light;
    ++generation_;
    lightPolygon_.clear();
    for (uint32_t v : lightFace) lightPolygon_.push_back(mesh.vertices[v]);
    for (size_t i = 0; i < 3; ++i) receiverPlane_[i] = mesh.vertices[receiverFace[i]];
    const FacePlane pl = facePlane(mesh, light);
    lightPlane_ = PlaneOrient(pl.a, pl.b, pl.c);
    // The receiver sees only its front hemisphere (B's plane, exact on input points).
    frontB_ = OrientedPlane{receiverPlane_[0], receiverPlane_[1], receiverPlane_[2]};
    frontL_ = OrientedPlane{pl.a, pl.b, pl.c};
    clipConvexInto(lightPolygon_, frontB_, lightClipped_, discard_);
    return true;
}

}  // namespace penumbra::vis
