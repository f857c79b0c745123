// Writes the visibility-file harness's seed: a file of the grids (fuzz_visibility_file.cpp's
// scene) with complete and partial trees, built with the harness's build budget.
#include <cstdio>

#include "engine/io/visibility_file.h"
#include "engine/precompute/visibility_store.h"
#include "engine/scene/procedural_scenes.h"

int main(int argc, char** argv) {
    using namespace penumbra;
    if (argc != 2) {
        std::fprintf(stderr, "usage: penumbra_fuzz_seed OUT.pvis\n");
        return 2;
    }
    const Scene scene = makeGrids();
    VisibilityStore::Options options;
    options.build.maxLpSolves = 25;
    VisibilityStore store(scene, nullptr, options);
    for (uint32_t f : {0u, 1u, 5u, 30u, 60u}) store.getOrBuild({f, 0, scene.lights[0]});
    writeVisibilityFile(argv[1], store);
    return 0;
}
