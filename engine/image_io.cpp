#include "engine/finite_output.h"
#include "engine/image_io.h"

#include <stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <random>
#include <stdexcept>
#include <system_error>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

struct FileCloser {
    void operator()(std::FILE* f) const noexcept {
        if (f) std::fclose(f);
    }
};

double srgbEncode(double linear) {
    if (!(linear > 0)) return 0;  // also NaN
    if (linear >= 1) return 1;
    return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

void requireFilm(const Film& film, const std::string& path) {
    if (film.width < 1 || film.height < 1 ||
        film.sum.size() != static_cast<size_t>(film.width) * film.height)
        throw std::runtime_error("cannot write '" + path +
                                 "': the film is empty or inconsistent (" +
                                 std::to_string(film.width) + "x" + std::to_string(film.height) +
                                 ", " + std::to_string(film.sum.size()) + " pixels)");
    for (size_t i = 0; i < film.sum.size(); ++i) {
        const Vec3& v = film.sum[i];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            throw NonFiniteOutput("internal error: cannot write '" + path + "': pixel (" +
                                  std::to_string(i % film.width) + ", " +
                                  std::to_string(i / film.width) + ") is not finite");
    }
}

}  // namespace

std::vector<uint8_t> toSrgb8(const Film& film, double exposure) {
    std::vector<uint8_t> out(static_cast<size_t>(film.width) * film.height * 3);
    size_t i = 0;
    for (int y = 0; y < film.height; ++y) {
        for (int x = 0; x < film.width; ++x) {
            const Vec3 c = film.mean(x, y) * exposure;
            for (double v : {c.x, c.y, c.z})
                out[i++] = static_cast<uint8_t>(std::lround(255.0 * srgbEncode(v)));
        }
    }
    return out;
}

void writeFileAtomically(const std::string& path, std::string_view bytes) {
    const fs::path target(path);
    std::random_device random;
    char suffix[32];
    std::snprintf(suffix, sizeof suffix, ".tmp-%08x%08x", random(), random());
    const fs::path temp = target.parent_path() / ("." + target.filename().string() + suffix);
    const auto fail = [&](const std::string& why) {
        std::error_code ignored;
        fs::remove(temp, ignored);
        return std::runtime_error("cannot write '" + path + "': " + why);
    };
    if (target.filename().empty()) throw fail("not a file name");
    {
        std::unique_ptr<std::FILE, FileCloser> file(std::fopen(temp.c_str(), "wbx"));
        if (!file) throw fail(std::strerror(errno));
        const bool written =
            std::fwrite(bytes.data(), 1, bytes.size(), file.get()) == bytes.size() &&
            std::fflush(file.get()) == 0 && ::fsync(::fileno(file.get())) == 0;
        const int err = errno;
        const bool closed = std::fclose(file.release()) == 0;
        if (!written || !closed) throw fail(std::strerror(err));
    }
    std::error_code ec;
    fs::rename(temp, target, ec);
    if (ec) throw fail(ec.message());
}

void writePfm(const Film& film, const std::string& path) {
    requireFilm(film, path);
    // Header: "PF" (colour), size, and a negative scale for little-endian floats.
    std::string bytes =
        "PF\n" + std::to_string(film.width) + " " + std::to_string(film.height) + "\n-1.0\n";
    const size_t header = bytes.size();
    bytes.resize(header + static_cast<size_t>(film.width) * film.height * 3 * sizeof(float));
    char* p = bytes.data() + header;
    for (int y = film.height - 1; y >= 0; --y) {  // PFM rows run from the bottom
        for (int x = 0; x < film.width; ++x) {
            const Vec3 c = film.mean(x, y);
            for (double v : {c.x, c.y, c.z}) {
                uint32_t u = std::bit_cast<uint32_t>(static_cast<float>(v));
                if constexpr (std::endian::native == std::endian::big) u = __builtin_bswap32(u);
                std::memcpy(p, &u, sizeof u);
                p += sizeof u;
            }
        }
    }
    writeFileAtomically(path, bytes);
}

void writePng(const Film& film, const std::string& path, double exposure) {
    requireFilm(film, path);
    const std::vector<uint8_t> pixels = toSrgb8(film, exposure);
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                   static_cast<size_t>(size));
    };
    if (stbi_write_png_to_func(append, &bytes, film.width, film.height, 3, pixels.data(),
                               film.width * 3) == 0)
        throw std::runtime_error("cannot write '" + path + "': PNG encoding failed");
    writeFileAtomically(path, bytes);
}

}  // namespace penumbra
