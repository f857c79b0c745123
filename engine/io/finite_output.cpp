#include "engine/io/finite_output.h"

namespace penumbra {
namespace {

void walk(const nlohmann::json& j, const std::string& what, const std::string& path) {
    if (j.is_number_float()) {
        if (!std::isfinite(j.get<double>()))
            throw NonFiniteOutput("internal error: " + what + ": non-finite number at " +
                                  (path.empty() ? "(root)" : path));
    } else if (j.is_object()) {
        for (auto it = j.begin(); it != j.end(); ++it)
            walk(it.value(), what, path.empty() ? it.key() : path + "." + it.key());
    } else if (j.is_array()) {
        for (size_t i = 0; i < j.size(); ++i)
            walk(j[i], what, path + "[" + std::to_string(i) + "]");
    }
}

}  // namespace

void requireFinite(const nlohmann::json& j, const std::string& what) { walk(j, what, ""); }

}  // namespace penumbra
