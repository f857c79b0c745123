// The edges of the exactness contract (README, scene contract), each against the exact CGAL
// reference (tests/support/exact_reference.h):
//   - the answered point: a point a rounding behind its face's plane is answered from the front
//     side, with the contact rule decided at the point given, on every path (tree walk, partial
//     tree, tree-less direct query, the renderer's and the viewer's shading point);
//   - the plane of a face: a face is exactly planar or split into triangles at load time, so the
//     answer is the same for every rotation of its vertex list;
//   - the patch that answers: the receiver patch whose tree answers a point contains it (exact
//     test), at every magnitude the coordinate contract accepts and every refinement level;
//   - points off the face they name are refused (query --face).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "engine/io/obj_io.h"
#include "engine/precompute/point_query.h"
#include "engine/precompute/visibility_store.h"
#include "engine/render/shading_point.h"
#include "tests/support/exact_reference.h"
#include "tests/support/face_boxes.h"
#include "tests/support/run_penumbra.h"
#include "tests/support/test_scale.h"
#include "visibility/face_plane.h"
#include "visibility/form_factor.h"
#include "visibility/orient2d.h"

namespace penumbra {
namespace {

using vis::Vec3;

const char* kMtl =
    "newmtl white\nKd 0.8 0.8 0.8\n"
    "newmtl lamp\nKd 0 0 0\nKe 10 10 10\n";

std::string vertexLine(const Vec3& p) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", p.x, p.y, p.z);
    return buf;
}

Scene loadRepaired(const std::string& obj, const std::string& name) {
    return loadObjFromString(obj, kMtl, name, DegenerateFaces::kDrop);
}

// Every path's fraction of light 0 at x on `face` equals the reference's at x (the point given:
// the reference skips the occluders whose plane holds it, the contact rule).
void expectEveryPathMatches(const Scene& scene, uint32_t face, const Vec3& x) {
    SCOPED_TRACE(vis::toString(x));
    const uint32_t light = scene.lights[0];
    const test::ReferenceResult ref = test::exactReference(scene.mesh, face, light, x);
    VisibilityStore::Options whole;
    whole.patchFraction = 0;
    VisibilityStore complete(scene, nullptr, whole);
    VisibilityStore::Options partialOptions = whole;
    partialOptions.build.maxLpSolves = 1;  // a partial tree: the occluders deferred to the query
    VisibilityStore partial(scene, nullptr, partialOptions);
    VisibilityStore patched(scene, nullptr, VisibilityStore::Options{});
    const vis::BoxTree boxes = test::faceBoxTree(scene.mesh);
    const double tree = queryPoint(complete, face, x, 0u)[0].fraction;
    const double deferred = queryPoint(partial, face, x, 0u)[0].fraction;
    const double patch = queryPoint(patched, face, x, 0u)[0].fraction;
    const double direct = queryPointDirect(scene, boxes, face, x, 0u)[0].fraction;
    EXPECT_NEAR(tree, ref.fraction, 1e-12);
    EXPECT_NEAR(deferred, ref.fraction, 1e-12);
    EXPECT_NEAR(patch, ref.fraction, 1e-12);
    EXPECT_NEAR(direct, ref.fraction, 1e-12);
    // The renderer's and the viewer's shading point for a hit there answers the same point.
    const vis::AnsweredPoint shading = shadingPoint(scene.mesh, face, x);
    const vis::AnsweredPoint answered = answeredPointOn(scene, face, x);
    EXPECT_EQ(answered.input, x);
    EXPECT_NE(vis::facePlane(scene.mesh, face).orient().sign(answered.at), vis::Sign::Negative);
    vis::FromPointQuery query;
    const double renderDirect = [&] {
        const auto& list =
            query.runDirect(scene.mesh, face, light, answered, boxes);  // the renderer's call
        double area = 0;
        for (size_t i = 0; i < list.size(); ++i) area += vis::polygonArea(list[i]);
        return area / scene.mesh.faceArea(light);
    }();
    EXPECT_NEAR(renderDirect, ref.fraction, 1e-12);
    (void)shading;
}

// A wall in the plane X = 0 standing on the tilted floor y = x/8 + z/16, a light above: a point
// exactly in the wall's plane on the floor touches the wall (the contact rule: it sees the light
// as if the wall were not there, fraction 1). Points 1 to 4 ulps behind the floor's plane are
// answered from its front side, some ulps off the wall's plane; the contact is decided at the
// point given, so they answer 1 too (the reference's value, by hand: nothing else is in the way).
TEST(ContractEdges, MovedPointKeepsTheContactsOfItsInput) {
    std::string obj = "mtllib scene.mtl\n";
    for (const Vec3& p : std::vector<Vec3>{{-4, -0.75, -4},
                                           {-4, -0.25, 4},
                                           {4, 0.75, 4},
                                           {4, 0.25, -4},  // floor, facing +y
                                           {0, -0.125, -2},
                                           {0, 0.125, 2},
                                           {0, 3, 2},
                                           {0, 3, -2},  // wall in X = 0, its foot on the floor
                                           {-1, 5, -1},
                                           {1, 5, -1},
                                           {1, 5, 1},
                                           {-1, 5, 1}})
        obj += vertexLine(p);
    obj += "usemtl white\nf 1 2 3 4\nf 5 6 7 8\nusemtl lamp\nf 9 10 11 12\n";
    const Scene scene = loadRepaired(obj, "lean.obj");
    ASSERT_EQ(scene.faceCount(), 3u);
    const vis::PlaneOrient floor = vis::facePlane(scene.mesh, 0).orient();
    int behind = 0;
    for (int i = 0; i < 24; ++i) {
        const double z = -1.75 + 0.125 * i;
        double y = z / 16;  // exact: on the floor and in the wall's plane
        for (int k = 0; k <= i % 4; ++k) y = std::nextafter(y, -1.0);
        const Vec3 x{0, y, z};
        ASSERT_EQ(floor.sign(x), vis::Sign::Negative);  // behind the floor's plane by ulps
        behind += answeredPointOn(scene, 0, x).moved();
        const test::ReferenceResult ref = test::exactReference(scene.mesh, 0, 2, x);
        EXPECT_NEAR(ref.fraction, 1.0, 1e-12);
        expectEveryPathMatches(scene, 0, x);
    }
    EXPECT_EQ(behind, 24);
}

// A lean-to: a plate whose lower edge lies on the floor, leaning towards the light, its plane
// cutting the light: a point on that edge, exactly in the plate's plane, touches it and sees the
// whole light (the reference's fraction is 1); from a point moved off the plate's plane the plate
// would hide the light's part beyond its plane (0.75). Points ulps behind the floor there must not
// lose that contact by the move.
TEST(ContractEdges, LeanToEdgeKeepsItsContact) {
    std::string obj = "mtllib scene.mtl\n";
    for (const Vec3& p : std::vector<Vec3>{{-4, 0, -4},
                                           {-4, 0, 4},
                                           {4, 0, 4},
                                           {4, 0, -4},
                                           // the plate: lower edge on the floor at x = 0, leaning
                                           // towards the light up to x = 1 at height 2; its
                                           // plane 2x = y cuts the light at x = 2.5
                                           {0, 0, -2},
                                           {0, 0, 2},
                                           {1, 2, 2},
                                           {1, 2, -2},
                                           // the light, facing -y, above +x
                                           {1, 5, -1},
                                           {3, 5, -1},
                                           {3, 5, 1},
                                           {1, 5, 1}})
        obj += vertexLine(p);
    obj += "usemtl white\nf 1 2 3 4\nf 5 6 7 8\nusemtl lamp\nf 9 10 11 12\n";
    const Scene scene = loadRepaired(obj, "leanto.obj");
    for (int i = 0; i < 12; ++i) {
        const double z = -1.5 + 0.25 * i;
        // On the floor exactly (y = 0) on the plate's edge line, and a hair below the floor in the
        // plate's plane 2x = y (exact: halving a dyadic number).
        const Vec3 on{0, 0, z};
        const double y = -std::ldexp(1.0 + i, -52);
        const Vec3 below{y / 2, y, z};
        EXPECT_NEAR(test::exactReference(scene.mesh, 0, 2, below).fraction, 1.0, 1e-12);
        EXPECT_TRUE(answeredPointOn(scene, 0, below).moved());
        expectEveryPathMatches(scene, 0, on);
        expectEveryPathMatches(scene, 0, below);
    }
}

// A wall planar only to 1e-8 .. 1e-15 of its size, standing on the floor: split into two
// triangles of its vertices at load time, the same two whatever vertex its list starts at, so
// the answers at points along its foot and beside it are identical for every rotation, and equal
// the reference's on the repaired mesh.
TEST(ContractEdges, FacePlaneDoesNotDependOnWhereItsListStarts) {
    std::mt19937_64 rng(38);
    std::uniform_real_distribution<double> u(-1, 1);
    const int walls = test::scaled(6);
    for (int w = 0; w < walls; ++w) {
        const double off =
            3 * std::pow(10.0, -8 - 7 * (0.5 + 0.5 * u(rng))) * (u(rng) < 0 ? -1 : 1);
        const std::vector<Vec3> wall = {{0, -2, 0}, {0, 2, 0}, {off, 2, 3}, {0, -2, 3}};
        std::vector<std::vector<double>> answers;
        for (int r = 0; r < 4; ++r) {
            std::string obj = "mtllib scene.mtl\n";
            for (const Vec3& p : std::vector<Vec3>{{-4, -4, 0},
                                                   {4, -4, 0},
                                                   {4, 4, 0},
                                                   {-4, 4, 0},
                                                   {-1, -1, 5},
                                                   {-1, 1, 5},
                                                   {1, 1, 5},
                                                   {1, -1, 5}})
                obj += vertexLine(p);
            for (const Vec3& p : wall) obj += vertexLine(p);
            obj += "usemtl white\nf 1 2 3 4\nusemtl lamp\nf 5 6 7 8\nusemtl white\nf";
            for (int i = 0; i < 4; ++i) obj += " " + std::to_string(9 + (i + r) % 4);
            obj += "\n";
            const Scene scene = loadRepaired(obj, "wall.obj");
            ASSERT_EQ(scene.faceCount(), 4u) << "the wall split into two triangles";
            ASSERT_EQ(scene.warnings.size(), 1u);
            EXPECT_NE(scene.warnings[0].find("split 1 non-planar faces into 2 triangles"),
                      std::string::npos)
                << scene.warnings[0];
            VisibilityStore store(scene, nullptr, VisibilityStore::Options{});
            std::vector<double> a;
            for (double y : {-1.5, -0.5, 0.25, 1.75})
                for (double x : {0.0, 1e-9, -1e-9, 0.3, -0.3}) {
                    const Vec3 p{x, y, 0};
                    const double f = queryPoint(store, 0, p, 0u)[0].fraction;
                    EXPECT_NEAR(f, test::exactReference(scene.mesh, 0, 1, p).fraction, 1e-12)
                        << vis::toString(p) << " rotation " << r;
                    a.push_back(f);
                }
            answers.push_back(std::move(a));
        }
        for (int r = 1; r < 4; ++r) EXPECT_EQ(answers[r], answers[0]) << "rotation " << r;
    }
}

// Whether x, projected along z, lies in the closed polygon (exact orientation signs).
bool containsExactly(const std::vector<Vec3>& polygon, const Vec3& x) {
    int turn = 0;
    for (size_t i = 1; i + 1 < polygon.size() && turn == 0; ++i)
        turn = vis::orient2d(vis::project(polygon[0], 0, 1), vis::project(polygon[i], 0, 1),
                             vis::project(polygon[i + 1], 0, 1));
    for (size_t i = 0; i < polygon.size(); ++i)
        if (vis::orient2d(vis::project(polygon[i], 0, 1),
                          vis::project(polygon[(i + 1) % polygon.size()], 0, 1),
                          vis::project(x, 0, 1)) *
                turn <
            0)
            return false;
    return true;
}

// A floor far from the origin (1e6 to 1e12, the scene 1 to 8 units), a plate standing on one of
// its patch lines and a light: at every point exactly on the patch grid's lines and corners the
// tree that answers is one whose patch (and sub-patch, two refinement levels down) contains the
// point, and the answer is the reference's.
TEST(ContractEdges, PatchThatAnswersContainsThePoint) {
    for (double origin : {1e6, 1e8, 1e9, 1e12})
        for (double size : {1.0, 8.0}) {
            SCOPED_TRACE("floor at " + std::to_string(origin) + ", size " + std::to_string(size));
            // Corners off the dyadic grid, so that the patches' corners are rounded.
            const double o = origin * 1.0000001 + 0.3, s = size * 0.9731;
            std::string obj = "mtllib scene.mtl\n";
            for (const Vec3& p : std::vector<Vec3>{
                     {o, o, 0},
                     {o + s, o, 0},
                     {o + s, o + s, 0},
                     {o, o + s, 0},  // floor
                     // a plate standing on the line y = o + s/2 (a patch line), facing -y
                     {o, o + s / 2, 0},
                     {o + s, o + s / 2, 0},
                     {o + s, o + s / 2, s / 4},
                     {o, o + s / 2, s / 4},
                     // the light, facing -z, above the +y half
                     {o + s / 4, o + s * 0.55, s},
                     {o + s / 4, o + s, s},
                     {o + s * 0.75, o + s, s},
                     {o + s * 0.75, o + s * 0.55, s}})
                obj += vertexLine(p);
            obj += "usemtl white\nf 1 2 3 4\nf 5 6 7 8\nusemtl lamp\nf 9 10 11 12\n";
            const Scene scene = loadRepaired(obj, "far.obj");
            ASSERT_EQ(scene.faceCount(), 3u);
            VisibilityStore::Options options;
            options.patchFraction = 0.1;
            VisibilityStore store(scene, nullptr, options);
            const vis::ReceiverPatches& patches = store.layout().patches(0);
            ASSERT_GT(patches.patches.size(), 4u);
            const int k = patches.cellsPerSide;
            const int steps = 2 * k;
            int checked = 0;
            for (int i = 0; i <= steps; ++i)
                for (int j = 0; j <= steps; ++j) {
                    // Every point in full runs, about one in four in the sanitizer's.
                    if ((i * 7 + j * 3) % (4 / std::min(4, test::scaled(4))) != 0) continue;
                    // On the patch grid's lines, to a rounding (the grid is not dyadic here).
                    const Vec3 x{o + s * i / steps, o + s * j / steps, 0};
                    PairKey key = store.layout().keyAt(0, x, 2);
                    ASSERT_TRUE(containsExactly(store.layout().region(key), x))
                        << vis::toString(x) << " patch " << key.patch;
                    // Two levels of refinement, each sub-patch holding x built.
                    if ((i + j) % 5 == 0) {
                        for (int level = 0; level < 2; ++level) {
                            ASSERT_TRUE(store.layout().refine(key));
                            key = store.layout().subKeyAt(key, x);
                            ASSERT_TRUE(containsExactly(store.layout().region(key), x))
                                << vis::toString(x) << " level " << level + 1;
                            store.getOrBuild(key);
                        }
                        EXPECT_EQ(store.layout().keyAt(0, x, 2), key);
                    }
                    const double f = queryPoint(store, 0, x, 0u)[0].fraction;
                    EXPECT_NEAR(f, test::exactReference(scene.mesh, 0, 2, x).fraction, 1e-9)
                        << vis::toString(x);
                    ++checked;
                }
            // The patches' own (rounded, grown) corners that lie on the face (those of the
            // patches along its edges lie a hair outside it, outside the contract): each lies on
            // the edges of its neighbours, a hair outside them.
            std::vector<Vec3> floor;
            for (uint32_t v : scene.mesh.faces[0]) floor.push_back(scene.mesh.vertices[v]);
            for (size_t p = 0; p < patches.patches.size(); p += 3)
                for (const Vec3& corner : patches.patches[p]) {
                    const Vec3 x{corner.x, corner.y, 0};
                    if (!containsExactly(floor, x)) continue;
                    const PairKey key = store.layout().keyAt(0, x, 2);
                    EXPECT_TRUE(containsExactly(store.layout().region(key), x)) << vis::toString(x);
                    ++checked;
                }
            EXPECT_GT(checked, 10);
        }
}

// query --face with a point that is not on the face: refused, naming the point, the face and the
// distance (outside the face's boundary, or off its plane).
TEST(ContractEdges, QueryRefusesAPointOffTheFaceItNames) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("penumbra_contract_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir);
    {
        std::ofstream(dir / "scene.mtl") << kMtl;
        std::ofstream(dir / "scene.obj")
            << "mtllib scene.mtl\nv -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
               "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"
               "usemtl white\nf 1 2 3 4\nusemtl lamp\nf 5 6 7 8\n";
    }
    const std::string scene = (dir / "scene.obj").string();
    const test::ProcessResult outside =
        test::runPenumbra({"query", scene, "--point=2.00005,0,0", "--face", "0"});
    EXPECT_NE(outside.exitCode, 0);
    EXPECT_NE(outside.err.find("point (2.00005, 0, 0) is not on face 0"), std::string::npos)
        << outside.err;
    EXPECT_NE(outside.err.find("outside its boundary"), std::string::npos) << outside.err;
    const test::ProcessResult off =
        test::runPenumbra({"query", scene, "--point=0,0,0.001", "--face", "0"});
    EXPECT_NE(off.exitCode, 0);
    EXPECT_NE(off.err.find("lies 0.001 from its plane"), std::string::npos) << off.err;
    // On the face (its boundary, and within the tolerance): answered.
    const test::ProcessResult on =
        test::runPenumbra({"query", scene, "--point=2,0,0", "--face", "0"});
    EXPECT_EQ(on.exitCode, 0) << on.err;
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace penumbra
