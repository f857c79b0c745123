// Receiver patches: a large receiver polygon is split into small convex patches, each with its own
// history tree. The visibility of a light from a whole floor under a table is an arrangement of
// every leaf's shadow; from a patch it is a small part of it. Trees stay small and fast to build,
// and the from-point query of x uses the tree of the patch that contains x.
//
// Patches are triangles of a regular subdivision of the face's fan triangles, enlarged about
// their centroid (by a relative 1e-7, more where the coordinates are large against the patch:
// subdivideReceiverGrid) so that any point of the face lies strictly inside at least one patch
// (their corners are rounded constructions: the enlargement absorbs that rounding). A patch's tree
// is exact for every line through the patch, so for every x inside it: find() returns a patch
// that contains x, decided by exact orientation signs in the projection that drops the dominant
// axis of the face's normal, at every magnitude and every refinement level.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "visibility/orient2d.h"
#include "visibility/vec3.h"

namespace penumbra::vis {

struct ReceiverPatches {
    std::vector<std::vector<Vec3>> patches;  // convex (triangles), counter-clockwise like the face
    // A patch containing x (x on the face's plane), decided exactly (contains()): guessed in
    // constant time per fan triangle from x's rounded barycentric coordinates, then checked, then
    // the cells around the guess, then (never seen but for points on patch edges at extreme
    // magnitudes) every patch. The nearest guess when x is outside the face.
    // With a hint (a patch that held a neighbouring point: the renderer's previous pixel), that
    // patch where it contains x, the one exact test instead of the guess: any patch containing x
    // answers it exactly.
    uint32_t find(const Vec3& x, uint32_t hint = kNoHint) const;
    static constexpr uint32_t kNoHint = UINT32_MAX;
    // Whether x, projected (dropAxis), lies in patch `patch`'s closed projected polygon: exact
    // orientation signs of the doubles given.
    bool contains(uint32_t patch, const Vec3& x) const;

    std::vector<Vec3> face;  // the face's vertices (fan triangles (0, t, t+1))
    int cellsPerSide = 1;    // k: each fan triangle is a k x k triangular grid
    int dropAxis = 2;        // coordinate dropped to work in 2D (the normal's dominant axis)
    int faceTurn = 0;        // the face's turn in that projection (exact; 0 if unknown)
    // The grid's triangles projected (dropAxis), one per patch when the face is subdivided.
    std::vector<std::array<Point2, 3>> corners2d;

  private:
    // The index of cell (i, j) (upper or lower half) of fan triangle `fan`'s grid.
    uint32_t cellIndex(size_t fan, int i, int j, bool upper) const;
};

// Subdivides until every patch has a diameter <= maxDiameter (a face already that small is one
// patch: itself, unchanged). maxDiameter <= 0 means no subdivision.
ReceiverPatches subdivideReceiver(std::span<const Vec3> face, double maxDiameter);
// The same with each fan triangle split into a k x k grid (k = cellsPerSide >= 1; 1: the face
// itself, one patch). `dropAxis` (0-2) sets the projection find() decides in (a refined patch
// takes its face's, so that a point inside the parent in that projection lies inside one of the
// sub-patches); -1 takes the dominant axis of the polygon's normal.
ReceiverPatches subdivideReceiverGrid(std::span<const Vec3> face, int cellsPerSide,
                                      int dropAxis = -1);
// The number of patches subdivideReceiver makes, without making them (1 for a small face).
size_t receiverPatchCount(std::span<const Vec3> face, double maxDiameter);

}  // namespace penumbra::vis
