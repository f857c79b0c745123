// An independent PFM reader for the tests (the renderer's writer is engine/io/image_io.h): header
// tokens, then little-endian floats (negative scale), rows from the bottom. Returns the pixels top
// row first, 3 floats each; gtest failures for anything off.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace penumbra::test {

inline std::vector<float> readPfm(const std::string& path, int& w, int& h) {
    std::ifstream in(path, std::ios::binary);
    std::string magic;
    double scale = 0;
    in >> magic >> w >> h >> scale;
    in.get();  // the single whitespace byte after the scale
    EXPECT_EQ(magic, "PF");
    EXPECT_LT(scale, 0) << "little-endian";
    std::vector<float> bottomUp(static_cast<size_t>(w) * h * 3);
    std::vector<unsigned char> bytes(bottomUp.size() * 4);
    in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    EXPECT_EQ(static_cast<size_t>(in.gcount()), bytes.size());
    EXPECT_EQ(in.peek(), std::char_traits<char>::eof()) << "no trailing bytes";
    std::vector<float> topDown(bottomUp.size());
    for (size_t i = 0; i < bottomUp.size(); ++i) {
        const uint32_t u = bytes[4 * i] | (bytes[4 * i + 1] << 8) | (bytes[4 * i + 2] << 16) |
                           (static_cast<uint32_t>(bytes[4 * i + 3]) << 24);
        float f;
        std::memcpy(&f, &u, sizeof f);
        const size_t pixel = i / 3, row = pixel / w, col = pixel % w;
        topDown[((h - 1 - row) * w + col) * 3 + i % 3] = f;
    }
    return topDown;
}

}  // namespace penumbra::test
