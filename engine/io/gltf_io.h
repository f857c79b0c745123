// glTF 2.0 scenes (.gltf with embedded or external buffers, .glb), parsed by tinygltf.
//
// What is read:
//   - the default scene (`scene`, else scene 0; a file without scenes uses every root node), its
//     node hierarchy walked from the roots; a node's transform is its `matrix` (must be affine) or
//     translation * rotation * scale, composed with its parents'. A node reached twice (a cycle
//     or a shared child) is an error;
//   - every mesh primitive of mode TRIANGLES (4, also the default), TRIANGLE_STRIP (5) or
//     TRIANGLE_FAN (6), indexed (UNSIGNED_BYTE/SHORT/INT indices) or not, from its POSITION
//     accessor (FLOAT VEC3). Point and line primitives are skipped with a warning. Every triangle
//     becomes one face; each primitive instance gets its own vertices. A node whose world
//     transform has a negative determinant has its triangles' vertex order reversed, so they stay
//     counter-clockwise seen from the front (glTF's rule);
//   - materials, all of them in file order (primitive material -1 is Scene's default material):
//     kd = base (1 - metallic), ks = mix(0.04, base, metallic), ns = 2 / roughness^4 - 2 (roughness
//     clamped to at least 0.01), base = baseColorFactor.rgb; ke = emissiveFactor times
//     KHR_materials_emissive_strength.emissiveStrength (default 1). A nonzero ke makes every
//     triangle with that material an area light. pbrMetallicRoughness.baseColorTexture becomes
//     Material::kdMap (engine/scene/texture.h): its image decoded (texture_io.h: a file next to
//     the glTF, a data URI or a buffer view), the sampler's wrapS/wrapT and magFilter NEAREST
//     (else bilinear), KHR_texture_transform's offset, rotation, scale and texCoord, and the
//     primitive's TEXCOORD_n (FLOAT, or normalised UNSIGNED_BYTE/SHORT VEC2) as Scene::faceUv.
//     An image that cannot be used (missing, undecodable, only in an extension's format such as
//     basisu or webp) or a primitive without that TEXCOORD_n is a repair: one warning naming it,
//     the material's baseColorFactor alone; an error in strict mode. The other textures (normal,
//     metallic-roughness, emissive, occlusion) are not read;
//   - the first node (in traversal order) that holds a perspective camera becomes Scene::camera:
//     eye at the node's origin, looking down its -Z axis, up its +Y axis, fov_y = yfov. An
//     orthographic camera is ignored with a warning.
// Refused before tinygltf parses the file, with a message that says what is unsupported: glTF 1.0
// (asset.version "1.x", a GLB of version 1, or, without asset.version, 1.0's dictionaries in place
// of arrays) and any other version than 2.x; a required extension (extensionsRequired) the loader
// does not implement, named (KHR_draco_mesh_compression with its own message; the loader implements
// KHR_materials_emissive_strength and KHR_texture_transform, and accepts KHR_texture_basisu,
// EXT_texture_webp, EXT_texture_avif and MSFT_texture_dds: an image only in such a format is not
// decoded, and its material keeps its factor, with the warning above); a primitive compressed with
// Draco that keeps no uncompressed POSITION data.
// Errors are SceneErrors naming the file and the element: tinygltf's own parse errors, an
// accessor that is sparse, of the wrong type or reaches past its buffer view or buffer, an index
// out of range of the POSITION accessor, a non-finite position ("node 2 mesh 0 primitive 1:
// POSITION 7: non-finite coordinate"), a triangle count not divisible by 3. Faces are checked
// by checkLoadedFaces (engine/scene/face_check.h) and named "node N mesh M primitive P triangle T";
// in repair mode (LoadOptions, the default) degenerate triangles are dropped with one warning.
#pragma once

#include <filesystem>

#include "engine/io/load_options.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_error.h"

namespace penumbra {

// Reads a .gltf or .glb file (binary when it starts with the GLB magic "glTF"); external buffers
// are resolved relative to the file's directory.
Scene loadGltf(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace penumbra
