// Image output of the renderer: tone mapping and file writing (writePfm / writePng / writeExr are
// declared in renderer.h next to Film, and implemented in image_io.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "engine/render/renderer.h"

namespace penumbra {

// The film's mean radiance times `exposure`, clamped to [0, 1] and encoded with the sRGB transfer
// curve, 8 bits per channel, RGB, rows from the top. Non-finite values become 0.
std::vector<uint8_t> toSrgb8(const Film& film, double exposure = 1.0);

// The film's answers (Film::answers, exact method) as colours (answers.h: each pixel the mean of
// its evaluations' colours, black where it has none), 8 bits per channel, RGB, rows from the top.
// Throws std::invalid_argument for a film without answers (RenderSettings::recordAnswers off).
std::vector<uint8_t> answersToRgb8(const Film& film);
// Writes them as a PNG, atomically. Throws std::runtime_error (naming the file) when the film has
// no answers or the file cannot be written.
void writeAnswersPng(const Film& film, const std::string& path);

// The formats a film is written in, chosen by the file's extension (case-insensitive): .png (tone
// mapped, sRGB, 8 bits), .pfm and .exr (linear radiance, 32-bit float; exr_io.h).
enum class ImageFormat { Png, Pfm, Exr };
// The format of `path` by its extension; nullopt for any other extension.
std::optional<ImageFormat> imageFormatOf(const std::filesystem::path& path);
// The accepted extensions, for messages.
inline constexpr const char* kImageExtensions = ".png, .pfm or .exr";
// Writes the film as `format`, atomically (`exposure`: PNG only). Throws std::runtime_error naming
// the file.
void writeImage(const Film& film, const std::string& path, ImageFormat format,
                double exposure = 1.0);

// A PNG file's bytes: `pixels` holds width * height * channels bytes (1 to 4 channels), rows from
// the top. Throws std::runtime_error when the image cannot be encoded.
std::string encodePng(int width, int height, int channels, const uint8_t* pixels);

}  // namespace penumbra
