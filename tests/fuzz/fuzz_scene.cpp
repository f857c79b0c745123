// libFuzzer harness for the scene formats, one executable under one name per format:
// fuzz_scene_obj, _ply, _off, _stl, _gltf, _glb and _json are links to it (tests/fuzz/
// CMakeLists.txt), and the name it runs under picks the format (compiled once, not seven times).
// Every input is written to a file of that extension (the loaders, OpenMesh and tinygltf
// included, read files) and loaded, in repair mode (the default) and in strict mode
// (engine/io/load_options.h). The contract it checks:
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
#include <string_view>

#include "engine/io/scene_loader.h"
#include "tests/support/answer_check.h"

namespace {

using namespace penumbra;

// The input file, named once by LLVMFuzzerInitialize from the harness's name.
std::filesystem::path& inputPath() {
    static std::filesystem::path p;
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

// The format is the name's suffix after "fuzz_scene_": fuzz_scene_obj reads OBJ files.
extern "C" int LLVMFuzzerInitialize(int* argc, char*** argv) {
    constexpr std::string_view prefix = "fuzz_scene_";
    const std::string name = *argc > 0 ? std::filesystem::path((*argv)[0]).filename().string() : "";
    constexpr std::string_view formats[] = {"obj", "ply", "off", "stl", "gltf", "glb", "json"};
    for (const std::string_view format : formats) {
        if (name == std::string(prefix) + std::string(format)) {
            inputPath() =
                std::filesystem::temp_directory_path() /
                ("penumbra_fuzz_" + std::to_string(::getpid()) + "." + std::string(format));
            return 0;
        }
    }
    std::fprintf(stderr,
                 "fuzz_scene: run it as fuzz_scene_FORMAT (obj, ply, off, stl, gltf, glb or json), "
                 "not as '%s'\n",
                 name.c_str());
    std::exit(2);
}

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
