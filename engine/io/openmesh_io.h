// PLY, OFF and STL scenes, parsed by OpenMesh 9's readers (OpenMeshCore).
//
// OpenMesh hands every vertex and face to our own importer (a BaseImporter that records them in
// file order into a PolygonMesh), so no half-edge mesh is built: non-manifold input is kept as it
// is, faces keep their file order and numbering, and a face with a repeated or out-of-range vertex
// index reaches validation (OpenMesh's own mesh importer would silently skip it).
//
// What is read: vertex positions (as doubles where the file has them, otherwise as floats) and
// face vertex lists; colours, normals, texture coordinates and other properties are ignored. Every
// face gets the default material (Scene::faceMaterial -1), so these scenes have no area lights;
// give them materials and lights in a JSON scene file (engine/io/scene_file.h).
//
// OpenMesh prints some problems to stderr and returns partial data, so the result is checked
// against the file itself:
//   - PLY: the header is parsed here (format, element counts, property types); the vertex and face
//     counts read must equal the header's; a binary body must have exactly the size the header
//     implies (face lists walked here), an ASCII body at least one line per element;
//   - OFF: the counts read must equal the "nv nf ne" line's;
//   - STL: a file whose size is 84 + 50 n for the triangle count n in its header is binary, else
//     one starting with "solid" is ASCII, else it is a truncated or malformed binary file. ASCII
//     is read token by token here (every facet 3 finite vertices, each solid ending in
//     "endsolid"; several solids one after the other, as tools concatenate them, are all read as
//     one mesh) and handed to OpenMesh rewritten as one plain solid. OpenMesh merges equal float
//     corners and skips facets whose corners coincide: those are put back in their place as
//     degenerate faces (face N is facet N; ASCII faces keep the line of their "facet"), dropped
//     with the other degenerate faces in repair mode, an error in strict mode.
//   - PLY header lines of no PLY keyword (a tool's "Created by ..." outside a comment) are
//     skipped with one warning in repair mode when the rest of the header is consistent; strict
//     mode refuses them ("PLY header: unknown keyword").
// Vertex coordinates must be finite ("vertex N: non-finite coordinate"). Faces are then checked
// by checkLoadedFaces (engine/scene/face_check.h): errors read "file: face N: <reason>" with N the
// 0-based face index in the file (for STL the index of the facet).
#pragma once

#include <filesystem>

#include "engine/io/load_options.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_error.h"

namespace penumbra {

// Reads a .ply, .off or .stl file (by extension, case-insensitive) in repair mode (the default)
// or strict mode (engine/io/load_options.h). Throws SceneError naming the file.
Scene loadOpenMeshFile(const std::filesystem::path& path, const LoadOptions& options = {});

}  // namespace penumbra
