// Helpers for the scene loader tests: a temporary directory per test, little-endian binary
// writers, base64, and an expectation that loading fails with a SceneError naming the file.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include "engine/scene/scene_error.h"

namespace penumbra::test {

namespace fs = std::filesystem;

class LoaderFiles : public ::testing::Test {
  protected:
    void SetUp() override {
        std::random_device random;
        dir_ = fs::temp_directory_path() /
               ("penumbra_loader_test_" + std::to_string(random()) + std::to_string(random()));
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        fs::remove_all(dir_, ec);
    }
    fs::path write(const std::string& name, const std::string& bytes) {
        const fs::path p = dir_ / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << bytes;
        return p;
    }
    fs::path dir_;
};

// Little-endian binary writers.
inline void putF32(std::string& s, float v) {
    uint32_t b;
    std::memcpy(&b, &v, 4);
    for (int i = 0; i < 4; ++i) s += static_cast<char>((b >> (8 * i)) & 0xff);
}
inline void putU32(std::string& s, uint32_t v) {
    for (int i = 0; i < 4; ++i) s += static_cast<char>((v >> (8 * i)) & 0xff);
}
inline void putU16(std::string& s, uint16_t v) {
    s += static_cast<char>(v & 0xff);
    s += static_cast<char>(v >> 8);
}
inline void putU8(std::string& s, uint8_t v) { s += static_cast<char>(v); }

inline std::string base64(const std::string& data) {
    static const char* kAlphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    size_t i = 0;
    for (; i + 2 < data.size(); i += 3) {
        const uint32_t n = (uint32_t(uint8_t(data[i])) << 16) |
                           (uint32_t(uint8_t(data[i + 1])) << 8) | uint8_t(data[i + 2]);
        for (int k = 3; k >= 0; --k) out += kAlphabet[(n >> (6 * k)) & 63];
    }
    if (i + 1 == data.size()) {
        const uint32_t n = uint32_t(uint8_t(data[i])) << 16;
        out += kAlphabet[(n >> 18) & 63];
        out += kAlphabet[(n >> 12) & 63];
        out += "==";
    } else if (i + 2 == data.size()) {
        const uint32_t n =
            (uint32_t(uint8_t(data[i])) << 16) | (uint32_t(uint8_t(data[i + 1])) << 8);
        out += kAlphabet[(n >> 18) & 63];
        out += kAlphabet[(n >> 12) & 63];
        out += kAlphabet[(n >> 6) & 63];
        out += '=';
    }
    return out;
}

// Runs `load` and expects a SceneError whose file is `file` and whose what() names the file and
// contains every keyword.
inline void expectLoadError(const std::function<void()>& load, const fs::path& file,
                            std::initializer_list<std::string> keywords) {
    try {
        load();
        ADD_FAILURE() << "no SceneError for " << file;
    } catch (const SceneError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.file, file.string()) << what;
        EXPECT_EQ(what.rfind(file.string(), 0), 0u) << what;
        for (const std::string& k : keywords)
            EXPECT_NE(what.find(k), std::string::npos) << what << " (expected '" << k << "')";
    }
}

}  // namespace penumbra::test
