// The OSMesa offscreen backend (see offscreen_context.h).
#include <memory>
#include <stdexcept>

#include "app/viewer/gl/dynamic_library.h"
#include "app/viewer/gl/offscreen_context.h"

namespace penumbra::gl {
namespace {

// <GL/osmesa.h> pulls in <GL/gl.h>, whose prototypes would collide with gl_api.h's macros; the
// few OSMesa constants and signatures are restated here (values from Mesa's osmesa.h).
constexpr int kOsmesaFormat = 0x22, kOsmesaDepthBits = 0x30, kOsmesaStencilBits = 0x31,
              kOsmesaAccumBits = 0x32, kOsmesaProfile = 0x33, kOsmesaCoreProfile = 0x34,
              kOsmesaMajor = 0x36, kOsmesaMinor = 0x37;
using OsmesaContextHandle = void*;
using CreateContextAttribsFn = OsmesaContextHandle (*)(const int*, OsmesaContextHandle);
using MakeCurrentFn = unsigned char (*)(OsmesaContextHandle, void*, GLenum, GLsizei, GLsizei);
using DestroyContextFn = void (*)(OsmesaContextHandle);
using GetProcAddressFn = void (*(*)(const char*))();

class OsmesaContext final : public OffscreenContext {
  public:
    OsmesaContext(int width, int height)
        : OffscreenContext(width, height), library_({"libOSMesa.so.8", "libOSMesa.so"}) {
        auto create = reinterpret_cast<CreateContextAttribsFn>(
            library_.require("OSMesaCreateContextAttribs"));
        auto makeCurrent = reinterpret_cast<MakeCurrentFn>(library_.require("OSMesaMakeCurrent"));
        destroy_ = reinterpret_cast<DestroyContextFn>(library_.require("OSMesaDestroyContext"));
        auto getProc = reinterpret_cast<GetProcAddressFn>(library_.require("OSMesaGetProcAddress"));
        const int attributes[] = {kOsmesaFormat,
                                  GL_RGBA,
                                  kOsmesaDepthBits,
                                  24,
                                  kOsmesaStencilBits,
                                  8,
                                  kOsmesaAccumBits,
                                  0,
                                  kOsmesaProfile,
                                  kOsmesaCoreProfile,
                                  kOsmesaMajor,
                                  3,
                                  kOsmesaMinor,
                                  3,
                                  0};
        context_ = create(attributes, nullptr);
        if (context_ == nullptr)
            throw std::runtime_error("OSMesa could not create an OpenGL 3.3 core context");
        // OSMesa needs a buffer of its own for the default framebuffer; drawing goes to the FBO.
        buffer_.assign(static_cast<size_t>(width) * static_cast<size_t>(height) * 4, 0);
        if (makeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, width, height) == 0)
            throw std::runtime_error("OSMesaMakeCurrent failed for a " + std::to_string(width) +
                                     "x" + std::to_string(height) + " buffer");
        initialise([getProc](const char* name) { return reinterpret_cast<void*>(getProc(name)); });
    }
    ~OsmesaContext() override {
        releaseFramebuffer();
        if (context_ != nullptr) destroy_(context_);
    }

  private:
    DynamicLibrary library_;
    DestroyContextFn destroy_ = nullptr;
    OsmesaContextHandle context_ = nullptr;
    std::vector<uint8_t> buffer_;
};

}  // namespace

std::unique_ptr<OffscreenContext> createOsmesaContext(int width, int height) {
    return std::make_unique<OsmesaContext>(width, height);
}

}  // namespace penumbra::gl
