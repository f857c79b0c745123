#include "app/cli/commands.h"

#include <iostream>
#include <system_error>

#include "engine/io/scene_loader.h"

namespace penumbra::cli {

Scene loadSceneFile(const std::filesystem::path& path) {
    Scene scene = loadScene(path);
    for (const std::string& warning : scene.warnings) {
        std::cerr << "penumbra: warning: " << warning << '\n';
    }
    return scene;
}

}  // namespace penumbra::cli
