// The output boundary's check that no NaN or infinity leaves the program: JSON answers and state
// files, images, visibility files. A non-finite number there is a bug upstream (the scene
// contract, engine/scene/scene_validation.h, keeps every input finite and in range): it is reported
// as an internal error naming where it is, instead of being printed as `null` or written as a
// pixel.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>

namespace penumbra {

struct NonFiniteOutput : std::logic_error {
    using std::logic_error::logic_error;
};

// Throws NonFiniteOutput("internal error: <what>: non-finite number at <JSON path>") for the first
// NaN or infinity in `j`.
void requireFinite(const nlohmann::json& j, const std::string& what);

// The same for one number.
inline void requireFinite(double v, const std::string& what) {
    if (!std::isfinite(v)) throw NonFiniteOutput("internal error: " + what + " is not finite");
}

}  // namespace penumbra
