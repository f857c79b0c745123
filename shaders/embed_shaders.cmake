# Writes OUTPUT: a C++ file defining penumbra::viewer::shaderSource(name) over the GLSL files
# (*.vert, *.frag) of SHADER_DIR, so that the executable does not depend on finding shaders/ at run
# time. Run by app/CMakeLists.txt at build time whenever a shader changes.
file(GLOB SOURCES ${SHADER_DIR}/*.vert ${SHADER_DIR}/*.frag)
list(SORT SOURCES)
set(body "// Generated from shaders/ by shaders/embed_shaders.cmake: do not edit.\n")
string(APPEND body "#include \"app/viewer/gl/shader_sources.h\"\n\n#include <stdexcept>\n#include <string>\n\n")
string(APPEND body "namespace penumbra::viewer {\n\nstd::string_view shaderSource(std::string_view name) {\n")
foreach(path IN LISTS SOURCES)
  get_filename_component(name ${path} NAME)
  file(READ ${path} text)
  string(APPEND body "    if (name == \"${name}\") return R\"penumbra_glsl(${text})penumbra_glsl\";\n")
endforeach()
string(APPEND body "    throw std::invalid_argument(\"no shader named \" + std::string(name));\n}\n\n}  // namespace penumbra::viewer\n")
file(WRITE ${OUTPUT}.tmp "${body}")
file(RENAME ${OUTPUT}.tmp ${OUTPUT})
