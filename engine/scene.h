// Scene: a polygon mesh with materials and area lights, as loaded from a file.
// The contract (DEVELOPERS.md issue 2): faces numbered from 0 in file order; a face whose material
// has a nonzero Ke is an area light; lights numbered from 0 in file order; vertices
// counter-clockwise seen from the front; faces planar and convex.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "visibility/polygon_mesh.h"

namespace penumbra {

using vis::Vec3;

struct Material {
    std::string name;
    Vec3 kd{0.8, 0.8, 0.8};  // diffuse albedo
    Vec3 ks{0, 0, 0};        // specular
    Vec3 ke{0, 0, 0};        // emitted radiance; nonzero makes the face an area light
    double ns = 0;           // Phong exponent
    bool isEmissive() const { return ke.x > 0 || ke.y > 0 || ke.z > 0; }
};

struct Scene {
    std::string sourcePath;           // for error messages
    vis::PolygonMesh mesh;            // geometry handed to the visibility core
    std::vector<int32_t> faceMaterial;  // per face, index into materials or -1 (default)
    std::vector<int32_t> faceSourceLine;  // per face, the 1-based line it came from (0 if none)
    std::vector<Material> materials;
    std::vector<uint32_t> lights;     // face indices of emissive faces, in file order

    uint32_t faceCount() const { return static_cast<uint32_t>(mesh.faces.size()); }
    const Material& material(uint32_t face) const;
    // Rebuilds `lights` from the face materials (file order).
    void collectLights();
};

}  // namespace penumbra
