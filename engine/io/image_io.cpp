#include "engine/io/image_io.h"

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

#include "engine/io/atomic_file.h"
#include "engine/io/exr_io.h"
#include "engine/io/finite_output.h"
#include "engine/io/text_input.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

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

std::vector<uint8_t> answersToRgb8(const Film& film) {
    const size_t n = static_cast<size_t>(std::max(film.width, 0)) * std::max(film.height, 0);
    if (n == 0 || film.answers.size() != n)
        throw std::invalid_argument(
            "the film holds no answers (an exact render keeps them when asked: "
            "RenderSettings::recordAnswers)");
    std::vector<uint8_t> out(n * 3);
    for (size_t i = 0; i < n; ++i) {
        const Vec3 c = answerPixel(film.answers[i]);
        size_t k = 3 * i;
        for (double v : {c.x, c.y, c.z})
            out[k++] = static_cast<uint8_t>(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
    }
    return out;
}

void writeAnswersPng(const Film& film, const std::string& path) {
    std::vector<uint8_t> pixels;
    try {
        pixels = answersToRgb8(film);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error("cannot write '" + path + "': " + e.what());
    }
    writeFileAtomically(path, encodePng(film.width, film.height, 3, pixels.data()));
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

void writeExr(const Film& film, const std::string& path) {
    requireFilm(film, path);
    std::vector<float> rgb(static_cast<size_t>(film.width) * film.height * 3);
    size_t i = 0;
    for (int y = 0; y < film.height; ++y) {  // OpenEXR rows run from the top (INCREASING_Y)
        for (int x = 0; x < film.width; ++x) {
            const Vec3 c = film.mean(x, y);
            for (double v : {c.x, c.y, c.z}) rgb[i++] = static_cast<float>(v);
        }
    }
    std::string bytes;
    try {
        bytes = encodeExr(film.width, film.height, rgb);
    } catch (const std::runtime_error& e) {
        throw std::runtime_error("cannot write '" + path + "': " + e.what());
    }
    writeFileAtomically(path, bytes);
}

std::optional<ImageFormat> imageFormatOf(const std::filesystem::path& path) {
    const std::string e = lowerExtension(path);
    if (e == ".png") return ImageFormat::Png;
    if (e == ".pfm") return ImageFormat::Pfm;
    if (e == ".exr") return ImageFormat::Exr;
    return std::nullopt;
}

void writeImage(const Film& film, const std::string& path, ImageFormat format, double exposure) {
    switch (format) {
        case ImageFormat::Png:
            return writePng(film, path, exposure);
        case ImageFormat::Pfm:
            return writePfm(film, path);
        case ImageFormat::Exr:
            return writeExr(film, path);
    }
}

std::string encodePng(int width, int height, int channels, const uint8_t* pixels) {
    std::string bytes;
    auto append = [](void* context, void* data, int size) {
        static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                                   static_cast<size_t>(size));
    };
    if (width < 1 || height < 1 || channels < 1 || channels > 4 ||
        stbi_write_png_to_func(append, &bytes, width, height, channels, pixels, width * channels) ==
            0)
        throw std::runtime_error("PNG encoding failed (" + std::to_string(width) + "x" +
                                 std::to_string(height) + ", " + std::to_string(channels) +
                                 " channels)");
    return bytes;
}

void writePng(const Film& film, const std::string& path, double exposure) {
    requireFilm(film, path);
    const std::vector<uint8_t> pixels = toSrgb8(film, exposure);
    writeFileAtomically(path, encodePng(film.width, film.height, 3, pixels.data()));
}

}  // namespace penumbra
