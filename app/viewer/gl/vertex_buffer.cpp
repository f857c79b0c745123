#include "app/viewer/gl/vertex_buffer.h"

#include <numeric>
#include <stdexcept>

namespace penumbra::viewer {

VertexBuffer::VertexBuffer(std::vector<int> attributeSizes)
    : stride_(std::accumulate(attributeSizes.begin(), attributeSizes.end(), 0)) {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    size_t offset = 0;
    for (size_t i = 0; i < attributeSizes.size(); ++i) {
        glEnableVertexAttribArray(static_cast<GLuint>(i));
        glVertexAttribPointer(static_cast<GLuint>(i), attributeSizes[i], GL_FLOAT, GL_FALSE,
                              static_cast<GLsizei>(stride_ * sizeof(float)),
                              reinterpret_cast<const void*>(offset * sizeof(float)));
        offset += static_cast<size_t>(attributeSizes[i]);
    }
    glBindVertexArray(0);
}

VertexBuffer::~VertexBuffer() {
    glDeleteBuffers(1, &vbo_);
    glDeleteVertexArrays(1, &vao_);
}

void VertexBuffer::upload(std::span<const float> data) {
    if (data.size() % static_cast<size_t>(stride_) != 0)
        throw std::invalid_argument("vertex data is not a whole number of vertices");
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(data.size() * sizeof(float)), data.data(),
                 GL_DYNAMIC_DRAW);
    count_ = data.size() / static_cast<size_t>(stride_);
}

void VertexBuffer::draw(GLenum mode, size_t first, size_t count) const {
    if (count == 0) return;
    glBindVertexArray(vao_);
    glDrawArrays(mode, static_cast<GLint>(first), static_cast<GLsizei>(count));
    glBindVertexArray(0);
}

}  // namespace penumbra::viewer
