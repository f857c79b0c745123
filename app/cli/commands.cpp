#include "app/cli/commands.h"

#include <iostream>
#include <new>
#include <system_error>

#include "engine/io/scene_loader.h"
#include "engine/scene/scene_error.h"

namespace penumbra::cli {

int fail(int code, const std::string& message) {
    std::cerr << "penumbra: error: " << message << '\n';
    return code;
}

int reportError(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const CommandError& e) {
        return fail(e.exitCode, e.what());
    } catch (const SceneError& e) {
        return fail(kExitInputError, e.what());
    } catch (const std::bad_alloc&) {
        return fail(kExitInputError, "out of memory");
    } catch (const std::exception& e) {
        return fail(kExitInputError, std::string("internal error: ") + e.what());
    } catch (...) {
        return fail(kExitInputError, "internal error: unknown exception");
    }
}

Scene loadSceneFile(const std::filesystem::path& path, const LoadOptions& options) {
    Scene scene = loadScene(path, options);
    for (const std::string& notice : scene.loadNotices())
        std::cerr << "penumbra: warning: " << notice << '\n';
    return scene;
}

}  // namespace penumbra::cli
