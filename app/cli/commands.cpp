#include "app/cli/commands.h"

#include <iostream>
#include <system_error>

#include "engine/io/scene_loader.h"

namespace penumbra::cli {

Scene loadSceneFile(const std::filesystem::path& path, const LoadOptions& options) {
    Scene scene = loadScene(path, options);
    for (const std::string& notice : scene.loadNotices())
        std::cerr << "penumbra: warning: " << notice << '\n';
    return scene;
}

}  // namespace penumbra::cli
