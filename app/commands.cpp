#include "app/commands.h"

#include <iostream>
#include <system_error>

#include "engine/scene_loader.h"

namespace penumbra::cli {

Scene loadSceneFile(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status))
        throw inputError("cannot open scene file '" + path.string() + "': no such file");
    if (fs::is_directory(status))
        throw inputError("cannot open scene file '" + path.string() + "': it is a directory");
    const std::string extension = path.extension().string();
    if (!isSupportedSceneExtension(extension)) {
        throw inputError("cannot load scene file '" + path.string() + "': unknown format '" +
                         (extension.empty() ? std::string("(no extension)") : extension) +
                         "' (supported: " + supportedSceneExtensions() + ")");
    }
    Scene scene = loadScene(path);
    for (const std::string& warning : scene.warnings) {
        std::cerr << "penumbra: warning: " << warning << '\n';
    }
    return scene;
}

}  // namespace penumbra::cli
