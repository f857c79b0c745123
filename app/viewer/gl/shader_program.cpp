#include "app/viewer/gl/shader_program.h"

#include <stdexcept>
#include <string>
#include <vector>

#include "app/viewer/gl/shader_sources.h"

namespace penumbra::viewer {
namespace {

GLuint compile(GLenum type, std::string_view name) {
    const std::string_view text = shaderSource(name);
    const GLuint shader = glCreateShader(type);
    const char* source = text.data();
    const GLint length = static_cast<GLint>(text.size());
    glShaderSource(shader, 1, &source, &length);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok == 0) {
        GLint logLength = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &logLength);
        std::vector<char> log(static_cast<size_t>(std::max(logLength, 1)));
        glGetShaderInfoLog(shader, logLength, nullptr, log.data());
        glDeleteShader(shader);
        throw std::runtime_error("shader " + std::string(name) +
                                 " does not compile: " + std::string(log.data()));
    }
    return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(std::string_view vertexName, std::string_view fragmentName) {
    const GLuint vs = compile(GL_VERTEX_SHADER, vertexName);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, fragmentName);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    program_ = glCreateProgram();
    glAttachShader(program_, vs);
    glAttachShader(program_, fs);
    glLinkProgram(program_);
    glDetachShader(program_, vs);
    glDetachShader(program_, fs);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLint ok = 0;
    glGetProgramiv(program_, GL_LINK_STATUS, &ok);
    if (ok == 0) {
        GLint logLength = 0;
        glGetProgramiv(program_, GL_INFO_LOG_LENGTH, &logLength);
        std::vector<char> log(static_cast<size_t>(std::max(logLength, 1)));
        glGetProgramInfoLog(program_, logLength, nullptr, log.data());
        glDeleteProgram(program_);
        throw std::runtime_error("shaders " + std::string(vertexName) + " + " +
                                 std::string(fragmentName) + " do not link: " + log.data());
    }
}

ShaderProgram::~ShaderProgram() { glDeleteProgram(program_); }

void ShaderProgram::use() const { glUseProgram(program_); }

void ShaderProgram::setMatrix(const char* name, const float* m) const {
    glUniformMatrix4fv(glGetUniformLocation(program_, name), 1, GL_FALSE, m);
}

void ShaderProgram::setVec3(const char* name, float x, float y, float z) const {
    glUniform3f(glGetUniformLocation(program_, name), x, y, z);
}

void ShaderProgram::setFloat(const char* name, float value) const {
    glUniform1f(glGetUniformLocation(program_, name), value);
}

}  // namespace penumbra::viewer
