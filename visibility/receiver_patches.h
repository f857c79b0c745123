// Receiver patches: a large receiver polygon is split into small convex patches, each with its own
// history tree. The visibility of a light from a whole floor under a table is an arrangement of
// every leaf's shadow; from a patch it is a small part of it. Trees stay small and fast to build,
// and the from-point query of x uses the tree of the patch that contains x.
//
// Patches are triangles of a regular subdivision of the face's fan triangles, enlarged about
// their centroid by a relative 1e-7 so that any point of the face lies strictly inside at least
// one patch (their corners are rounded constructions: the enlargement absorbs that rounding). A
// patch's tree is exact for every line through the patch, so for every x inside it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "visibility/vec3.h"

namespace penumbra::vis {

struct ReceiverPatches {
    std::vector<std::vector<Vec3>> patches;  // convex (triangles), counter-clockwise like the face
    // The patch containing x (x on the face's plane), found in constant time per fan triangle
    // from x's barycentric coordinates; the nearest one when x is outside the face.
    uint32_t find(const Vec3& x) const;

    std::vector<Vec3> face;  // the face's vertices (fan triangles (0, t, t+1))
    int cellsPerSide = 1;    // k: each fan triangle is a k x k triangular grid
    int dropAxis = 2;        // coordinate dropped to work in 2D (the normal's dominant axis)
};

// Subdivides until every patch has a diameter <= maxDiameter (a face already that small is one
// patch: itself, unchanged). maxDiameter <= 0 means no subdivision.
ReceiverPatches subdivideReceiver(std::span<const Vec3> face, double maxDiameter);
// The same with each fan triangle split into a k x k grid (k = cellsPerSide >= 1; 1: the face
// itself, one patch).
ReceiverPatches subdivideReceiverGrid(std::span<const Vec3> face, int cellsPerSide);
// The number of patches subdivideReceiver makes, without making them (1 for a small face).
size_t receiverPatchCount(std::span<const Vec3> face, double maxDiameter);

}  // namespace penumbra::vis
