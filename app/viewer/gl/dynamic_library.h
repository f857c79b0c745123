// DynamicLibrary: a shared library opened at run time (dlopen, RTLD_LOCAL). It is never closed:
// Mesa's libraries keep thread-local state and exit handlers that must outlive any context, and
// leak checkers need the module loaded to name (and suppress) what it keeps at exit.
// The offscreen GL backends open libOSMesa and libEGL this way so that their gl* symbols never
// meet libGL's (which GLFW opens the same way) in one symbol namespace.
#pragma once

#include <string>

namespace penumbra::gl {

class DynamicLibrary {
  public:
    // Tries each name in turn; throws std::runtime_error listing dlerror() for each when none
    // opens.
    explicit DynamicLibrary(std::initializer_list<const char*> names);
    ~DynamicLibrary() = default;
    DynamicLibrary(const DynamicLibrary&) = delete;
    DynamicLibrary& operator=(const DynamicLibrary&) = delete;

    // The symbol, or nullptr.
    void* find(const char* symbol) const;
    // The symbol; throws std::runtime_error naming it and the library when absent.
    void* require(const char* symbol) const;
    const std::string& name() const { return name_; }

  private:
    void* handle_ = nullptr;
    std::string name_;
};

}  // namespace penumbra::gl
