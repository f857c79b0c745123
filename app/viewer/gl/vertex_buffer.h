// VertexBuffer: a vertex array object with one interleaved float buffer, for the scene mesh and
// the overlays. Attribute i has attributeSizes[i] floats and location i.
#pragma once

#include <span>
#include <vector>

#include "app/viewer/gl/gl_api.h"

namespace penumbra::viewer {

class VertexBuffer {
  public:
    explicit VertexBuffer(std::vector<int> attributeSizes);
    ~VertexBuffer();
    VertexBuffer(const VertexBuffer&) = delete;
    VertexBuffer& operator=(const VertexBuffer&) = delete;

    int stride() const { return stride_; }  // floats per vertex
    // Replaces the contents (data.size() must be a multiple of stride()).
    void upload(std::span<const float> data);
    size_t vertexCount() const { return count_; }
    void draw(GLenum mode) const { draw(mode, 0, count_); }
    void draw(GLenum mode, size_t first, size_t count) const;

  private:
    GLuint vao_ = 0, vbo_ = 0;
    int stride_ = 0;
    size_t count_ = 0;
};

}  // namespace penumbra::viewer
