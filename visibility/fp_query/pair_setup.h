// The part of a from-point query that depends on the (receiver B, light L) pair and not on x:
// L's vertices and plane, B's plane, and L clipped to B's front half-space. Reused while
// consecutive runs ask for the same pair.
#pragma once

#include <cstdint>
#include <vector>

#include "visibility/polygon_clip.h"
#include "visibility/polygon_mesh.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

class PairSetup {
  public:
    // Prepares the pair (checked by value, the faces' vertex coordinates, so a changed or
    // reloaded mesh is noticed); true when it changed (what was derived from the last one is
    // stale).
    bool prepare(const PolygonMesh& mesh, uint32_t receiver, uint32_t light);
    // Counts the pairs prepared: what a caller derived from the pair is current while it holds.
    uint64_t generation() const { return generation_; }

    const PolygonMesh& mesh() const { return *mesh_; }
    uint32_t receiver() const { return receiver_; }
    uint32_t light() const { return light_; }
    // L's vertices, and L clipped to B's front half-space (rounded where B's plane cuts L).
    const std::vector<Vec3>& lightPolygon() const { return lightPolygon_; }
    const std::vector<Vec3>& lightClipped() const { return lightClipped_; }
    // L's plane (the light emits to its positive side), and B's and L's planes as clip planes.
    const PlaneOrient& lightPlane() const { return lightPlane_; }
    const OrientedPlane& frontB() const { return frontB_; }
    const OrientedPlane& frontL() const { return frontL_; }

  private:
    const PolygonMesh* mesh_ = nullptr;
    uint32_t receiver_ = 0, light_ = 0;
    uint64_t generation_ = 0;
    Vec3 receiverPlane_[3];
    PlaneOrient lightPlane_;
    OrientedPlane frontB_{{}, {}, {}}, frontL_{{}, {}, {}};
    std::vector<Vec3> lightPolygon_, lightClipped_, discard_;
};

}  // namespace penumbra::vis
