// Writes the procedural scenes (engine/scene/procedural_scenes.h) as OBJ + MTL into a directory:
// the committed files under assets/ are produced by `penumbra_make_assets assets`.
#include <cstdio>
#include <exception>
#include <filesystem>

#include "engine/io/obj_io.h"
#include "engine/scene/procedural_scenes.h"

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: penumbra_make_assets OUTPUT_DIR\n");
        return 2;
    }
    try {
        const std::filesystem::path dir = argv[1];
        std::filesystem::create_directories(dir);
        const std::pair<const char*, penumbra::Scene> scenes[] = {
            {"stairs", penumbra::makeStairs()},
            {"table", penumbra::makeTable()},
            {"grids", penumbra::makeGrids()},
            {"cornell_box", penumbra::makeCornellBox()},
        };
        for (const auto& [name, scene] : scenes) {
            const auto path = dir / (std::string(name) + ".obj");
            penumbra::writeObj(scene, path);
            std::printf("%s: %u faces, %zu lights\n", path.c_str(), scene.faceCount(),
                        scene.lights.size());
        }
    } catch (const std::exception& e) {
        std::fprintf(stderr, "penumbra_make_assets: error: %s\n", e.what());
        return 1;
    }
    return 0;
}
