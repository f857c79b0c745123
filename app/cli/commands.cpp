#include "app/cli/commands.h"

#include <iostream>
#include <system_error>

#include "engine/io/scene_loader.h"

namespace penumbra::cli {

Scene loadSceneFile(const std::filesystem::path& path, bool strict) {
    Scene scene = loadScene(path, strict ? LoadOptions::strictMode() : LoadOptions{});
    for (const std::string& warning : scene.warnings) {
        std::cerr << "penumbra: warning: " << warning << '\n';
    }
    return scene;
}

}  // namespace penumbra::cli
