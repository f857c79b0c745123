// GlApi: the OpenGL functions Penumbra's UI uses, as a table of pointers loaded by name.
//
// Why a table: the window (GLFW: libGL through GLX), OSMesa and EGL each provide their own gl*
// entry points, and linking libGL and libOSMesa into one process clashes (both export every gl*
// symbol). No UI file calls a gl* symbol: every call goes through the table of the context that is
// current on the calling thread, loaded through that context's get-proc-address function
// (glfwGetProcAddress, OSMesaGetProcAddress, eglGetProcAddress). The macros at the end of this
// header route the plain gl* names (as used by Dear ImGui's OpenGL3 backend, compiled here with
// IMGUI_IMPL_OPENGL_LOADER_CUSTOM) to that table.
//
// The current table is thread-local state, set by ScopedGlApi, exactly like GL's own notion of a
// context current on a thread; it is the one piece of global state of the UI.
#pragma once

#include <GL/glcorearb.h>

#include <functional>
#include <string>

namespace penumbra::gl {

// Resolves one GL function by name; nullptr when absent.
using ProcLoader = std::function<void*(const char* name)>;

#define PENUMBRA_GL_FUNCTIONS(X)                                 \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                     \
    X(PFNGLATTACHSHADERPROC, AttachShader)                       \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                           \
    X(PFNGLBINDSAMPLERPROC, BindSampler)                         \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                         \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                 \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                     \
    X(PFNGLBLENDEQUATIONSEPARATEPROC, BlendEquationSeparate)     \
    X(PFNGLBLENDFUNCPROC, BlendFunc)                             \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)             \
    X(PFNGLBUFFERDATAPROC, BufferData)                           \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                     \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                     \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                     \
    X(PFNGLCREATESHADERPROC, CreateShader)                       \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                     \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                     \
    X(PFNGLDELETESHADERPROC, DeleteShader)                       \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                   \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)           \
    X(PFNGLDETACHSHADERPROC, DetachShader)                       \
    X(PFNGLDISABLEPROC, Disable)                                 \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                       \
    X(PFNGLDRAWELEMENTSBASEVERTEXPROC, DrawElementsBaseVertex)   \
    X(PFNGLENABLEPROC, Enable)                                   \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                           \
    X(PFNGLGENTEXTURESPROC, GenTextures)                         \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                 \
    X(PFNGLGETATTRIBLOCATIONPROC, GetAttribLocation)             \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                         \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)             \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                       \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)               \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                         \
    X(PFNGLGETSTRINGPROC, GetString)                             \
    X(PFNGLGETSTRINGIPROC, GetStringi)                           \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)           \
    X(PFNGLISENABLEDPROC, IsEnabled)                             \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                         \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                         \
    X(PFNGLPOLYGONMODEPROC, PolygonMode)                         \
    X(PFNGLSCISSORPROC, Scissor)                                 \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                       \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                           \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                     \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                             \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)               \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                           \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)         \
    X(PFNGLVIEWPORTPROC, Viewport)                               \
    X(PFNGLCLEARPROC, Clear)                                     \
    X(PFNGLCLEARCOLORPROC, ClearColor)                           \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                           \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                             \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                             \
    X(PFNGLUNIFORM4FPROC, Uniform4f)                             \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                             \
    X(PFNGLDEPTHMASKPROC, DepthMask)                             \
    X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                     \
    X(PFNGLLINEWIDTHPROC, LineWidth)                             \
    X(PFNGLREADPIXELSPROC, ReadPixels)                           \
    X(PFNGLFINISHPROC, Finish)                                   \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                 \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                 \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer) \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)               \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)               \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)         \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)   \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)           \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)         \
    X(PFNGLTEXSUBIMAGE2DPROC, TexSubImage2D)                     \
    X(PFNGLGETERRORPROC, GetError)                               \
    X(PFNGLREADBUFFERPROC, ReadBuffer)                           \
    X(PFNGLCULLFACEPROC, CullFace)                               \
    X(PFNGLFRONTFACEPROC, FrontFace)                             \
    X(PFNGLCOLORMASKPROC, ColorMask)

struct GlApi {
#define PENUMBRA_GL_FIELD(type, name) type name = nullptr;
    PENUMBRA_GL_FUNCTIONS(PENUMBRA_GL_FIELD)
#undef PENUMBRA_GL_FIELD
};

// Loads every function through `loader`. Throws std::runtime_error naming the missing functions
// when a required one is absent (BindSampler and GetStringi are optional: ImGui checks them).
GlApi loadGlApi(ProcLoader loader);

// The table current on this thread; throws std::logic_error when none is (a programming error:
// a GL call outside a ScopedGlApi).
const GlApi& currentGlApi();

// Makes `api` current on this thread for the lifetime of the object (restores the previous one).
class ScopedGlApi {
  public:
    explicit ScopedGlApi(const GlApi& api);
    ~ScopedGlApi();
    ScopedGlApi(const ScopedGlApi&) = delete;
    ScopedGlApi& operator=(const ScopedGlApi&) = delete;

  private:
    const GlApi* previous_;
};

// "GL_INVALID_ENUM" etc. for glGetError codes.
std::string glErrorName(GLenum code);

}  // namespace penumbra::gl

// The plain GL names, routed to the current table.
#define glActiveTexture (::penumbra::gl::currentGlApi().ActiveTexture)
#define glAttachShader (::penumbra::gl::currentGlApi().AttachShader)
#define glBindBuffer (::penumbra::gl::currentGlApi().BindBuffer)
#define glBindSampler (::penumbra::gl::currentGlApi().BindSampler)
#define glBindTexture (::penumbra::gl::currentGlApi().BindTexture)
#define glBindVertexArray (::penumbra::gl::currentGlApi().BindVertexArray)
#define glBlendEquation (::penumbra::gl::currentGlApi().BlendEquation)
#define glBlendEquationSeparate (::penumbra::gl::currentGlApi().BlendEquationSeparate)
#define glBlendFunc (::penumbra::gl::currentGlApi().BlendFunc)
#define glBlendFuncSeparate (::penumbra::gl::currentGlApi().BlendFuncSeparate)
#define glBufferData (::penumbra::gl::currentGlApi().BufferData)
#define glBufferSubData (::penumbra::gl::currentGlApi().BufferSubData)
#define glCompileShader (::penumbra::gl::currentGlApi().CompileShader)
#define glCreateProgram (::penumbra::gl::currentGlApi().CreateProgram)
#define glCreateShader (::penumbra::gl::currentGlApi().CreateShader)
#define glDeleteBuffers (::penumbra::gl::currentGlApi().DeleteBuffers)
#define glDeleteProgram (::penumbra::gl::currentGlApi().DeleteProgram)
#define glDeleteShader (::penumbra::gl::currentGlApi().DeleteShader)
#define glDeleteTextures (::penumbra::gl::currentGlApi().DeleteTextures)
#define glDeleteVertexArrays (::penumbra::gl::currentGlApi().DeleteVertexArrays)
#define glDetachShader (::penumbra::gl::currentGlApi().DetachShader)
#define glDisable (::penumbra::gl::currentGlApi().Disable)
#define glDrawElements (::penumbra::gl::currentGlApi().DrawElements)
#define glDrawElementsBaseVertex (::penumbra::gl::currentGlApi().DrawElementsBaseVertex)
#define glEnable (::penumbra::gl::currentGlApi().Enable)
#define glEnableVertexAttribArray (::penumbra::gl::currentGlApi().EnableVertexAttribArray)
#define glGenBuffers (::penumbra::gl::currentGlApi().GenBuffers)
#define glGenTextures (::penumbra::gl::currentGlApi().GenTextures)
#define glGenVertexArrays (::penumbra::gl::currentGlApi().GenVertexArrays)
#define glGetAttribLocation (::penumbra::gl::currentGlApi().GetAttribLocation)
#define glGetIntegerv (::penumbra::gl::currentGlApi().GetIntegerv)
#define glGetProgramInfoLog (::penumbra::gl::currentGlApi().GetProgramInfoLog)
#define glGetProgramiv (::penumbra::gl::currentGlApi().GetProgramiv)
#define glGetShaderInfoLog (::penumbra::gl::currentGlApi().GetShaderInfoLog)
#define glGetShaderiv (::penumbra::gl::currentGlApi().GetShaderiv)
#define glGetString (::penumbra::gl::currentGlApi().GetString)
#define glGetStringi (::penumbra::gl::currentGlApi().GetStringi)
#define glGetUniformLocation (::penumbra::gl::currentGlApi().GetUniformLocation)
#define glIsEnabled (::penumbra::gl::currentGlApi().IsEnabled)
#define glLinkProgram (::penumbra::gl::currentGlApi().LinkProgram)
#define glPixelStorei (::penumbra::gl::currentGlApi().PixelStorei)
#define glPolygonMode (::penumbra::gl::currentGlApi().PolygonMode)
#define glScissor (::penumbra::gl::currentGlApi().Scissor)
#define glShaderSource (::penumbra::gl::currentGlApi().ShaderSource)
#define glTexImage2D (::penumbra::gl::currentGlApi().TexImage2D)
#define glTexParameteri (::penumbra::gl::currentGlApi().TexParameteri)
#define glUniform1i (::penumbra::gl::currentGlApi().Uniform1i)
#define glUniformMatrix4fv (::penumbra::gl::currentGlApi().UniformMatrix4fv)
#define glUseProgram (::penumbra::gl::currentGlApi().UseProgram)
#define glVertexAttribPointer (::penumbra::gl::currentGlApi().VertexAttribPointer)
#define glViewport (::penumbra::gl::currentGlApi().Viewport)
#define glClear (::penumbra::gl::currentGlApi().Clear)
#define glClearColor (::penumbra::gl::currentGlApi().ClearColor)
#define glDrawArrays (::penumbra::gl::currentGlApi().DrawArrays)
#define glUniform1f (::penumbra::gl::currentGlApi().Uniform1f)
#define glUniform3f (::penumbra::gl::currentGlApi().Uniform3f)
#define glUniform4f (::penumbra::gl::currentGlApi().Uniform4f)
#define glDepthFunc (::penumbra::gl::currentGlApi().DepthFunc)
#define glDepthMask (::penumbra::gl::currentGlApi().DepthMask)
#define glPolygonOffset (::penumbra::gl::currentGlApi().PolygonOffset)
#define glLineWidth (::penumbra::gl::currentGlApi().LineWidth)
#define glReadPixels (::penumbra::gl::currentGlApi().ReadPixels)
#define glFinish (::penumbra::gl::currentGlApi().Finish)
#define glGenFramebuffers (::penumbra::gl::currentGlApi().GenFramebuffers)
#define glBindFramebuffer (::penumbra::gl::currentGlApi().BindFramebuffer)
#define glFramebufferRenderbuffer (::penumbra::gl::currentGlApi().FramebufferRenderbuffer)
#define glGenRenderbuffers (::penumbra::gl::currentGlApi().GenRenderbuffers)
#define glBindRenderbuffer (::penumbra::gl::currentGlApi().BindRenderbuffer)
#define glRenderbufferStorage (::penumbra::gl::currentGlApi().RenderbufferStorage)
#define glCheckFramebufferStatus (::penumbra::gl::currentGlApi().CheckFramebufferStatus)
#define glDeleteFramebuffers (::penumbra::gl::currentGlApi().DeleteFramebuffers)
#define glDeleteRenderbuffers (::penumbra::gl::currentGlApi().DeleteRenderbuffers)
#define glTexSubImage2D (::penumbra::gl::currentGlApi().TexSubImage2D)
#define glGetError (::penumbra::gl::currentGlApi().GetError)
#define glReadBuffer (::penumbra::gl::currentGlApi().ReadBuffer)
#define glCullFace (::penumbra::gl::currentGlApi().CullFace)
#define glFrontFace (::penumbra::gl::currentGlApi().FrontFace)
#define glColorMask (::penumbra::gl::currentGlApi().ColorMask)
