// The texture coordinates of a point of a face, from its corners' (Scene::faceUv).
//
// Interpolated in the triangle of the face's fan (corners 0, k, k + 1) that holds the point,
// barycentrically; rather than mean-value coordinates over the whole polygon because it is exact
// for triangles (every glTF face) and for any polygon whose corner UVs are an affine image of its
// positions (a planar quad mapped onto a rectangle of the image, the usual OBJ quad), costs one
// triangle's barycentrics, and is what the raster view's GPU interpolates over the same fan, so
// the rendered and the raster view put a texel at the same place. Across a fan diagonal of a quad
// whose UVs are no affine image it is continuous but bends, as in every rasteriser.
#pragma once

#include <cstdint>
#include <optional>

#include "engine/scene/scene.h"

namespace penumbra {

// nullopt when the scene or the face has no texture coordinates. x should lie on the face's plane
// (a shading point); a point a rounding outside the face takes the nearest fan triangle's
// extrapolation.
std::optional<Uv> faceUvAt(const Scene& scene, uint32_t face, const Vec3& x);

}  // namespace penumbra
