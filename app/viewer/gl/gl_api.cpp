#include "app/viewer/gl/gl_api.h"

#include <stdexcept>

namespace penumbra::gl {
namespace {

// The table current on this thread (see the header: mirrors GL's per-thread current context).
thread_local const GlApi* tCurrent = nullptr;

template <typename T>
void loadOne(ProcLoader loader, const char* name, T& slot, bool optional, std::string& missing) {
    slot = reinterpret_cast<T>(loader(name));
    if (slot == nullptr && !optional) missing += std::string(missing.empty() ? "" : ", ") + name;
}

}  // namespace

GlApi loadGlApi(ProcLoader loader) {
    if (loader == nullptr) throw std::runtime_error("OpenGL: no get-proc-address function");
    GlApi api;
    std::string missing;
    const std::string optionalNames = " glBindSampler glGetStringi ";
#define PENUMBRA_GL_LOAD(type, name)      \
    loadOne(loader, "gl" #name, api.name, \
            optionalNames.find(" gl" #name " ") != std::string::npos, missing);
    PENUMBRA_GL_FUNCTIONS(PENUMBRA_GL_LOAD)
#undef PENUMBRA_GL_LOAD
    if (!missing.empty())
        throw std::runtime_error("OpenGL: the context lacks required functions: " + missing);
    return api;
}

const GlApi& currentGlApi() {
    if (tCurrent == nullptr)
        throw std::logic_error("OpenGL call with no GL function table current on this thread");
    return *tCurrent;
}

ScopedGlApi::ScopedGlApi(const GlApi& api) : previous_(tCurrent) { tCurrent = &api; }
ScopedGlApi::~ScopedGlApi() { tCurrent = previous_; }

std::string glErrorName(GLenum code) {
    switch (code) {
        case GL_NO_ERROR:
            return "GL_NO_ERROR";
        case GL_INVALID_ENUM:
            return "GL_INVALID_ENUM";
        case GL_INVALID_VALUE:
            return "GL_INVALID_VALUE";
        case GL_INVALID_OPERATION:
            return "GL_INVALID_OPERATION";
        case GL_INVALID_FRAMEBUFFER_OPERATION:
            return "GL_INVALID_FRAMEBUFFER_OPERATION";
        case GL_OUT_OF_MEMORY:
            return "GL_OUT_OF_MEMORY";
        default:
            return "GL error " + std::to_string(code);
    }
}

}  // namespace penumbra::gl
