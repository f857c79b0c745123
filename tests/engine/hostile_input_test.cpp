// The defects of hostile input that once took the program down or printed a wrong answer with
// exit status 0, each reproduced: coordinates beyond the contract in every format, PLY headers
// that made OpenMesh loop forever, a JSON number beyond the double range, and non-finite numbers
// at the output boundary.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "engine/io/finite_output.h"
#include "engine/io/image_io.h"
#include "engine/io/scene_loader.h"
#include "engine/render/renderer.h"
#include "engine/scene/scene_validation.h"
#include "tests/support/answer_check.h"
#include "tests/support/loader_test_support.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

class HostileInput : public test::LoaderFiles {
  protected:
    // Loading `bytes` as `name` fails with a SceneError about that file whose message has every
    // one of `needles`.
    void refused(const std::string& name, const std::string& bytes,
                 std::initializer_list<const char*> needles, const LoadOptions& options = {}) {
        const fs::path p = write(name, bytes);
        try {
            (void)loadScene(p, options);
            ADD_FAILURE() << name << ": loaded";
        } catch (const SceneError& e) {
            EXPECT_EQ(e.file, p.string()) << e.what();
            for (const char* n : needles)
                EXPECT_NE(std::string(e.what()).find(n), std::string::npos)
                    << name << ": '" << n << "' not in: " << e.what();
        }
    }
};

const char* kMtl = "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKe 10 10 10\n";

std::string objWithVertex(const std::string& coordinate) {
    return "mtllib s.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv " + coordinate +
           " 0 0\nv 0 0 1\nv 0 1 1\nusemtl white\nf 1 2 3\nf 4 5 6\n";
}

TEST_F(HostileInput, CoordinatesBeyondTheContractAreRefusedInEveryFormat) {
    write("s.mtl", kMtl);
    // The reproducers: an OFF vertex at 1e20, an OBJ at 1e18 (Embree aborts from about 1.8e18).
    refused("big.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n99999999999999999999 0 0\n3 0 1 3\n",
            {"vertex 3", "2^59"});
    refused("big.obj", objWithVertex("1e18"), {"vertex 3", "beyond the supported magnitude"});
    refused("nan.obj", objWithVertex("-1e300"), {"vertex 3", "2^59"});
    // A JSON scene whose area light has a vertex at -2^63 - 1.
    refused("big.json",
            R"({"polygons": [{"vertices": [[0,0,0],[1,0,0],[1,1,0]]}],
                "area_lights": [{"vertices": [[0,0,2],[-9223372036854775809,1,2],[1,0,2]],
                                 "emission": 5}]})",
            {"2^59"});
    // An ASCII STL and a PLY vertex.
    refused("big.stl",
            "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e19 0 0\n"
            "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n",
            {"2^59"});
    refused("big.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
            "property double z\nelement face 1\nproperty list uchar int vertex_indices\n"
            "end_header\n0 0 0\n1e155 0 0\n0 1 0\n3 0 1 2\n",
            {"vertex 1", "2^59"});
    // Inside the contract: loads.
    const fs::path ok = write("ok.obj", objWithVertex("1e17"));
    EXPECT_NO_THROW((void)loadScene(ok));
    EXPECT_FALSE(coordinateProblem({0x1p59, -0x1p59, 1e-300}).has_value());
    EXPECT_TRUE(coordinateProblem({std::nextafter(0x1p59, 1e300), 0, 0}).has_value());
    EXPECT_TRUE(coordinateProblem({0, std::numeric_limits<double>::quiet_NaN(), 0}).has_value());
}

// An area light thinner than its coordinates resolve (a fragment's rounding would exceed it) is
// refused naming the face, in OBJ and in a JSON scene; a long thin light that doubles do resolve
// loads, and its answer keeps its fraction within [0, 1] up to the rounding the rule bounds.
TEST_F(HostileInput, LightsThinnerThanDoublesResolveAreRefused) {
    write("s.mtl", kMtl);
    // The fuzzed glb's light as an OBJ: 2 units long, area 6e-39, whose edge vectors from its
    // first vertex round to the same vector: its area rounds to zero.
    // A face whose area rounds to zero is degenerate: refused in strict mode, dropped (with the
    // light it was) in repair mode.
    const std::string sliver =
        "mtllib s.mtl\nv -2 0 -2\nv 2 0 -2\nv 0 0 2\n"
        "v -0.5 -1.99969482421875 -0.50001519918441772\nv 0 2 1.7540579766176321e-38\n"
        "v 5.4182942733214815e-39 2 5.6051938572992683e-45\nusemtl white\nf 1 3 2\n"
        "usemtl lamp\nf 4 5 6\n";
    refused("sliver.obj", sliver, {"face 1", "its area rounds to zero"}, LoadOptions::strictMode());
    const Scene repaired = loadScene(write("sliver.obj", sliver));
    EXPECT_EQ(repaired.faceCount(), 1u);
    EXPECT_TRUE(repaired.lights.empty());
    ASSERT_EQ(repaired.warnings.size(), 1u);
    EXPECT_NE(repaired.warnings[0].find("dropped 1 degenerate"), std::string::npos)
        << repaired.warnings[0];
    EXPECT_NE(repaired.warnings[0].find("its area rounds to zero"), std::string::npos)
        << repaired.warnings[0];
    refused("sliver.json",
            R"({"polygons": [{"vertices": [[-2,0,-2],[0,0,2],[2,0,-2]]}],
                "area_lights": [{"vertices": [[0,3,0],[1e-30,3,1e-30],[1000,3,1e-30]],
                                 "emission": 5}]})",
            {"face 1", "2^-40"});
    // Long and thin but resolved: 1000 by 1e-6, at 1e3 from the origin.
    const fs::path ok = write("thin.obj",
                              "mtllib s.mtl\nv -2 0 -2\nv 2 0 -2\nv 0 0 2\n"
                              "v 1000 3 0\nv 1000 3 1e-6\nv 2000 3 1e-6\nv 2000 3 0\n"
                              "usemtl white\nf 1 3 2\nusemtl lamp\nf 4 5 6 7\n");
    const Scene scene = loadScene(ok);
    ASSERT_EQ(scene.lights.size(), 1u);
    EXPECT_FALSE(
        lightAreaProblem(scene.mesh, scene.lights[0], scene.mesh.bounds().diagonal()).has_value());
    EXPECT_FALSE(test::answerProblem(scene).has_value()) << *test::answerProblem(scene);
}

TEST_F(HostileInput, PlyHeadersThatHungTheReaderAreRefused) {
    const std::string body =
        "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    for (const char* version : {"x", "nan", "1e309", "1", "2.0"})
        refused("v.ply", std::string("ply\nformat ascii ") + version + "\n" + body,
                {"v.ply:2:", "format version"});
    // A second format line, counts that cannot fit, an element with no properties.
    refused("f.ply", "ply\nformat ascii 1.0\nformat binary_little_endian 1.0\n" + body,
            {"second format line"});
    refused("c.ply",
            "ply\nformat ascii 1.0\nelement vertex 99999999999\nproperty float x\n"
            "property float y\nproperty float z\nend_header\n0 0 0\n",
            {"cannot fit"});
    refused("e.ply", "ply\nformat ascii 1.0\nelement junk 1000\n" + body, {"no properties"});
    refused("p.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float x\n"
            "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n",
            {"declared twice"});
    refused("y.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float z\n"
            "end_header\n0 0\n1 0\n0 1\n",
            {"x, y and z"});
}

TEST_F(HostileInput, JsonNumberBeyondTheDoubleRangeNamesItsPath) {
    refused("n.json",
            "{\"polygons\": [{\"vertices\": [[0,0,0],[1,0,0],\n[1,1e309,0]]}],\n"
            "\"area_lights\": []}",
            {"n.json:2:", "polygons[0].vertices[2][1]", "1e309", "beyond the range of a double"});
    refused("m.json", "{\"camera\": {\"fov_y\": -1e999}}", {"camera.fov_y", "-1e999"});
}

TEST(FiniteOutput, NonFiniteNumbersNeverLeave) {
    nlohmann::json j = {{"lights", {{{"fraction", 0.5}}, {{"fraction", std::nan("")}}}}};
    try {
        requireFinite(j, "the answer");
        ADD_FAILURE() << "accepted a NaN";
    } catch (const NonFiniteOutput& e) {
        EXPECT_NE(std::string(e.what()).find("lights[1].fraction"), std::string::npos) << e.what();
    }
    j["lights"][1]["fraction"] = 0.25;
    EXPECT_NO_THROW(requireFinite(j, "the answer"));
    j["x"] = std::numeric_limits<double>::infinity();
    EXPECT_THROW(requireFinite(j, "the answer"), NonFiniteOutput);
    // Images: a film with a NaN pixel is not written.
    Film film;
    film.reset(2, 2);
    film.passes = 1;
    film.sum[3] = {0, std::nan(""), 0};
    const std::string path = (fs::temp_directory_path() / "penumbra_nan.pfm").string();
    EXPECT_THROW(writePfm(film, path), NonFiniteOutput);
    EXPECT_THROW(writePng(film, path + ".png"), NonFiniteOutput);
    EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace penumbra
