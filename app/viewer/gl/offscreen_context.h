// OffscreenContext: an OpenGL 3.3 core context with no window, rendering into a framebuffer
// object that it keeps bound, for `penumbra screenshot` and the no-display fallback of `view`.
//   OSMesa: Mesa's software rasteriser (llvmpipe), works anywhere.
//   EGL:    surfaceless EGL (EGL_MESA_platform_surfaceless); uses the GPU's driver when one is
//           there, Mesa's llvmpipe otherwise.
// Both libraries are opened at run time (DynamicLibrary), never linked, so they cannot clash with
// the libGL that GLFW opens for the window.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "app/viewer/gl/gl_api.h"

namespace penumbra::gl {

enum class OffscreenBackend { OsMesa, Egl };
const char* toString(OffscreenBackend b);

class OffscreenContext {
  public:
    virtual ~OffscreenContext() = default;
    int width() const { return width_; }
    int height() const { return height_; }
    const GlApi& api() const { return api_; }
    // GL_RENDERER / GL_VERSION of the context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits) / 4.5".
    const std::string& description() const { return description_; }
    // The image drawn so far into the framebuffer: RGBA8, width * height * 4 bytes, top row first.
    // Needs the context's API current (ScopedGlApi).
    std::vector<uint8_t> readRgba() const;

  protected:
    OffscreenContext(int width, int height) : width_(width), height_(height) {}
    // Loads the table, creates and binds the framebuffer (called by the backends once current).
    void initialise(ProcLoader loader);
    void releaseFramebuffer();

    int width_, height_;
    GlApi api_;
    std::string description_;
    GLuint framebuffer_ = 0, colour_ = 0, depth_ = 0;
};

// Asks Mesa's software rasteriser (llvmpipe: OSMesa, EGL and GLX without a GPU, Xvfb) to draw on
// the calling thread (LP_NUM_THREADS=0) unless the user set LP_NUM_THREADS. Why: with its own
// rasteriser threads, the UI thread waits for them at every flush, and while oneTBB's workers
// keep the cores busy (precompute, preview) those waits were measured at tens of seconds on a
// loaded 2-core machine; drawn on the UI thread, a frame costs what the UI thread itself gets.
// Call before the first context is created (Mesa reads it then).
void preferUiThreadSoftwareRasteriser();

// Creates a context of the given size (1..8192 pixels a side). Throws std::runtime_error saying
// what failed (library missing, no surfaceless platform, no 3.3 core context, ...).
std::unique_ptr<OffscreenContext> createOffscreenContext(OffscreenBackend backend, int width,
                                                         int height);

}  // namespace penumbra::gl
