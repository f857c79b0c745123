// penumbra_scene_info SCENE...: loads each scene with engine/io/scene_loader.h and prints its size
// (vertices, faces, triangles, lights, materials), bounds and load time (wall clock, one run), and
// its warnings. Used to check the scene files in assets/scenes/ and to measure loaders.
#include <chrono>
#include <cstdio>
#include <exception>

#include "engine/io/scene_loader.h"

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: penumbra_scene_info SCENE...\n");
        return 2;
    }
    int status = 0;
    for (int i = 1; i < argc; ++i) {
        try {
            const auto start = std::chrono::steady_clock::now();
            const penumbra::Scene scene = penumbra::loadScene(argv[i]);
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            size_t triangles = 0;
            for (const auto& f : scene.mesh.faces) triangles += f.size() - 2;
            const penumbra::vis::Bounds3 b = scene.mesh.bounds();
            std::printf(
                "%s: %zu vertices, %u faces (%zu triangles), %zu area lights, %zu point lights, "
                "%zu materials, camera %s, bounds [%g %g %g]-[%g %g %g], loaded in %.3f s\n",
                argv[i], scene.mesh.vertices.size(), scene.faceCount(), triangles,
                scene.lights.size(), scene.pointLights.size(), scene.materials.size(),
                scene.camera ? "yes" : "no", b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z,
                seconds);
            for (const std::string& w : scene.warnings) std::printf("  warning: %s\n", w.c_str());
        } catch (const std::exception& e) {
            std::fprintf(stderr, "penumbra_scene_info: error: %s\n", e.what());
            status = 1;
        }
    }
    return status;
}
