// Small helpers of the tests: a whole file as bytes, and Vec3 comparisons.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "visibility/vec3.h"

namespace penumbra::test {

// The file's bytes ("" when it cannot be read).
inline std::string readFile(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Each coordinate within 1e-12.
inline void expectNear(const vis::Vec3& a, const vis::Vec3& b) {
    EXPECT_NEAR(a.x, b.x, 1e-12) << vis::toString(a) << " vs " << vis::toString(b);
    EXPECT_NEAR(a.y, b.y, 1e-12) << vis::toString(a) << " vs " << vis::toString(b);
    EXPECT_NEAR(a.z, b.z, 1e-12) << vis::toString(a) << " vs " << vis::toString(b);
}

}  // namespace penumbra::test
