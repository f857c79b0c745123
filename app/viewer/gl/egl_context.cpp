// The EGL surfaceless offscreen backend (see offscreen_context.h).
#define EGL_NO_PROTOTYPES  // every EGL function is looked up at run time
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <memory>
#include <stdexcept>

#include "app/viewer/gl/dynamic_library.h"
#include "app/viewer/gl/offscreen_context.h"

namespace penumbra::gl {
namespace {

class EglContext final : public OffscreenContext {
  public:
    EglContext(int width, int height)
        : OffscreenContext(width, height), library_({"libEGL.so.1", "libEGL.so"}) {
        getProc_ =
            reinterpret_cast<PFNEGLGETPROCADDRESSPROC>(library_.require("eglGetProcAddress"));
        auto queryString = load<PFNEGLQUERYSTRINGPROC>("eglQueryString");
        const char* clientExtensions = queryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
        if (clientExtensions == nullptr ||
            std::string(clientExtensions).find("EGL_MESA_platform_surfaceless") ==
                std::string::npos)
            throw std::runtime_error(
                "EGL has no surfaceless platform (EGL_MESA_platform_surfaceless missing from the "
                "client extensions: " +
                std::string(clientExtensions != nullptr ? clientExtensions : "none") + ")");
        auto getPlatformDisplay = load<PFNEGLGETPLATFORMDISPLAYEXTPROC>("eglGetPlatformDisplayEXT");
        display_ = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        EGLint major = 0, minor = 0;
        if (display_ == EGL_NO_DISPLAY ||
            load<PFNEGLINITIALIZEPROC>("eglInitialize")(display_, &major, &minor) == EGL_FALSE)
            throw std::runtime_error("EGL surfaceless display did not initialise (error 0x" +
                                     hex(load<PFNEGLGETERRORPROC>("eglGetError")()) + ")");
        terminate_ = load<PFNEGLTERMINATEPROC>("eglTerminate");
        if (load<PFNEGLBINDAPIPROC>("eglBindAPI")(EGL_OPENGL_API) == EGL_FALSE)
            throw std::runtime_error("EGL display has no desktop OpenGL API");
        const EGLint configAttributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
        EGLConfig config = nullptr;
        EGLint configs = 0;
        load<PFNEGLCHOOSECONFIGPROC>("eglChooseConfig")(display_, configAttributes, &config, 1,
                                                        &configs);
        const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                            3,
                                            EGL_CONTEXT_MINOR_VERSION,
                                            3,
                                            EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                            EGL_NONE};
        context_ = load<PFNEGLCREATECONTEXTPROC>("eglCreateContext")(
            display_, configs > 0 ? config : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, contextAttributes);
        if (context_ == EGL_NO_CONTEXT)
            throw std::runtime_error("EGL could not create an OpenGL 3.3 core context (error 0x" +
                                     hex(load<PFNEGLGETERRORPROC>("eglGetError")()) + ")");
        makeCurrent_ = load<PFNEGLMAKECURRENTPROC>("eglMakeCurrent");
        destroyContext_ = load<PFNEGLDESTROYCONTEXTPROC>("eglDestroyContext");
        if (makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_FALSE)
            throw std::runtime_error(
                "eglMakeCurrent without a surface failed (no "
                "EGL_KHR_surfaceless_context?)");
        auto getProc = getProc_;
        initialise([getProc](const char* name) { return reinterpret_cast<void*>(getProc(name)); });
    }
    ~EglContext() override {
        releaseFramebuffer();
        if (context_ != EGL_NO_CONTEXT) {
            makeCurrent_(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            destroyContext_(display_, context_);
        }
        if (terminate_ != nullptr) terminate_(display_);
    }

  private:
    template <typename F>
    F load(const char* name) const {
        auto f = reinterpret_cast<F>(getProc_(name));
        if (f == nullptr) f = reinterpret_cast<F>(library_.find(name));
        if (f == nullptr) throw std::runtime_error(library_.name() + " lacks " + name);
        return f;
    }
    static std::string hex(EGLint v) {
        static constexpr char kDigits[] = "0123456789abcdef";
        std::string s;
        for (int shift = 12; shift >= 0; shift -= 4) s += kDigits[(v >> shift) & 0xF];
        return s;
    }

    DynamicLibrary library_;
    PFNEGLGETPROCADDRESSPROC getProc_ = nullptr;
    PFNEGLMAKECURRENTPROC makeCurrent_ = nullptr;
    PFNEGLDESTROYCONTEXTPROC destroyContext_ = nullptr;
    PFNEGLTERMINATEPROC terminate_ = nullptr;
    EGLDisplay display_ = EGL_NO_DISPLAY;
    EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<OffscreenContext> createEglContext(int width, int height) {
    return std::make_unique<EglContext>(width, height);
}

}  // namespace penumbra::gl
