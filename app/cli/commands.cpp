#include "app/cli/commands.h"

#include <charconv>
#include <cmath>
#include <iostream>
#include <system_error>

#include "engine/io/scene_loader.h"

namespace penumbra::cli {

std::optional<double> parseNumber(std::string_view s) {
    const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
    while (!s.empty() && blank(s.front())) s.remove_prefix(1);
    while (!s.empty() && blank(s.back())) s.remove_suffix(1);
    if (s.size() > 1 && s.front() == '+' && s[1] != '-') s.remove_prefix(1);
    double v = 0;
    const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || r.ec != std::errc{} || r.ptr != s.data() + s.size() || !std::isfinite(v))
        return std::nullopt;
    return v;
}

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
