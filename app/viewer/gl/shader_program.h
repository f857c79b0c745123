// ShaderProgram: a linked GLSL program (through the current GL function table,
// app/viewer/gl/gl_api.h).
#pragma once

#include <string>
#include <string_view>

#include "app/viewer/gl/gl_api.h"

namespace penumbra::viewer {

class ShaderProgram {
  public:
    // Compiles and links; throws std::runtime_error with the names and the driver's log on error.
    ShaderProgram(std::string_view vertexName, std::string_view fragmentName);
    ~ShaderProgram();
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;

    void use() const;
    void setMatrix(const char* name, const float* columnMajor4x4) const;
    void setVec3(const char* name, float x, float y, float z) const;
    void setFloat(const char* name, float value) const;

  private:
    GLuint program_ = 0;
};

}  // namespace penumbra::viewer
