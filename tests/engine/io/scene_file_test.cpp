// Tests of JSON scene files (engine/io/scene_file.h): composition of mesh files with transforms,
// fit_into, material overrides, area and point lights and a camera, checked against hand-derived
// positions; mirrored meshes keep their faces counter-clockwise; errors name the JSON path.
#include "engine/io/scene_file.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "engine/io/scene_loader.h"
#include "tests/support/loader_test_support.h"
#include "tests/support/test_files.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using test::expectLoadError;

// The test solid: a unit square at z=0 (face 0, facing +z) and a triangle on its edge y=0 (face 1,
// vertices 0 1 4, facing -y). Bounds [0,1]^3.
const std::string kSolidPly =
    "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
    "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0 1\n4 0 1 2 3\n3 0 1 4\n";

using test::expectNear;

class SceneFile : public test::LoaderFiles {
  protected:
    void SetUp() override {
        LoaderFiles::SetUp();
        write("meshes/solid.ply", kSolidPly);
    }
    Scene load(const std::string& json) { return loadJsonScene(write("scene.json", json)); }
    void expectError(const std::string& json, std::initializer_list<std::string> keywords) {
        const fs::path p = write("scene.json", json);
        expectLoadError([&] { loadJsonScene(p); }, p, keywords);
    }
};

TEST_F(SceneFile, ComposesMeshesLightsAndCamera) {
    const Scene scene = load(R"({
      "meshes": [
        {"file": "meshes/solid.ply",
         "transform": {"scale": 2, "rotate": {"axis": [0, 0, 1], "degrees": 90}, "translate": [1, 2, 3]},
         "material": {"name": "red", "kd": [0.5, 0, 0]}},
        {"file": "meshes/solid.ply", "transform": {"scale": [-1, 1, 1]}}
      ],
      "area_lights": [{"vertices": [[0, 0, 5], [0, 1, 5], [1, 1, 5], [1, 0, 5]], "emission": 10}],
      "point_lights": [{"position": [1, 2, 3], "intensity": [1, 2, 3]}],
      "camera": {"eye": [0, -5, 1], "target": [0, 0, 0], "fov_y": 30}
    })");
    ASSERT_EQ(scene.faceCount(), 5u);
    ASSERT_EQ(scene.mesh.vertices.size(), 14u);
    // Mesh 0: p -> Rz(90) (2 p) + (1, 2, 3), Rz(90): (x, y, z) -> (-y, x, z).
    expectNear(scene.mesh.vertices[0], {1, 2, 3});
    expectNear(scene.mesh.vertices[1], {1, 4, 3});
    expectNear(scene.mesh.vertices[2], {-1, 4, 3});
    expectNear(scene.mesh.vertices[4], {1, 3, 5});
    EXPECT_EQ(scene.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2, 3}));
    // Mesh 1, mirrored in x: positions negated in x, vertex order reversed (first kept).
    expectNear(scene.mesh.vertices[6], {-1, 0, 0});
    expectNear(scene.mesh.vertices[9], {-0.5, 0, 1});
    EXPECT_EQ(scene.mesh.faces[2], (std::vector<uint32_t>{5, 8, 7, 6}));
    EXPECT_EQ(scene.mesh.faces[3], (std::vector<uint32_t>{5, 9, 6}));
    // Fronts are where they were: the square faces +z, the triangle -y.
    EXPECT_GT(scene.mesh.faceAreaNormal(2).z, 0);
    EXPECT_LT(scene.mesh.faceAreaNormal(3).y, 0);
    // The area light: face 4, facing -z (counter-clockwise seen from below).
    EXPECT_EQ(scene.lights, (std::vector<uint32_t>{4}));
    EXPECT_LT(scene.mesh.faceAreaNormal(4).z, 0);
    EXPECT_EQ(scene.faceMaterial, (std::vector<int32_t>{0, 0, -1, -1, 1}));
    ASSERT_EQ(scene.materials.size(), 2u);
    EXPECT_EQ(scene.materials[0].name, "red");
    EXPECT_EQ(scene.materials[0].kd, Vec3(0.5, 0, 0));
    EXPECT_FALSE(scene.materials[0].isEmissive());
    EXPECT_EQ(scene.materials[1].ke, Vec3(10, 10, 10));
    ASSERT_EQ(scene.pointLights.size(), 1u);
    EXPECT_EQ(scene.pointLights[0].position, Vec3(1, 2, 3));
    EXPECT_EQ(scene.pointLights[0].intensity, Vec3(1, 2, 3));
    ASSERT_TRUE(scene.camera.has_value());
    EXPECT_EQ(scene.camera->eye, Vec3(0, -5, 1));
    EXPECT_EQ(scene.camera->target, Vec3(0, 0, 0));
    EXPECT_EQ(scene.camera->up, Vec3(0, 1, 0));
    EXPECT_EQ(scene.camera->fovYDegrees, 30);
    EXPECT_TRUE(scene.warnings.empty());
    EXPECT_EQ(scene.sourcePath, (dir_ / "scene.json").string());
}

TEST_F(SceneFile, FitIntoScalesUniformlyAndAligns) {
    // Bounds [0,1]^3 into [0,4]x[0,2]x[0,8]: scale 2 (the y extent limits), x and z centred, y at
    // the bottom: [1,3]x[0,2]x[3,5].
    const Scene scene = load(R"({"meshes": [{"file": "meshes/solid.ply",
        "fit_into": {"min": [0, 0, 0], "max": [4, 2, 8], "align": ["center", "min", "center"]}}]})");
    const vis::Bounds3 b = scene.mesh.bounds();
    expectNear(b.lo, {1, 0, 3});
    expectNear(b.hi, {3, 2, 5});
    EXPECT_DOUBLE_EQ(scene.mesh.faceArea(0), 4.0);
}

TEST_F(SceneFile, FitIntoAppliesAfterTheTransform) {
    // Rotated 90 degrees about x: (x, y, z) -> (x, -z, y), bounds [0,1]x[-1,0]x[0,1]; then into
    // [10,11]x[0,1]x[0,1] aligned at the max corner.
    const Scene scene = load(R"({"meshes": [{"file": "meshes/solid.ply",
        "transform": {"rotate": {"axis": [1, 0, 0], "degrees": 90}},
        "fit_into": {"min": [10, 0, 0], "max": [11, 1, 1], "align": ["max", "max", "max"]}}]})");
    expectNear(scene.mesh.vertices[4], {10.5, 0, 0});  // (0.5, 0, 1) -> (0.5, -1, 0) -> +(10, 1, 0)
    expectNear(scene.mesh.vertices[2], {11, 1, 1});    // (1, 1, 0) -> (1, 0, 1) -> +(10, 1, 0)
}

TEST_F(SceneFile, MatrixAndTransformSequences) {
    const Scene m = load(R"({"meshes": [{"file": "meshes/solid.ply",
        "transform": {"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]}}]})");
    expectNear(m.mesh.vertices[1], {1, 3, 3});
    expectNear(m.mesh.vertices[2], {0, 3, 3});
    const Scene s = load(R"({"meshes": [{"file": "meshes/solid.ply",
        "transform": [{"translate": [1, 0, 0]}, {"scale": 2}]}]})");
    expectNear(s.mesh.vertices[1], {4, 0, 0});
    expectNear(s.mesh.vertices[3], {2, 2, 0});
    // A mirror through a matrix also reverses the faces.
    const Scene r = load(R"({"meshes": [{"file": "meshes/solid.ply",
        "transform": {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, -1, 0], [0, 0, 0, 1]]}}]})");
    EXPECT_EQ(r.mesh.faces[0], (std::vector<uint32_t>{0, 3, 2, 1}));
    EXPECT_LT(r.mesh.faceAreaNormal(0).z, 0);  // the square now lies under its mirrored apex
}

TEST_F(SceneFile, MaterialOverridesByNameAndPolygons) {
    write("meshes/lamp.obj", "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl glow\nf 1 2 3\n");
    write("meshes/lamp.mtl", "newmtl glow\nKd 0.1 0.2 0.3\nKe 1 1 1\n");
    const Scene scene = load(R"({
      "meshes": [{"file": "meshes/lamp.obj", "materials": {"glow": {"ke": [5, 6, 7]}}},
                 {"file": "meshes/lamp.obj"}],
      "polygons": [{"vertices": [[0, 0, -1], [2, 0, -1], [2, 2, -1], [0, 2, -1]],
                    "material": {"kd": 0.25}}]
    })");
    ASSERT_EQ(scene.materials.size(), 3u);
    EXPECT_EQ(scene.materials[0].name, "glow");
    EXPECT_EQ(scene.materials[0].ke, Vec3(5, 6, 7));
    EXPECT_EQ(scene.materials[0].kd, Vec3(0.1, 0.2, 0.3));  // kept
    EXPECT_EQ(scene.materials[1].name, "glow_2");           // made unique
    EXPECT_EQ(scene.materials[1].ke, Vec3(1, 1, 1));
    EXPECT_EQ(scene.materials[2].kd, Vec3(0.25, 0.25, 0.25));
    EXPECT_EQ(scene.lights, (std::vector<uint32_t>{0, 1}));  // the OBJ's own lights stay lights
    EXPECT_EQ(scene.faceMaterial, (std::vector<int32_t>{0, 1, 2}));
}

TEST_F(SceneFile, DegenerateFacesDroppedUnlessStrictOrRefusedOnRequest) {
    write("meshes/deg.ply",
          "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
          "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0\n1 0 0\n0 1 0\n2 0 0\n3 0 1 2\n3 0 1 3\n");
    const auto expectDropped = [&](const std::string& json) {
        SCOPED_TRACE(json);
        const Scene scene = load(json);
        EXPECT_EQ(scene.faceCount(), 1u);
        EXPECT_EQ(scene.mesh.faces[0], (std::vector<uint32_t>{0, 1, 2}));
        ASSERT_EQ(scene.warnings.size(), 1u);
        EXPECT_NE(scene.warnings[0].find("scene.json: meshes[0]: "), std::string::npos)
            << scene.warnings[0];
        EXPECT_NE(scene.warnings[0].find("deg.ply: dropped 1 degenerate"), std::string::npos)
            << scene.warnings[0];
    };
    // Repair mode by default; "drop_degenerate_faces": true drops them even when strict.
    expectDropped(R"({"meshes": [{"file": "meshes/deg.ply"}]})");
    expectDropped(R"({"meshes": [{"file": "meshes/deg.ply", "drop_degenerate_faces": true}]})");
    expectDropped(R"({"strict": true,
                      "meshes": [{"file": "meshes/deg.ply", "drop_degenerate_faces": true}]})");
    expectDropped(R"({"strict": true, "meshes": [{"file": "meshes/deg.ply", "strict": false}]})");
    // Refused: the file's "strict", the entry's, "drop_degenerate_faces": false, the caller's.
    for (const char* json :
         {R"({"strict": true, "meshes": [{"file": "meshes/deg.ply"}]})",
          R"({"meshes": [{"file": "meshes/deg.ply", "strict": true}]})",
          R"({"meshes": [{"file": "meshes/deg.ply", "drop_degenerate_faces": false}]})"})
        expectError(json, {"meshes[0]", "deg.ply", "face 1", "degenerate"});
    const fs::path p = write("scene.json", R"({"meshes": [{"file": "meshes/deg.ply"}]})");
    expectLoadError([&] { loadJsonScene(p, LoadOptions::strictMode()); }, p,
                    {"meshes[0]", "face 1", "degenerate"});
    expectError(R"({"strict": 1, "meshes": [{"file": "meshes/deg.ply"}]})",
                {"strict: expected true or false"});
}

TEST_F(SceneFile, MissingMaterialsRepairedUnlessStrict) {
    // The default material keeps the usemtl's name, so the scene can give it colours.
    write("meshes/m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl Default\nf 1 2 3\n");
    const Scene scene = load(R"({"meshes": [{"file": "meshes/m.obj",
                                             "materials": {"Default": {"kd": 0.3}}}]})");
    ASSERT_EQ(scene.materials.size(), 1u);
    EXPECT_EQ(scene.materials[0].name, "Default");
    EXPECT_EQ(scene.materials[0].kd, Vec3(0.3, 0.3, 0.3));
    EXPECT_EQ(scene.faceMaterial, (std::vector<int32_t>{0}));
    ASSERT_EQ(scene.warnings.size(), 1u);
    EXPECT_NE(scene.warnings[0].find("meshes[0]: "), std::string::npos) << scene.warnings[0];
    EXPECT_NE(scene.warnings[0].find("m.obj: usemtl 'Default' on line 4 names no material (no "
                                     "mtllib): 1 face uses a default diffuse material"),
              std::string::npos)
        << scene.warnings[0];
    // "drop_degenerate_faces" decides faces only: the materials stay strict.
    expectError(R"({"strict": true, "meshes": [{"file": "meshes/m.obj",
                                                "drop_degenerate_faces": true}]})",
                {"meshes[0]", "m.obj:4: usemtl: unknown material 'Default'"});
}

// A file that is not there is its own kind of error, naming the file: a mesh a JSON scene names
// (the bench skips such a scene on it, app/cli/bench/bench_command.cpp) or the scene file itself.
// A malformed scene, or a mesh path naming a directory, is an Invalid one.
TEST_F(SceneFile, AMissingFileIsItsOwnKindOfError) {
    auto errorOf = [](const fs::path& p) -> SceneError {
        try {
            loadScene(p);  // through the loader, as the commands and the bench load
        } catch (const SceneError& e) {
            return e;
        }
        ADD_FAILURE() << p << " loaded";
        return SceneError("", 0, "");
    };
    const SceneError mesh =
        errorOf(write("scene.json", R"({"meshes": [{"file": "meshes/none.ply"}]})"));
    EXPECT_EQ(mesh.kind, SceneError::Kind::MissingFile) << mesh.what();
    EXPECT_EQ(fs::path(mesh.missingFile), dir_ / "meshes" / "none.ply");
    EXPECT_NE(mesh.message.find("meshes[0].file: no such file: "), std::string::npos)
        << mesh.what();
    const SceneError scene = errorOf(dir_ / "none.json");
    EXPECT_EQ(scene.kind, SceneError::Kind::MissingFile) << scene.what();
    EXPECT_EQ(fs::path(scene.missingFile), dir_ / "none.json");

    fs::create_directories(dir_ / "meshes" / "folder.ply");
    for (const char* json :
         {R"({"meshes": [{"file": "meshes/solid.ply", "transform": {"scale": "big"}}]})",
          R"({"meshes": [{"file": "meshes/folder.ply"}]})", R"({"meshes": [)"}) {
        const SceneError e = errorOf(write("scene.json", json));
        EXPECT_EQ(e.kind, SceneError::Kind::Invalid) << e.what();
        EXPECT_TRUE(e.missingFile.empty()) << e.what();
    }
}

TEST_F(SceneFile, ErrorsNameTheJsonPath) {
    {
        const fs::path p =
            write("scene.json",
                  R"({"meshes": [{"file": "meshes/solid.ply", "transform": {"scale": "big"}}]})");
        try {
            loadJsonScene(p);
            ADD_FAILURE() << "no error";
        } catch (const SceneError& e) {
            EXPECT_EQ(std::string(e.what()),
                      p.string() + ": meshes[0].transform.scale: expected a number or 3 numbers");
        }
    }
    expectError(R"({"meshes": [{"fille": "meshes/solid.ply"}]})",
                {"meshes[0]", "unknown key \"fille\""});
    expectError(R"({"meshes": [{"file": "meshes/none.ply"}]})", {"meshes[0].file", "no such file"});
    expectError(R"({"meshes": [{"file": "meshes/solid.ply", "transform": {"scale": 0}}]})",
                {"singular"});
    expectError(R"({"meshes": [{"file": "meshes/solid.ply", "materials": {"nope": {}}}]})",
                {"meshes[0].materials.nope", "no material named"});
    expectError(R"({"meshes": [{"file": "other.json"}]})", {"meshes[0].file"});
    expectError(
        R"({"meshes": [{"file": "meshes/solid.ply", "transform": {"matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]}}]})",
        {"meshes[0].transform.matrix[3]", "affine"});
    expectError(
        R"({"area_lights": [{"vertices": [[0,0,0],[1,0,0],[1,1,0.5],[0,1,0]], "emission": 1}]})",
        {"area_lights[0]", "non-planar"});
    expectError(R"({"area_lights": [{"vertices": [[0,0,0],[1,0,0],[1,1,0]], "emission": 0}]})",
                {"area_lights[0].emission", "nonzero"});
    expectError(
        R"({"area_lights": [{"vertices": [[0,0,0],[1,0,0],[1,1,0]], "emission": [1, -1, 1]}]})",
        {"area_lights[0].emission", "non-negative"});
    expectError(R"({"camera": {"eye": [0,0,0], "target": [0,0,0]}, "polygons": []})", {"camera"});
    expectError(R"({"polygons": [{"vertices": [[0,0,0],[1,0,0]]}]})", {"polygons[0].vertices"});
    expectError(R"({"polygons": [{"vertices": [[0,0,0],[1,0,0],[1,"x",0]]}]})",
                {"polygons[0].vertices[2][1]", "expected a number"});
    expectError(R"({})", {"no faces"});
    expectError(R"([1, 2])", {"expected a JSON object"});
    // A mesh file's own error is passed on under the entry's path.
    write("meshes/bent.ply",
          "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
          "0 0 0\n1 0 0\n1 1 0.2\n0 1 0\n4 0 1 2 3\n");
    expectError(R"({"strict": true, "meshes": [{"file": "meshes/bent.ply"}]})",
                {"meshes[0]", "bent.ply", "face 0", "non-planar"});
}

TEST_F(SceneFile, SyntaxErrorGivesTheLine) {
    const fs::path p = write("scene.json", "{\n  \"meshes\": [\n    {\"file\": ,}\n  ]\n}\n");
    try {
        loadJsonScene(p);
        ADD_FAILURE() << "no error";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.file, p.string());
        EXPECT_EQ(e.line, 3) << e.what();
        EXPECT_NE(std::string(e.what()).find("JSON syntax error"), std::string::npos) << e.what();
    }
}

TEST_F(SceneFile, LoadSceneDispatchesJson) {
    const fs::path p = write("Scene.JSON", R"({"meshes": [{"file": "meshes/solid.ply"}]})");
    EXPECT_EQ(loadScene(p).faceCount(), 2u);
}

}  // namespace
}  // namespace penumbra
