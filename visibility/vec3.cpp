#include "visibility/vec3.h"

#include <cstdio>

namespace penumbra::vis {

std::string toString(const Vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.17g, %.17g, %.17g)", v.x, v.y, v.z);
    return buf;
}

}  // namespace penumbra::vis
