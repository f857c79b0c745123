#include "engine/io/scene_loader.h"

#include <array>
#include <system_error>

#include "engine/io/gltf_io.h"
#include "engine/io/obj_io.h"
#include "engine/io/openmesh_io.h"
#include "engine/io/scene_file.h"
#include "engine/io/text_input.h"
#include "engine/scene/default_light.h"
#include "engine/scene/light_checks.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

constexpr std::array<std::string_view, 7> kExtensions = {".obj",  ".ply", ".off", ".stl",
                                                         ".gltf", ".glb", ".json"};

}  // namespace

std::string supportedSceneExtensions() {
    std::string list;
    for (std::string_view e : kExtensions) {
        if (e.empty()) continue;
        if (!list.empty()) list += ", ";
        list += e;
    }
    return list;
}

bool isSupportedSceneExtension(std::string_view extension) {
    for (std::string_view k : kExtensions)
        if (!k.empty() && equalsIgnoreCase(extension, k)) return true;
    return false;
}

Scene loadScenePart(const std::filesystem::path& path, const LoadOptions& options) {
    std::error_code ec;
    const std::filesystem::file_status status = std::filesystem::status(path, ec);
    if (!std::filesystem::exists(status))
        throw makeMissingFileError(path.string(), 0, "no such file", path.string());
    if (std::filesystem::is_directory(status))
        throw makeSceneError(path.string(), 0, "it is a directory, not a scene file");
    const std::string e = lowerExtension(path);
    // Every format's scene, once its lights are known: none thinner than doubles resolve.
    auto lightsChecked = [](Scene scene) {
        validateLights(scene);
        return scene;
    };
    if (e == ".obj") return lightsChecked(loadObj(path, options));
    if (e == ".ply" || e == ".off" || e == ".stl")
        return lightsChecked(loadOpenMeshFile(path, options));
    if (e == ".gltf" || e == ".glb") return lightsChecked(loadGltf(path, options));
    if (e == ".json") return lightsChecked(loadJsonScene(path, options));
    throw makeSceneError(path.string(), 0,
                         "unknown scene format '" +
                             (e.empty() ? std::string("(no extension)") : e) +
                             "' (supported: " + supportedSceneExtensions() + ")");
}

Scene loadScene(const std::filesystem::path& path, const LoadOptions& options) {
    Scene scene = loadScenePart(path, options);
    if (options.defaultLight && needsDefaultLight(scene)) addDefaultLight(scene);
    if (auto warning = lightsFacingAwayWarning(scene))
        scene.warnings.push_back(std::move(*warning));
    return scene;
}

}  // namespace penumbra
