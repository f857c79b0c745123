#include "app/viewer/panels/panel.h"

#include <cstdio>

namespace penumbra::viewer {

std::string humanBytes(size_t bytes) {
    char buf[32];
    if (bytes >= (1u << 20))
        std::snprintf(buf, sizeof buf, "%.1f MiB", static_cast<double>(bytes) / (1u << 20));
    else
        std::snprintf(buf, sizeof buf, "%.1f KiB", static_cast<double>(bytes) / (1u << 10));
    return buf;
}

}  // namespace penumbra::viewer
