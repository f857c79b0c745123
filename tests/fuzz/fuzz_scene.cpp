// libFuzzer harness for one scene format (PENUMBRA_FUZZ_EXTENSION: ".obj", ".ply", ".off",
// ".stl", ".gltf", ".glb" or ".json"). Every input is written to a file of that extension (the
// loaders, OpenMesh and tinygltf included, read files) and loaded, in repair mode (the default)
// and in strict mode (engine/io/load_options.h). The contract it checks:
//   - a load succeeds or throws SceneError naming the file; any other exception, a crash, a
//     sanitizer report, a hang (libFuzzer's -timeout) or a flood of memory is a finding;
//   - a scene that loads is inside the coordinate contract and its first pair's exact answer is
//     sound (tests/support/answer_check.h, shared with the regression test).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "engine/io/scene_loader.h"
#include "tests/support/answer_check.h"

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
    if (const std::optional<std::string> problem = test::answerProblem(scene)) finding(*problem);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    {
        std::ofstream out(inputPath(), std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    for (const LoadOptions& options : {LoadOptions{}, LoadOptions::strictMode()}) {
        try {
            const Scene scene = loadScene(inputPath(), options);
            checkAnswer(scene);
        } catch (const SceneError& e) {
            if (e.file != inputPath().string())
                finding(std::string("error about another file: ") + e.what());
        } catch (const std::exception& e) {
            finding(std::string("not a SceneError: ") + e.what());
        }
    }
    return 0;
}
