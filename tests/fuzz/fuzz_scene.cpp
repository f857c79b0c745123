// libFuzzer harness for one scene format (PENUMBRA_FUZZ_EXTENSION: ".obj", ".ply", ".off",
// ".stl", ".gltf", ".glb" or ".json"). Every input is written to a file of that extension (the
// loaders, OpenMesh and tinygltf included, read files) and loaded. The contract it checks:
//   - a load succeeds or throws SceneError naming the file; any other exception, a crash, a
//     sanitizer report, a hang (libFuzzer's -timeout) or a flood of memory is a finding;
//   - a scene that loads is inside the coordinate contract and its first pair's exact answer is
//     finite: the history tree of (face 0, the first light) is built with a small budget and the
//     from-point query at face 0's centroid gives fragments of finite, non-negative area no larger
//     than the light's.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/io/scene_loader.h"
#include "engine/scene/scene_validation.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query.h"
#include "visibility/history_tree_builder.h"

#ifndef PENUMBRA_FUZZ_EXTENSION
#error "PENUMBRA_FUZZ_EXTENSION must name the scene format"
#endif

namespace {

using namespace penumbra;

const std::filesystem::path& inputPath() {
    static const std::filesystem::path p =
        std::filesystem::temp_directory_path() /
        ("penumbra_fuzz_" + std::to_string(::getpid()) + PENUMBRA_FUZZ_EXTENSION);
    return p;
}

[[noreturn]] void finding(const std::string& what) {
    std::fprintf(stderr, "finding: %s\n", what.c_str());
    std::abort();
}

void checkAnswer(const Scene& scene) {
    for (const Vec3& v : scene.mesh.vertices)
        if (coordinateProblem(v)) finding("a loaded vertex breaks the coordinate contract");
    if (scene.lights.empty() || scene.faceCount() < 2 || scene.faceCount() > 64) return;
    const uint32_t light = scene.lights[0];
    const uint32_t receiver = light == 0 ? 1 : 0;
    vis::BuildOptions options;
    options.maxLpSolves = 200;
    const vis::HistoryTree tree = vis::buildHistoryTree(scene.mesh, receiver, light, options);
    Vec3 x{};
    for (uint32_t v : scene.mesh.faces[receiver]) x += scene.mesh.vertices[v];
    x = x / static_cast<double>(scene.mesh.faces[receiver].size());
    vis::FromPointQuery query;
    const vis::FragmentList& fragments = query.run(scene.mesh, tree, x);
    double area = 0;
    for (size_t i = 0; i < fragments.size(); ++i) area += vis::polygonArea(fragments[i]);
    const double lightArea = scene.mesh.faceArea(light);
    if (!std::isfinite(area) || area < 0 || area > lightArea * (1 + 1e-6) + 1e-300) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "visible area %.17g of a light of area %.17g", area,
                      lightArea);
        finding(buf);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    {
        std::ofstream out(inputPath(), std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const Scene scene = loadScene(inputPath());
        checkAnswer(scene);
    } catch (const SceneError& e) {
        if (e.file != inputPath().string())
            finding(std::string("error about another file: ") + e.what());
    } catch (const std::exception& e) {
        finding(std::string("not a SceneError: ") + e.what());
    }
    return 0;
}
