// libFuzzer harness for the visibility file (engine/io/visibility_file.h) of a fixed small scene
// (the grids: chords, partial trees and deferred occluders all occur). Each input is written as
// the file and read into a fresh store. The contract: a read succeeds or throws
// VisibilityFileError; a file that passes validation cannot make FPQuery misbehave, so every tree
// read is then queried at points of its receiver (fragments of finite area, at most the light's).
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/scene/procedural_scenes.h"
#include "visibility/form_factor.h"
#include "visibility/fp_query/from_point_query.h"

namespace {

using namespace penumbra;

const Scene& scene() {
    static const Scene s = makeGrids();
    return s;
}

const std::filesystem::path& inputPath() {
    static const std::filesystem::path p =
        std::filesystem::temp_directory_path() /
        ("penumbra_fuzz_" + std::to_string(::getpid()) + ".pvis");
    return p;
}

[[noreturn]] void finding(const std::string& what) {
    std::fprintf(stderr, "finding: %s\n", what.c_str());
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    {
        std::ofstream out(inputPath(), std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    VisibilityStore::Options options;
    options.build.maxLpSolves = 25;  // as the seed file was written
    VisibilityStore store(scene(), nullptr, options);
    try {
        readVisibilityFile(inputPath(), store);
    } catch (const VisibilityFileError&) {
        return 0;
    } catch (const std::exception& e) {
        finding(std::string("not a VisibilityFileError: ") + e.what());
    }
    vis::FromPointQuery query;
    store.forEach([&](const PairKey& key, const PairRecord& record) {
        const auto& face = scene().mesh.faces[key.receiver];
        Vec3 x{};
        for (uint32_t v : face) x += scene().mesh.vertices[v];
        x = x / static_cast<double>(face.size());
        const vis::FragmentList& f = query.run(scene().mesh, record.tree, x);
        double area = 0;
        for (size_t i = 0; i < f.size(); ++i) area += vis::polygonArea(f[i]);
        const double lightArea = scene().mesh.faceArea(key.lightFace);
        if (!std::isfinite(area) || area < 0 || area > lightArea * (1 + 1e-6))
            finding("a validated tree answered area " + std::to_string(area));
    });
    return 0;
}
