// The GLSL sources of shaders/, embedded into the executable at build time
// (shaders/embed_shaders.cmake generates the definition).
#pragma once

#include <string_view>

namespace penumbra::viewer {

// The text of shaders/<name> (e.g. "mesh.vert"); throws std::invalid_argument for an unknown name.
std::string_view shaderSource(std::string_view name);

}  // namespace penumbra::viewer
