#include "app/viewer/gl/dynamic_library.h"

#include <dlfcn.h>

#include <stdexcept>

namespace penumbra::gl {

DynamicLibrary::DynamicLibrary(std::initializer_list<const char*> names) {
    std::string errors;
    for (const char* n : names) {
        handle_ = dlopen(n, RTLD_NOW | RTLD_LOCAL);
        if (handle_ != nullptr) {
            name_ = n;
            return;
        }
        const char* e = dlerror();
        errors += std::string(errors.empty() ? "" : "; ") + (e != nullptr ? e : n);
    }
    throw std::runtime_error("cannot open library: " + errors);
}

void* DynamicLibrary::find(const char* symbol) const { return dlsym(handle_, symbol); }

void* DynamicLibrary::require(const char* symbol) const {
    void* p = find(symbol);
    if (p == nullptr)
        throw std::runtime_error(name_ + " lacks the function " + std::string(symbol));
    return p;
}

}  // namespace penumbra::gl
