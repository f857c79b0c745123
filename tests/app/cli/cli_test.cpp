// Tests of the point queries (engine/precompute/point_query.h) and of the `penumbra` executable,
// run as a real process (its path comes from the PENUMBRA_EXE compile definition).
//
// The test scene (y is "sideways", z is "up"):
//   face 0  floor    [-2,2]^2 at z=0, facing +z
//   face 1  light    [-0.5,0.5]^2 at z=2, facing -z (material "lamp", Ke 10 10 10)
//   face 2  blocker  [0,1]x[-0.5,0.5] at z=1, facing -z
//   face 3  ceiling  [-2,2]^2 at z=3, facing -z (behind the light)
// Seen from the origin, the blocker's edge x=0 (at z=1) lies in the plane x=0 through the origin
// and the light's middle line, and the blocker spans x in [0,1], y in [-0.5,0.5] at half the
// light's height: its shadow cone from the origin covers x in [0,2], y in [-1,1] at z=2, which
// holds the whole half x >= 0 of the light and nothing of the half x < 0. So exactly half of the
// light is visible (the fragment [-0.5,0]x[-0.5,0.5], whose corners are exact doubles), and by
// symmetry about x=0 the form factor is exactly half the unoccluded one.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "engine/io/obj_io.h"
#include "engine/precompute/point_query.h"
#include "tests/support/closed_forms.h"
#include "tests/support/exact_reference.h"
#include "tests/support/run_penumbra.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::ProcessResult;
using test::runPenumbra;

const char* kSceneObj =
    "mtllib scene.mtl\n"
    "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"                  // floor
    "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"  // light
    "v 0 -0.5 1\nv 0 0.5 1\nv 1 0.5 1\nv 1 -0.5 1\n"            // blocker
    "v -2 -2 3\nv -2 2 3\nv 2 2 3\nv 2 -2 3\n"                  // ceiling
    "usemtl white\nf 1 2 3 4\n"
    "usemtl lamp\nf 5 6 7 8\n"
    "usemtl white\nf 9 10 11 12\n"
    "f 13 14 15 16\n";
const char* kSceneMtl =
    "newmtl white\nKd 0.8 0.8 0.8\n"
    "newmtl lamp\nKd 0 0 0\nKe 10 10 10\n";

using test::cornerFormFactor;

// ---- the executable -----------------------------------------------------------------------------

std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

class CliTest : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("penumbra_cli_test_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        write("scene.obj", kSceneObj);
        write("scene.mtl", kSceneMtl);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }

    fs::path path(const std::string& name) const { return dir_ / name; }
    std::string scene() const { return path("scene.obj").string(); }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name), std::ios::binary) << text;
    }

    // Runs a query expected to succeed with one output line, and returns its JSON.
    json queryOne(const std::vector<std::string>& args) const {
        const ProcessResult r = runPenumbra(args);
        EXPECT_EQ(r.exitCode, 0) << r.err;
        EXPECT_EQ(r.err, "");
        const std::vector<std::string> out = lines(r.out);
        EXPECT_EQ(out.size(), 1u) << r.out;
        return out.empty() ? json() : json::parse(out.front());
    }

    // Expects a clean failure: the exit code, nothing on stdout, one "penumbra: error: " message
    // containing every one of `keywords`.
    void expectError(const std::vector<std::string>& args, int exitCode,
                     const std::vector<std::string>& keywords) const {
        const ProcessResult r = runPenumbra(args);
        EXPECT_EQ(r.exitCode, exitCode) << r.err;
        EXPECT_EQ(r.out, "");
        EXPECT_EQ(r.err.rfind("penumbra: error: ", 0), 0u) << r.err;
        for (const std::string& k : keywords) EXPECT_NE(r.err.find(k), std::string::npos) << r.err;
    }

  private:
    fs::path dir_;
};

TEST_F(CliTest, HalfBlockedLightGivesFractionOneHalf) {
    const json j = queryOne({"query", scene(), "--point", "0,0,0"});
    ASSERT_TRUE(j.is_object()) << j.dump();
    EXPECT_EQ(j["point"], json::array({0.0, 0.0, 0.0}));
    EXPECT_EQ(j["face"], 0);
    ASSERT_EQ(j["lights"].size(), 1u);
    const json& l = j["lights"][0];
    EXPECT_EQ(l["light"], 0);
    EXPECT_EQ(l["light_face"], 1);
    EXPECT_EQ(l["pair"], "penumbra");
    EXPECT_NEAR(l["light_area"].get<double>(), 1.0, 1e-12);
    EXPECT_NEAR(l["visible_area"].get<double>(), 0.5, 1e-12);
    EXPECT_NEAR(l["fraction"].get<double>(), 0.5, 1e-12);
    const double unoccluded = 4 * cornerFormFactor(0.5, 0.5, 2);
    EXPECT_NEAR(l["unoccluded_form_factor"].get<double>(), unoccluded, 1e-12);
    EXPECT_NEAR(l["form_factor"].get<double>(), unoccluded / 2, 1e-12);
    EXPECT_GT(l["nodes_visited"].get<int>(), 0);
    EXPECT_EQ(l["path"].size(), l["nodes_visited"].get<size_t>());
    // Every fragment vertex lies in the light's plane z=2 and within the light's square; the
    // visible part is x <= 0.
    ASSERT_FALSE(l["fragments"].empty());
    double area = 0;
    for (const json& fragment : l["fragments"]) {
        ASSERT_GE(fragment.size(), 3u);
        std::vector<Vec3> polygon;
        for (const json& v : fragment) {
            ASSERT_EQ(v.size(), 3u);
            const Vec3 p{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
            EXPECT_NEAR(p.z, 2.0, 1e-12);
            EXPECT_LE(p.x, 1e-12);
            EXPECT_GE(p.x, -0.5 - 1e-12);
            EXPECT_LE(std::fabs(p.y), 0.5 + 1e-12);
            polygon.push_back(p);
        }
        for (size_t i = 0; i < polygon.size(); ++i) {  // shoelace in the xy plane
            const Vec3& a = polygon[i];
            const Vec3& b = polygon[(i + 1) % polygon.size()];
            area += 0.5 * (a.x * b.y - b.x * a.y);
        }
    }
    EXPECT_NEAR(std::fabs(area), 0.5, 1e-12);
    // The outline of the visible region: the rectangle [-0.5, 0] x [-0.5, 0.5] at z = 2, one loop
    // of four edges, whatever pieces the query cut it into; its contour integral is the form
    // factor.
    const json& outline = l["outline"];
    ASSERT_EQ(outline["loops"].size(), 1u);
    EXPECT_EQ(outline["edges"], 4);
    for (const json& v : outline["loops"][0]) {
        const Vec3 p{v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
        EXPECT_NEAR(p.z, 2.0, 1e-12);
        EXPECT_TRUE(std::fabs(p.x) <= 1e-12 || std::fabs(p.x + 0.5) <= 1e-12) << v.dump();
        EXPECT_NEAR(std::fabs(p.y), 0.5, 1e-12) << v.dump();
    }
    EXPECT_NEAR(outline["form_factor"].get<double>(), unoccluded / 2, 1e-12);
}

TEST_F(CliTest, OnlyLightAndExplicitFace) {
    const json j = queryOne({"query", scene(), "--point=0.3,0.2,0", "--face", "0", "--light", "0"});
    ASSERT_EQ(j["lights"].size(), 1u);
    // From (0.3, 0.2, 0) the blocker's edge x=0 at z=1 projects to x=-0.3 on the light.
    EXPECT_NEAR(j["lights"][0]["fraction"].get<double>(), 0.2, 1e-12);
}

TEST_F(CliTest, PointsFilePrintsOneLinePerPoint) {
    write("points.txt",
          "# x y z [face]\n"
          "0 0 0\n"
          "\n"
          "  0.3 0.2 0   # a comment\n"
          "-1 -1 0 0\n"
          "0 0 3\r\n");
    const ProcessResult r =
        runPenumbra({"query", scene(), "--points", path("points.txt").string()});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const std::vector<std::string> out = lines(r.out);
    ASSERT_EQ(out.size(), 4u) << r.out;
    const int faces[] = {0, 0, 0, 3};
    const double fractions[] = {0.5, 0.2, 1.0, 0.0};
    for (size_t i = 0; i < out.size(); ++i) {
        const json j = json::parse(out[i]);
        EXPECT_EQ(j["face"], faces[i]) << out[i];
        EXPECT_NEAR(j["lights"][0]["fraction"].get<double>(), fractions[i], 1e-12) << out[i];
    }
}

TEST_F(CliTest, PointBehindTheLightGetsNothing) {
    // (0, 0, 3) is on the ceiling, behind the light's plane z=2 (the light faces -z).
    const json j = queryOne({"query", scene(), "--point", "0,0,3"});
    EXPECT_EQ(j["face"], 3);
    const json& l = j["lights"][0];
    EXPECT_EQ(l["fraction"].get<double>(), 0.0);
    EXPECT_EQ(l["visible_area"].get<double>(), 0.0);
    EXPECT_EQ(l["form_factor"].get<double>(), 0.0);
    EXPECT_EQ(l["unoccluded_form_factor"].get<double>(), 0.0);
    EXPECT_TRUE(l["fragments"].empty());
    EXPECT_TRUE(l["outline"]["loops"].empty());
    EXPECT_EQ(l["outline"]["form_factor"].get<double>(), 0.0);
    EXPECT_NEAR(l["light_area"].get<double>(), 1.0, 1e-12);
}

// A point a rounding behind its face's plane is answered from the face's front side, some ulps
// away, and says so. Here a wall sunk into the floor stands between the point and a light that the
// floor's plane cuts: seen from the point as given, 1e-9 under the floor, the lines that pass
// under the wall's chord on the floor's plane reach a sliver of the light along the floor, under
// the wall's shadow, which becomes a hole (the exact reference's two boundary loops); from the
// front side the shadow reaches the light's clipped edge (one loop).
TEST_F(CliTest, PointBehindItsFacesPlaneIsAnsweredFromItsFrontSide) {
    const char* obj =
        "mtllib scene.mtl\n"
        "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"                              // floor
        "v 1.5 -0.5 -0.5\nv 1.5 -0.5 1\nv 1.5 0.5 1\nv 1.5 0.5 -0.5\n"          // light, facing -x
        "v 0.75 -0.2 -0.2\nv 0.75 0.2 -0.2\nv 0.75 0.2 0.3\nv 0.75 -0.2 0.3\n"  // sunk wall
        "usemtl white\nf 1 2 3 4\n"
        "usemtl lamp\nf 5 6 7 8\n"
        "usemtl white\nf 9 10 11 12\n";
    write("sunk.obj", obj);
    const Scene scene = loadObjFromString(obj, kSceneMtl, "sunk.obj");
    const Vec3 given{0.1, 0.05, -1e-9};
    const json j = queryOne({"query", path("sunk.obj").string(), "--point=0.1,0.05,-1e-9"});
    EXPECT_EQ(j["face"], 0);
    EXPECT_EQ(j["point"], json::array({given.x, given.y, given.z}));
    ASSERT_TRUE(j.contains("answered_point")) << j.dump();
    const json& a = j["answered_point"];
    const Vec3 answered{a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
    // Strictly in front of the floor's plane (exact), on the floor within some ulps.
    EXPECT_EQ(vis::orientSign(scene.mesh.vertices[0], scene.mesh.vertices[1],
                              scene.mesh.vertices[2], answered),
              vis::Sign::Positive);
    EXPECT_EQ(answered.x, given.x);
    EXPECT_EQ(answered.y, given.y);
    EXPECT_GT(answered.z, 0.0);
    EXPECT_LT(answered.z, 1e-15);
    const test::ReferenceResult asGiven = test::exactReference(scene.mesh, 0, 1, given);
    const test::ReferenceResult ref = test::exactReference(scene.mesh, 0, 1, answered);
    EXPECT_EQ(asGiven.boundaryLoops, 2);
    EXPECT_EQ(ref.boundaryLoops, 1);
    const json& l = j["lights"][0];
    EXPECT_NEAR(l["fraction"].get<double>(), ref.fraction, 1e-12);
    EXPECT_NEAR(l["form_factor"].get<double>(), ref.formFactor, 1e-12);
    EXPECT_EQ(l["outline"]["loops"].size(), 1u) << l["outline"].dump();
    // A point on or in front of its face's plane is answered as given.
    const json on = queryOne({"query", path("sunk.obj").string(), "--point=0.1,0.05,0"});
    EXPECT_FALSE(on.contains("answered_point")) << on.dump();
    EXPECT_NEAR(on["lights"][0]["fraction"].get<double>(),
                test::exactReference(scene.mesh, 0, 1, {0.1, 0.05, 0}).fraction, 1e-12);
}

TEST_F(CliTest, MissingSceneFile) {
    const std::string missing = path("no_such_scene.obj").string();
    expectError({"query", missing, "--point", "0,0,0"}, 1, {missing});
}

TEST_F(CliTest, UnknownSceneFormat) {
    write("scene.fbx", "ply\n");
    expectError({"query", path("scene.fbx").string(), "--point", "0,0,0"}, 1,
                {".fbx", ".obj", ".ply", ".gltf", ".json"});
    // A known format with a malformed file is an input error too, naming the file.
    write("scene.ply", "ply\n");
    expectError({"query", path("scene.ply").string(), "--point", "0,0,0"}, 1,
                {"scene.ply", "end_header"});
}

TEST_F(CliTest, MalformedSceneIsAnInputError) {
    write("broken.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n");
    expectError({"query", path("broken.obj").string(), "--point", "0,0,0"}, 1, {"broken.obj:3"});
}

// The test scene with what other tools repair: a degenerate face after the floor (line 20) and a
// usemtl naming no material (line 25) for the ceiling.
const char* kRepairObj =
    "mtllib scene.mtl\n"
    "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"                  // lines 2-5
    "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"  // 6-9
    "v 0 -0.5 1\nv 0 0.5 1\nv 1 0.5 1\nv 1 -0.5 1\n"            // 10-13
    "v -2 -2 3\nv -2 2 3\nv 2 2 3\nv 2 -2 3\n"                  // 14-17
    "usemtl white\nf 1 2 3 4\nf 1 2 1\n"                        // 18-20
    "usemtl lamp\nf 5 6 7 8\n"                                  // 21-22
    "usemtl white\nf 9 10 11 12\n"                              // 23-24
    "usemtl wood\nf 13 14 15 16\n";                             // 25-26

TEST_F(CliTest, RepairsAreWarningsAndTheRepairedMeshIsQueried) {
    write("repair.obj", kRepairObj);
    const std::string file = path("repair.obj").string();
    const ProcessResult r = runPenumbra({"query", file, "--point", "0,0,0"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    const std::vector<std::string> err = lines(r.err);
    ASSERT_EQ(err.size(), 2u) << r.err;
    EXPECT_EQ(err[0], "penumbra: warning: " + file +
                          ": usemtl 'wood' on line 25 names no material (2 materials defined): 1 "
                          "face uses a default diffuse material");
    EXPECT_EQ(err[1].rfind("penumbra: warning: " + file + ": dropped 1 degenerate", 0), 0u)
        << err[1];
    EXPECT_NE(err[1].find("(first: face 1, line 20: "), std::string::npos) << err[1];
    // Faces are the repaired mesh's: the light, the file's face 2, is face 1.
    const std::vector<std::string> out = lines(r.out);
    ASSERT_EQ(out.size(), 1u) << r.out;
    const json j = json::parse(out[0]);
    EXPECT_EQ(j["face"], 0);
    EXPECT_EQ(j["source_line"], 19);  // the face's line in the file
    ASSERT_EQ(j["lights"].size(), 1u);
    EXPECT_EQ(j["lights"][0]["light_face"], 1);
    EXPECT_NEAR(j["lights"][0]["fraction"].get<double>(), 0.5, 1e-12);
    // The blocker, the file's face 3 (line 24), is face 2 of the repaired mesh.
    const ProcessResult b = runPenumbra({"query", file, "--point", "0.5,0,1"});
    ASSERT_EQ(b.exitCode, 0) << b.err;
    const json k = json::parse(lines(b.out).at(0));
    EXPECT_EQ(k["face"], 2);
    EXPECT_EQ(k["source_line"], 24);
}

TEST_F(CliTest, StrictTurnsRepairsIntoErrorsInEveryCommand) {
    write("repair.obj", kRepairObj);
    const std::string file = path("repair.obj").string();
    const std::vector<std::string> degenerate = {file + ":20: face 1: vertex 1 repeated"};
    expectError({"query", file, "--point", "0,0,0", "--strict"}, 1, degenerate);
    expectError({"render", file, "--out", path("x.png").string(), "--size", "8x8", "--strict"}, 1,
                degenerate);
    expectError({"precompute", file, "-o", path("x.pvis").string(), "--strict"}, 1, degenerate);
    EXPECT_FALSE(fs::exists(path("x.png")));
    EXPECT_FALSE(fs::exists(path("x.pvis")));
    // Without the degenerate face, the missing material is the error.
    std::string materials = kRepairObj;
    materials.replace(materials.find("f 1 2 1\n"), 8, "# no face\n");
    write("materials.obj", materials);
    expectError({"query", path("materials.obj").string(), "--point", "0,0,0", "--strict"}, 1,
                {path("materials.obj").string() + ":25: usemtl: unknown material 'wood'"});
    // Every command that loads a scene takes --strict.
    for (const char* command : {"query", "render", "precompute", "view", "screenshot", "bench"}) {
        const ProcessResult help = runPenumbra({command, "--help"});
        EXPECT_EQ(help.exitCode, 0) << command;
        EXPECT_NE(help.out.find("--strict"), std::string::npos) << command << "\n" << help.out;
    }
}

TEST_F(CliTest, MalformedPointIsAUsageError) {
    expectError({"query", scene(), "--point", "1,2"}, 2, {"--point", "'1,2'"});
    expectError({"query", scene(), "--point", "1,2,3,4"}, 2, {"--point"});
    expectError({"query", scene(), "--point", "1,x,3"}, 2, {"--point"});
    expectError({"query", scene(), "--point", "1,nan,3"}, 2, {"--point"});
}

TEST_F(CliTest, PointOnNoFace) {
    expectError({"query", scene(), "--point", "0,0,5"}, 1, {"lies on no face", "(0, 0, 5)"});
}

TEST_F(CliTest, FaceAndLightOutOfRange) {
    expectError({"query", scene(), "--point", "0,0,0", "--face", "4"}, 1, {"--face 4"});
    expectError({"query", scene(), "--point", "0,0,0", "--light", "1"}, 1, {"--light 1"});
    expectError({"query", scene(), "--point", "0,0,0", "--face", "-1"}, 2, {"--face"});
}

TEST_F(CliTest, MalformedPointsFileNamesFileAndLine) {
    write("bad.txt", "0 0 0\n# fine\n1 2\n");
    const std::string file = path("bad.txt").string();
    expectError({"query", scene(), "--points", file}, 1, {file + ":3"});
    write("bad.txt", "0 0 0\n\n0 0 zero\n");
    expectError({"query", scene(), "--points", file}, 1, {file + ":3", "'zero'"});
    write("bad.txt", "0 0 0 9\n");
    expectError({"query", scene(), "--points", file}, 1, {file + ":1", "face 9"});
    write("bad.txt", "0 0 0\n0 0 7\n");
    expectError({"query", scene(), "--points", file}, 1, {file + ":2", "lies on no face"});
    const std::string missing = path("missing.txt").string();
    expectError({"query", scene(), "--points", missing}, 1, {missing});
}

TEST_F(CliTest, CommandLineUsage) {
    expectError({}, 2, {"subcommand"});
    expectError({"frobnicate"}, 2, {"frobnicate"});
    expectError({"query", scene()}, 2, {"--point"});
    expectError({"query", scene(), "--point", "0,0,0", "--points", "p.txt"}, 2, {"--points"});
    expectError({"query", scene(), "--point", "0,0,0", "--no-such-flag"}, 2, {"--no-such-flag"});
    const ProcessResult help = runPenumbra({"query", "--help"});
    EXPECT_EQ(help.exitCode, 0);
    EXPECT_NE(help.out.find("--point"), std::string::npos) << help.out;
    EXPECT_NE(help.out.find("--light"), std::string::npos) << help.out;
    const ProcessResult version = runPenumbra({"--version"});
    EXPECT_EQ(version.exitCode, 0);
    EXPECT_NE(version.out.find("penumbra"), std::string::npos) << version.out;
}

// A scene without lights (a 2 x 2 floor at y = 0 and a tile at y = 0.4 over its corner): every
// command that loads a scene gives it the default light, says so on stderr and in its summary,
// and --no-default-light (one option, on every such command) leaves it unlit. The light, by the
// rule of engine/scene/default_light.h: a 0.5 x 0.5 square centred over the scene, D / 2 above
// its top (D = sqrt(8.16), the bounds' diagonal): the floor's centre sees it whole, with the
// closed form's form factor.
TEST_F(CliTest, DefaultLightInEveryCommandThatLoadsAScene) {
    write("unlit.obj",
          "v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
          "v 0.5 0.4 0.5\nv 0.5 0.4 0.9\nv 0.9 0.4 0.9\nv 0.9 0.4 0.5\n"
          "f 1 2 3 4\nf 5 6 7 8\n");
    const std::string unlit = path("unlit.obj").string();
    const std::string announced =
        "penumbra: warning: " + unlit + " has no lights: added a default area light";
    ProcessResult r = runPenumbra({"query", unlit, "--point", "0,0,0"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.rfind(announced, 0), 0u) << r.err;
    const json j = json::parse(lines(r.out).at(0));
    ASSERT_EQ(j["lights"].size(), 1u) << j.dump();
    EXPECT_EQ(j["lights"][0]["light_face"], 2);
    EXPECT_EQ(j["lights"][0]["pair"], "fully-visible");
    const double f = 4 * cornerFormFactor(0.25, 0.25, std::sqrt(8.16) / 2 + 0.4);
    EXPECT_NEAR(j["lights"][0]["form_factor"].get<double>(), f, 1e-12);
    r = runPenumbra({"query", unlit, "--point", "0,0,0", "--no-default-light"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_TRUE(json::parse(lines(r.out).at(0))["lights"].empty()) << r.out;

    r = runPenumbra({"precompute", unlit, "-o", path("unlit.pvis").string()});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(r.err.rfind(announced, 0), 0u) << r.err;
    EXPECT_NE(r.out.find("3 faces, 1 lights (the default light: the scene has none of its own; "
                         "--no-default-light turns it off)\n"),
              std::string::npos)
        << r.out;
    r = runPenumbra({"precompute", unlit, "-o", path("dark.pvis").string(), "--no-default-light"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("2 faces, 0 lights\n"), std::string::npos) << r.out;

    // The same flag, registered once, in every command that loads a scene.
    for (const char* command : {"query", "render", "precompute", "bench", "view", "screenshot"}) {
        const ProcessResult help = runPenumbra({command, "--help"});
        EXPECT_EQ(help.exitCode, 0) << command;
        EXPECT_NE(help.out.find("--no-default-light"), std::string::npos) << command;
        EXPECT_NE(help.out.find("--strict"), std::string::npos) << command;
    }
}

// A lamp hung above the ceiling instead of below it: it faces the floor, but every
// (receiver patch, light) pair is back-facing (the ceiling, facing down, away from it) or fully
// hidden (the floor, behind the ceiling), which only the precompute's classification knows; it
// says so, naming the light.
TEST_F(CliTest, PrecomputeNamesALightHiddenFromEveryReceiver) {
    // Floor [-2,2]^2 at z = 0 facing up, ceiling [-3,3]^2 at z = 1 facing down, the lamp at z = 2
    // facing down (line 18).
    write("above.obj",
          "mtllib scene.mtl\n"
          "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
          "v -3 -3 1\nv -3 3 1\nv 3 3 1\nv 3 -3 1\n"
          "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"
          "usemtl white\nf 1 2 3 4\nf 5 6 7 8\n"
          "usemtl lamp\nf 9 10 11 12\n");
    const ProcessResult r = runPenumbra({"precompute", path("above.obj").string(), "-o",
                                         path("above.pvis").string(), "--patch-fraction", "0"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
    EXPECT_NE(r.out.find("1 back-facing, 0 fully visible, 1 fully hidden, 0 penumbra"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.err.find("penumbra: warning: " + path("above.obj").string() +
                         ": light 0 (face 2, material 'lamp', line 18) is hidden from every "
                         "receiver: of its 2 (receiver patch, light) pairs 1 are back-facing and "
                         "1 hidden"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("normal points away"), std::string::npos) << "it faces the floor";
    // The lamp below the ceiling lights the floor: no warning.
    write("below.obj",
          "mtllib scene.mtl\n"
          "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
          "v -3 -3 1\nv -3 3 1\nv 3 3 1\nv 3 -3 1\n"
          "v -0.5 -0.5 0.5\nv -0.5 0.5 0.5\nv 0.5 0.5 0.5\nv 0.5 -0.5 0.5\n"
          "usemtl white\nf 1 2 3 4\nf 5 6 7 8\n"
          "usemtl lamp\nf 9 10 11 12\n");
    const ProcessResult b = runPenumbra({"precompute", path("below.obj").string(), "-o",
                                         path("below.pvis").string(), "--patch-fraction", "0"});
    ASSERT_EQ(b.exitCode, 0) << b.err;
    EXPECT_EQ(b.err.find("warning"), std::string::npos) << b.err;
}

// ---- findFaceContaining and queryPoint, directly ------------------------------------------------

Scene testScene() { return loadObjFromString(kSceneObj, kSceneMtl, "scene.obj"); }

TEST(PointQuery, FindsTheFaceOfAPoint) {
    const Scene scene = testScene();
    EXPECT_EQ(findFaceContaining(scene, {0, 0, 0}).face, 0u);
    EXPECT_EQ(findFaceContaining(scene, {-2, 2, 0}).face, 0u);  // a corner
    EXPECT_EQ(findFaceContaining(scene, {0.25, 0, 1}).face, 2u);
    EXPECT_EQ(findFaceContaining(scene, {1.5, 1.5, 3}).face, 3u);
    // Within the tolerance (1e-9 * diagonal) of the plane and of the boundary.
    EXPECT_EQ(findFaceContaining(scene, {0, 0, 1e-12}).face, 0u);
    EXPECT_EQ(findFaceContaining(scene, {2 + 1e-12, 0, 0}).face, 0u);
    // Off every face.
    const FaceLookup none = findFaceContaining(scene, {0, 0, 0.5});
    EXPECT_FALSE(none.ok());
    EXPECT_NE(none.error.find("lies on no face"), std::string::npos) << none.error;
    EXPECT_FALSE(findFaceContaining(scene, {0, 0, 1e-6}).ok());
    EXPECT_FALSE(findFaceContaining(scene, {2.001, 0, 0}).ok());
    EXPECT_FALSE(findFaceContaining(scene, {0, 0, NAN}).ok());
}

TEST(PointQuery, CoplanarFacesPickTheLowestIndexOtherwiseAmbiguous) {
    // A unit quad split along its diagonal into faces 0 and 1; a wall (face 2) standing on the
    // edge x=1 and facing -x; the first triangle again, reversed (face 3), far away at z=5.
    const char* obj =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "v 1 0 1\nv 1 1 1\n"
        "v 0 0 5\nv 1 0 5\nv 1 1 5\n"
        "f 1 2 3\nf 1 3 4\n"
        "f 2 5 6 3\n"
        "f 7 8 9\nf 9 8 7\n";
    const Scene scene = loadObjFromString(obj, "", "split.obj");
    EXPECT_EQ(findFaceContaining(scene, {0.5, 0.5, 0}).face, 0u);  // on the diagonal
    EXPECT_EQ(findFaceContaining(scene, {0.25, 0.75, 0}).face, 1u);
    EXPECT_EQ(findFaceContaining(scene, {0.75, 0.25, 0}).face, 0u);
    EXPECT_EQ(findFaceContaining(scene, {1, 0.5, 0.5}).face, 2u);
    // On the edge where the floor meets the wall: two planes.
    const FaceLookup corner = findFaceContaining(scene, {1, 0.5, 0});
    EXPECT_FALSE(corner.ok());
    EXPECT_EQ(corner.candidates, (std::vector<uint32_t>{0, 2}));
    EXPECT_NE(corner.error.find("ambiguous"), std::string::npos) << corner.error;
    EXPECT_NE(corner.error.find("0 and 2"), std::string::npos) << corner.error;
    // A double-sided triangle: one plane, two orientations.
    const FaceLookup twoSided = findFaceContaining(scene, {0.75, 0.25, 5});
    EXPECT_FALSE(twoSided.ok());
    EXPECT_EQ(twoSided.candidates, (std::vector<uint32_t>{3, 4}));
}

TEST(PointQuery, MatchesTheExactReference) {
    const Scene scene = testScene();
    VisibilityStore::Options options;
    options.patchFraction = 0.0;  // whole faces: one tree per (receiver, light) pair
    VisibilityStore store(scene, nullptr, options);
    const Vec3 points[] = {{0, 0, 0},      {0.3, 0.2, 0}, {-1, -1, 0},
                           {0.7, -1.3, 0}, {1.9, 0.1, 0}, {-0.1, 0.4, 0}};
    for (const Vec3& x : points) {
        SCOPED_TRACE(vis::toString(x));
        const std::vector<LightAtPoint> result = queryPoint(store, 0, x, std::nullopt);
        ASSERT_EQ(result.size(), 1u);
        const LightAtPoint& l = result[0];
        const test::ReferenceResult ref = test::exactReference(scene.mesh, 0, 1, x);
        EXPECT_EQ(l.light, 0u);
        EXPECT_EQ(l.lightFace, 1u);
        EXPECT_NEAR(l.lightArea, 1.0, 1e-12);
        EXPECT_NEAR(l.fraction, ref.fraction, 1e-12);
        EXPECT_NEAR(l.visibleArea, ref.visibleArea, 1e-12);
        EXPECT_NEAR(l.formFactor, ref.formFactor, 1e-12);
        EXPECT_NEAR(l.unoccludedFormFactor, ref.unoccludedFormFactor, 1e-12);
        EXPECT_EQ(l.trace.size(), l.nodesVisited);
        for (const vis::Polygon3& fragment : l.fragments)
            for (const Vec3& v : fragment) EXPECT_NEAR(v.z, 2.0, 1e-12);
    }
    EXPECT_EQ(store.treeCount(), 1u);  // one (receiver, light) pair, built once
}

// The tree-less query (what a click shows at once) against the same reference, on a box
// hierarchy over the faces as EmbreeScene builds it; its work limit is reported, not hidden.
TEST(PointQuery, DirectQueryMatchesTheExactReference) {
    const Scene scene = testScene();
    std::vector<vis::Bounds3> boxes(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) boxes[f] = scene.mesh.faceBounds(f);
    const vis::BoxTree faces(boxes);
    const Vec3 points[] = {{0, 0, 0},      {0.3, 0.2, 0}, {-1, -1, 0},
                           {0.7, -1.3, 0}, {1.9, 0.1, 0}, {-0.1, 0.4, 0}};
    int partlyLit = 0;
    for (const Vec3& x : points) {
        SCOPED_TRACE(vis::toString(x));
        const std::vector<LightAtPoint> result = queryPointDirect(scene, faces, 0, x, std::nullopt);
        ASSERT_EQ(result.size(), 1u);
        const LightAtPoint& l = result[0];
        const test::ReferenceResult ref = test::exactReference(scene.mesh, 0, 1, x);
        EXPECT_FALSE(l.fromTree);
        EXPECT_TRUE(l.complete);
        EXPECT_TRUE(l.trace.empty());
        EXPECT_NEAR(l.fraction, ref.fraction, 1e-12);
        EXPECT_NEAR(l.visibleArea, ref.visibleArea, 1e-12);
        EXPECT_NEAR(l.formFactor, ref.formFactor, 1e-12);
        EXPECT_NEAR(l.unoccludedFormFactor, ref.unoccludedFormFactor, 1e-12);
        partlyLit += ref.fraction > 0 && ref.fraction < 1;
    }
    EXPECT_GE(partlyLit, 2);  // the blocker does cut the light for some of them
    // One plane test allowed: the origin's query (the blocker must be clipped) cannot finish.
    const std::vector<LightAtPoint> limited = queryPointDirect(scene, faces, 0, {0, 0, 0}, 0u, 1);
    EXPECT_FALSE(limited[0].complete);
    EXPECT_THROW(queryPointDirect(scene, faces, 4, {0, 0, 0}, std::nullopt), std::out_of_range);
    EXPECT_THROW(queryPointDirect(scene, faces, 0, {0, 0, 0}, 1u), std::out_of_range);
    // Behind the light, and on the light itself: nothing.
    for (const auto& [face, x] : {std::pair<uint32_t, Vec3>{3, {0, 0, 3}}, {1, {0, 0, 2}}}) {
        const LightAtPoint r = queryPointDirect(scene, faces, face, x, 0u)[0];
        EXPECT_EQ(r.fraction, 0.0);
        EXPECT_TRUE(r.fragments.empty());
    }
}

// The tree-less query with face groups, as the viewer's click and hover run it: a plate of 128
// triangles under half of the light forms a group, which the floor points beneath it take whole;
// their answers against the exact reference, and the same as without the groups.
TEST(PointQuery, DirectQueryWithFaceGroupsMatchesTheExactReference) {
    std::string obj = kSceneObj;
    const int n = 8;  // the plate z = 0.5 over [-1.5, 0] x [-1, 1], facing the floor
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            obj += "v " + std::to_string(-1.5 + 1.5 * i / n) + " " +
                   std::to_string(-1 + 2.0 * j / n) + " 0.5\n";
    auto id = [&](int i, int j) { return std::to_string(17 + j * (n + 1) + i); };
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            obj += "f " + id(i, j) + " " + id(i, j + 1) + " " + id(i + 1, j + 1) + "\n";
            obj += "f " + id(i, j) + " " + id(i + 1, j + 1) + " " + id(i + 1, j) + "\n";
        }
    const Scene scene = loadObjFromString(obj, kSceneMtl, "plate.obj");
    ASSERT_EQ(scene.faceCount(), 4u + 2 * n * n);
    std::vector<vis::Bounds3> boxes(scene.faceCount());
    for (uint32_t f = 0; f < scene.faceCount(); ++f) boxes[f] = scene.mesh.faceBounds(f);
    const vis::BoxTree faces(boxes);
    const vis::FaceClusters groups(scene.mesh, faces);
    int grouped = 0, partlyLit = 0;
    // Beneath the plate, and near the lines x = 0 and x = -2 where its edges cut the light.
    for (const Vec3& x : {Vec3{-0.75, 0, 0}, Vec3{-0.1, 0.3, 0}, Vec3{0.05, -0.6, 0},
                          Vec3{-1.95, 0.9, 0}, Vec3{0.3, 0.2, 0}, Vec3{-0.5, 0.5, 0}}) {
        SCOPED_TRACE(vis::toString(x));
        const LightAtPoint with = queryPointDirect(scene, faces, 0, x, 0u, 0, &groups)[0];
        const LightAtPoint without = queryPointDirect(scene, faces, 0, x, 0u)[0];
        const test::ReferenceResult ref = test::exactReference(scene.mesh, 0, 1, x);
        EXPECT_TRUE(with.complete);
        EXPECT_NEAR(with.fraction, ref.fraction, 1e-12);
        EXPECT_NEAR(with.formFactor, ref.formFactor, 1e-12);
        EXPECT_NEAR(without.formFactor, ref.formFactor, 1e-12);
        EXPECT_EQ(without.faceGroups, 0u);
        grouped += with.faceGroups > 0;
        partlyLit += ref.fraction > 0 && ref.fraction < 1;
    }
    EXPECT_GE(grouped, 4);  // the points beneath the plate take its group
    EXPECT_GE(partlyLit, 3);
}

TEST(PointQuery, BehindTheLightAndOnTheLight) {
    const Scene scene = testScene();
    VisibilityStore store(scene);
    for (const auto& [face, x] : {std::pair<uint32_t, Vec3>{3, {0, 0, 3}}, {1, {0, 0, 2}}}) {
        const std::vector<LightAtPoint> result = queryPoint(store, face, x, 0u);
        ASSERT_EQ(result.size(), 1u);
        EXPECT_EQ(result[0].fraction, 0.0);
        EXPECT_EQ(result[0].formFactor, 0.0);
        EXPECT_EQ(result[0].unoccludedFormFactor, 0.0);
        EXPECT_TRUE(result[0].fragments.empty());
        EXPECT_EQ(result[0].kind, vis::PairKind::BackFacing);
    }
    EXPECT_THROW(queryPoint(store, 4, {0, 0, 0}, std::nullopt), std::out_of_range);
    EXPECT_THROW(queryPoint(store, 0, {0, 0, 0}, 1u), std::out_of_range);
}

}  // namespace
}  // namespace penumbra
