// Tests of loadScene (engine/io/scene_loader.h): the reader is chosen by extension, in any case;
// unknown extensions are an error listing the supported ones; OBJ degenerate faces are an error
// naming the line or, on request, dropped with a warning.
#include "engine/io/scene_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tests/support/loader_test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::expectLoadError;

class SceneLoader : public test::LoaderFiles {};

TEST_F(SceneLoader, ChoosesTheReaderByExtensionInAnyCase) {
    const std::string square = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    const fs::path obj = write("a.OBJ", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    const fs::path off = write("a.Off", "OFF\n4 1 0\n" + square + "4 0 1 2 3\n");
    const fs::path ply = write("a.pLy",
                               "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n"
                               "property float y\nproperty float z\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n" +
                                   square + "4 0 1 2 3\n");
    for (const fs::path& p : {obj, off, ply}) {
        const Scene scene = loadScene(p);
        EXPECT_EQ(scene.faceCount(), 1u) << p;
        EXPECT_EQ(scene.mesh.vertices.size(), 4u) << p;
        EXPECT_DOUBLE_EQ(scene.mesh.faceArea(0), 1.0) << p;
        EXPECT_EQ(scene.sourcePath, p.string());
    }
    EXPECT_TRUE(isSupportedSceneExtension(".GLB"));
    EXPECT_TRUE(isSupportedSceneExtension(".stl"));
    EXPECT_TRUE(isSupportedSceneExtension(".Json"));
    EXPECT_FALSE(isSupportedSceneExtension(".fbx"));
    EXPECT_FALSE(isSupportedSceneExtension(".mtl"));  // next to the OBJ files in assets/
    EXPECT_FALSE(isSupportedSceneExtension(""));
}

TEST_F(SceneLoader, UnknownExtensionListsTheSupportedOnes) {
    const fs::path p = write("model.fbx", "whatever");
    expectLoadError([&] { loadScene(p); }, p,
                    {"unknown scene format '.fbx'", ".obj, .ply, .off, .stl, .gltf, .glb, .json"});
    const fs::path q = write("model", "whatever");
    expectLoadError([&] { loadScene(q); }, q, {"(no extension)"});
}

TEST_F(SceneLoader, ObjDegenerateFacesDroppedByDefaultOrRejectedWhenStrict) {
    // Face 1 (line 6) is collinear, face 2 (line 7) repeats a vertex.
    const fs::path p = write("deg.obj",
                             "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\nf 1 3 3\n"
                             "f 2 3 1\n");
    // Strict: the repeated vertex is found while parsing, before any geometry is checked.
    const LoadOptions strict = LoadOptions::strictMode();
    expectLoadError([&] { loadScene(p, strict); }, p, {"deg.obj:7: face 2", "repeated"});
    const fs::path q =
        write("collinear.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 2 0 0\nf 1 2 3\nf 1 2 4\n");
    expectLoadError([&] { loadScene(q, strict); }, q, {"collinear.obj:6: face 1", "degenerate"});
    const Scene scene = loadScene(p);
    EXPECT_EQ(scene.faceCount(), 2u);
    EXPECT_EQ(scene.faceSourceLine, (std::vector<int32_t>{5, 8}));
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("dropped 2 degenerate"), std::string::npos)
        << scene.warnings[0];
    EXPECT_NE(scene.warnings[0].find("line 6"), std::string::npos) << scene.warnings[0];
}

// The repairs reach every format through loadScene, and strict mode refuses them all.
TEST_F(SceneLoader, EveryFormatRepairsByDefaultAndRefusesWhenStrict) {
    struct Case {
        std::string name, text, warning, error;
        uint32_t faces;
    };
    const std::string plyHeader =
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const std::vector<Case> cases = {
        {"m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Default\nf 1 2 3\n",
         "usemtl 'Default' on line 4 names no material", "m.obj:4: usemtl: unknown material", 1},
        {"d.ply", plyHeader + "0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n",
         "dropped 1 degenerate", "face 1", 1},
        {"h.ply",
         "ply\nformat ascii 1.0\nCreated by Blender\nelement vertex 3\nproperty float x\n"
         "property float y\nproperty float z\nelement face 1\n"
         "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         "h.ply:3: PLY header: line 'Created by Blender' is no header keyword",
         "h.ply:3: PLY header: unknown keyword 'Created'", 1},
        {"d.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n",
         "dropped 1 degenerate", "face 1", 1},
        {"d.stl",
         "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
         "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
         "vertex 1 0 0\nendloop\nendfacet\nendsolid s\n",
         "dropped 1 degenerate", "d.stl:9: face 1", 1},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.name);
        const fs::path p = write(c.name, c.text);
        const Scene scene = loadScene(p);
        EXPECT_EQ(scene.faceCount(), c.faces);
        ASSERT_EQ(scene.warnings.size(), 1u);
        EXPECT_EQ(scene.warnings[0].rfind(p.string(), 0), 0u) << scene.warnings[0];
        EXPECT_NE(scene.warnings[0].find(c.warning), std::string::npos) << scene.warnings[0];
        expectLoadError([&] { loadScene(p, LoadOptions::strictMode()); }, p, {c.error});
    }
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

#ifndef PENUMBRA_SOURCE_DIR
#error "PENUMBRA_SOURCE_DIR must name the source tree"
#endif

const fs::path kAssets = fs::path(PENUMBRA_SOURCE_DIR) / "assets";

// The committed Cornell box composed with a mesh written here, fitted on its floor: the box's lamp
// stays the one light, the mesh stands on the floor inside the fit box.
TEST_F(SceneLoader, CornellBoxComposesWithAFittedMesh) {
    write("tet.off",
          "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    const fs::path json = write("box.json", R"({"meshes": [
        {"file": ")" + (kAssets / "cornell_box.obj").string() +
                                                R"("},
        {"file": "tet.off", "fit_into": {"min": [310, 0, 15], "max": [540, 250, 235],
                                         "align": ["center", "min", "center"]}}]})");
    const Scene box = loadScene(kAssets / "cornell_box.obj");
    const Scene scene = loadScene(json);
    EXPECT_EQ(scene.faceCount(), box.faceCount() + 4);
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_EQ(scene.lights[0], box.lights[0]);
    EXPECT_EQ(scene.material(scene.lights[0]).ke, box.material(box.lights[0]).ke);
    // The unit tetrahedron scaled by min(230, 250, 220) = 220, centred in x and z, on y = 0.
    vis::Bounds3 b;
    for (uint32_t f = box.faceCount(); f < scene.faceCount(); ++f) {
        const vis::Bounds3 fb = scene.mesh.faceBounds(f);
        b.add(fb.lo);
        b.add(fb.hi);
        // Outward normals: the tetrahedron is closed and its faces were written outward.
        const Vec3 centroidToFace = scene.mesh.vertex(scene.mesh.faces[f][0]) - Vec3(370, 55, 70);
        EXPECT_GT(dot(scene.mesh.faceAreaNormal(f), centroidToFace), 0) << f;
    }
    EXPECT_EQ(b.lo, Vec3(315, 0, 15));
    EXPECT_EQ(b.hi, Vec3(535, 220, 235));
}

// Every scene file of assets/scenes/ loads when the meshes it names are present, and names the
// mesh it misses when one is not: those under assets/external/ come from scripts/fetch_meshes.sh
// (neither a fresh clone nor CI has them), every other one is committed and must exist. What each
// scene must hold is read from its JSON here: a camera where it gives one, a light, and at least a
// face per mesh, polygon and area light; a scene of committed meshes only (cheap to load one by
// one) has exactly its parts' faces and lights.
TEST_F(SceneLoader, CommittedSceneFilesLoadOrNameTheMeshTheyMiss) {
    int loaded = 0, refused = 0;
    for (const auto& entry : fs::directory_iterator(kAssets / "scenes")) {
        const fs::path scene = entry.path();
        if (scene.extension() != ".json") continue;
        SCOPED_TRACE(scene.string());
        std::ifstream in(scene);
        const nlohmann::json j = nlohmann::json::parse(in);
        std::vector<fs::path> meshes, missing;
        for (const nlohmann::json& m : j.value("meshes", nlohmann::json::array())) {
            const fs::path mesh = scene.parent_path() / m.at("file").get<std::string>();
            meshes.push_back(mesh);
            if (fs::exists(mesh)) continue;
            missing.push_back(mesh);
            EXPECT_EQ(mesh.parent_path().filename(), "external") << mesh << " is not committed";
        }
        const size_t polygons = j.value("polygons", nlohmann::json::array()).size();
        const size_t areaLights = j.value("area_lights", nlohmann::json::array()).size();
        if (!missing.empty()) {
            expectLoadError([&] { loadScene(scene); }, scene,
                            {"no such file: " + missing.front().string()});
            ++refused;
            continue;
        }
        const Scene s = loadScene(scene);
        EXPECT_EQ(s.camera.has_value(), j.contains("camera"));
        EXPECT_GE(s.lights.size(), std::max<size_t>(areaLights, 1));
        EXPECT_GE(s.faceCount(), meshes.size() + polygons + areaLights);
        const bool committedOnly = std::none_of(
            meshes.begin(), meshes.end(),
            [](const fs::path& m) { return m.parent_path().filename() == "external"; });
        if (committedOnly) {
            size_t faces = polygons + areaLights, lights = areaLights;
            for (const fs::path& m : meshes) {
                const Scene part = loadScene(m);
                faces += part.faceCount();
                lights += part.lights.size();
            }
            EXPECT_EQ(s.faceCount(), faces);
            EXPECT_EQ(s.lights.size(), lights);
        }
        ++loaded;
    }
    // The paper's scenes and the Cornell box are committed with their meshes.
    EXPECT_GE(loaded, 4);
    std::printf("%d scene files loaded, %d refused for a mesh scripts/fetch_meshes.sh fetches\n",
                loaded, refused);
}

}  // namespace
}  // namespace penumbra
