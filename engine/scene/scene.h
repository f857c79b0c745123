// Scene: a polygon mesh with materials and area lights, as loaded from a file.
// The contract (README, "Scene contract"): faces numbered from 0 in file order; a face whose
// material has a nonzero Ke is an area light; lights numbered from 0 in file order; vertices
// counter-clockwise seen from the front; faces planar and convex.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "engine/scene/camera.h"
#include "engine/scene/default_light.h"
#include "engine/scene/texture.h"
#include "visibility/polygon_mesh.h"

namespace penumbra {

using vis::Vec3;

// A material as the renderer sees it: Lambertian diffuse plus an optional normalised Phong lobe.
// OBJ/MTL maps directly (Kd, Ks, Ns, Ke); glTF's metallic-roughness is converted by its loader
// (kd = base (1 - metallic), ks = mix(0.04, base, metallic), ns = 2 / roughness^4 - 2).
// kdMap, when present, multiplies kd at each point by the texture's colour there (Scene::kdAt).
struct Material {
    std::string name;
    Vec3 kd{0.8, 0.8, 0.8};  // diffuse albedo (the factor, with a kdMap)
    Vec3 ks{0, 0, 0};        // specular albedo of the Phong lobe
    Vec3 ke{0, 0, 0};        // emitted radiance; nonzero makes the face an area light
    double ns = 0;           // Phong exponent
    TextureRef kdMap;        // glTF baseColorTexture, MTL map_Kd (last: aggregate initialisers)
    bool isEmissive() const { return ke.x > 0 || ke.y > 0 || ke.z > 0; }
    // A purely diffuse material is shaded analytically from the exact fragments; a glossy one
    // (nonzero ks) needs samples inside them.
    bool isGlossy() const { return ks.x > 0 || ks.y > 0 || ks.z > 0; }
};

// An isotropic point light: one shadow ray decides its visibility, no history tree.
struct PointLight {
    Vec3 position;
    Vec3 intensity{1, 1, 1};  // radiant intensity (W/sr) per channel
};

struct Scene {
    std::string sourcePath;               // for error messages
    vis::PolygonMesh mesh;                // geometry handed to the visibility core
    std::vector<int32_t> faceMaterial;    // per face, index into materials or -1 (default)
    std::vector<int32_t> faceSourceLine;  // per face, the 1-based line it came from (0 if none)
    std::vector<Material> materials;
    std::vector<TextureImage> textures;  // the images of the materials' maps (TextureRef::image)
    // Texture coordinates per face corner (texture.h's convention), in the face's vertex order:
    // empty when the scene has none, else one entry per face, itself empty (the face has none) or
    // one Uv per vertex of the face.
    std::vector<std::vector<Uv>> faceUv;
    std::vector<uint32_t> lights;         // face indices of emissive faces, in file order
    std::vector<PointLight> pointLights;  // from scene files; no visibility precompute
    std::optional<Camera> camera;         // from scene files (glTF, JSON); else the viewer fits one
    // Problems the loader worked around (e.g. dropped degenerate faces), one message each, naming
    // the file; commands print them to stderr.
    std::vector<std::string> warnings;
    // The light added because the file has none (engine/scene/default_light.h): the last face,
    // its material the last; nullopt when the scene's lights are its file's.
    std::optional<DefaultLight> defaultLight;

    uint32_t faceCount() const { return static_cast<uint32_t>(mesh.faces.size()); }
    const Material& material(uint32_t face) const;
    // The bounds of the file's geometry: the mesh's, the default light left out (what cameras are
    // fitted to).
    vis::Bounds3 fileBounds() const;
    // What the commands print on stderr after loading, one line each: the default light's
    // announcement, then the warnings.
    std::vector<std::string> loadNotices() const;
    // The diffuse albedo at x, a point of face `face`: the material's kd, times its kdMap at x's
    // texture coordinates (faceUvAt, face_uv.h) when it has one and the face has coordinates.
    Vec3 kdAt(uint32_t face, const Vec3& x) const;
    // Rebuilds `lights` from the face materials (file order).
    void collectLights();
};

}  // namespace penumbra
