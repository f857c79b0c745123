#include "app/viewer/gl/offscreen_context.h"

#include <cstdlib>
#include <cstring>
#include <stdexcept>

namespace penumbra::gl {

void preferUiThreadSoftwareRasteriser() { setenv("LP_NUM_THREADS", "0", /*overwrite=*/0); }

const char* toString(OffscreenBackend b) {
    return b == OffscreenBackend::OsMesa ? "osmesa" : "egl";
}

void OffscreenContext::initialise(ProcLoader loader) {
    api_ = loadGlApi(std::move(loader));
    const ScopedGlApi scope(api_);
    const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    description_ = std::string(renderer != nullptr ? renderer : "?") + " / " +
                   (version != nullptr ? version : "?");
    glGenFramebuffers(1, &framebuffer_);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glGenRenderbuffers(1, &colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width_, height_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
    glGenRenderbuffers(1, &depth_);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width_, height_);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth_);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        throw std::runtime_error("offscreen framebuffer incomplete (status " +
                                 std::to_string(status) + ") on " + description_);
    glViewport(0, 0, width_, height_);
}

void OffscreenContext::releaseFramebuffer() {
    if (framebuffer_ == 0) return;
    const ScopedGlApi scope(api_);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteRenderbuffers(1, &colour_);
    glDeleteRenderbuffers(1, &depth_);
    framebuffer_ = 0;
}

std::vector<uint8_t> OffscreenContext::readRgba() const {
    const size_t row = static_cast<size_t>(width_) * 4;
    std::vector<uint8_t> bottomUp(row * static_cast<size_t>(height_));
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glFinish();
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
    // GL rows go bottom to top; images top to bottom.
    std::vector<uint8_t> out(bottomUp.size());
    for (int y = 0; y < height_; ++y)
        std::memcpy(out.data() + static_cast<size_t>(y) * row,
                    bottomUp.data() + static_cast<size_t>(height_ - 1 - y) * row, row);
    return out;
}

}  // namespace penumbra::gl

namespace penumbra::gl {

std::unique_ptr<OffscreenContext> createOsmesaContext(int width, int height);  // osmesa_context.cpp
std::unique_ptr<OffscreenContext> createEglContext(int width, int height);     // egl_context.cpp

std::unique_ptr<OffscreenContext> createOffscreenContext(OffscreenBackend backend, int width,
                                                         int height) {
    if (width < 1 || height < 1 || width > 8192 || height > 8192)
        throw std::runtime_error("offscreen size " + std::to_string(width) + "x" +
                                 std::to_string(height) + " out of range (1..8192 a side)");
    preferUiThreadSoftwareRasteriser();
    try {
        return backend == OffscreenBackend::OsMesa ? createOsmesaContext(width, height)
                                                   : createEglContext(width, height);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error(std::string(toString(backend)) + " backend: " + e.what());
    }
}

}  // namespace penumbra::gl
