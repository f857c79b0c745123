#include "app/commands.h"

#include <cctype>
#include <system_error>

#include "engine/obj_io.h"

namespace penumbra::cli {

Scene loadSceneFile(const std::filesystem::path& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status status = fs::status(path, ec);
    if (!fs::exists(status))
        throw inputError("cannot open scene file '" + path.string() + "': no such file");
    if (fs::is_directory(status))
        throw inputError("cannot open scene file '" + path.string() + "': it is a directory");
    std::string extension = path.extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension == ".obj") return loadObj(path);
    throw inputError("cannot load scene file '" + path.string() + "': unknown format '" +
                     (extension.empty() ? std::string("(no extension)") : extension) +
                     "' (supported: .obj)");
}

}  // namespace penumbra::cli
