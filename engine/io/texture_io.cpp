#include "engine/io/texture_io.h"

#include <stb_image.h>

#include <climits>
#include <cstdint>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "engine/io/text_input.h"

namespace penumbra {
namespace texture_io_detail {

struct StbFree {
    void operator()(unsigned char* p) const { stbi_image_free(p); }
};

}  // namespace texture_io_detail

TextureRead decodeTexture(std::span<const unsigned char> bytes, std::string source) {
    TextureRead out;
    if (bytes.empty()) {
        out.problem = "cannot decode it: no image data";
        return out;
    }
    if (bytes.size() > static_cast<size_t>(INT_MAX)) {
        out.problem = "cannot decode it: larger than 2 GiB";
        return out;
    }
    const int size = static_cast<int>(bytes.size());
    int width = 0, height = 0, channels = 0;
    if (stbi_info_from_memory(bytes.data(), size, &width, &height, &channels) == 0) {
        out.problem = std::string("cannot decode it: ") + stbi_failure_reason();
        return out;
    }
    if (width < 1 || height < 1 ||
        static_cast<size_t>(width) * static_cast<size_t>(height) > kMaxTextureTexels) {
        out.problem = std::to_string(width) + " x " + std::to_string(height) +
                      " texels, more than the " + std::to_string(kMaxTextureTexels) +
                      " texels a texture may have";
        return out;
    }
    const std::unique_ptr<unsigned char, texture_io_detail::StbFree> pixels(
        stbi_load_from_memory(bytes.data(), size, &width, &height, &channels, 3));
    if (!pixels) {
        out.problem = std::string("cannot decode it: ") + stbi_failure_reason();
        return out;
    }
    TextureImage image;
    image.source = std::move(source);
    image.width = width;
    image.height = height;
    image.srgb.assign(pixels.get(), pixels.get() + 3 * static_cast<size_t>(width) * height);
    out.image = std::move(image);
    return out;
}

TextureRead readTextureFile(const std::filesystem::path& path) {
    // Only a regular file of bounded size: a name in a scene file may point anywhere (a device, a
    // pipe, a directory), and reading one of those would block or never end.
    std::error_code ec;
    if (std::filesystem::exists(path, ec)) {
        if (!std::filesystem::is_regular_file(path, ec))
            return {std::nullopt, "not a regular file"};
        const uintmax_t size = std::filesystem::file_size(path, ec);
        if (!ec && size > kMaxTextureFileBytes)
            return {std::nullopt,
                    "larger than " + std::to_string(kMaxTextureFileBytes >> 20) + " MiB"};
    }
    std::vector<unsigned char> bytes;
    try {
        bytes = readWholeFileBytes(path);
    } catch (const FileReadError& e) {
        TextureRead out;
        out.problem = cannotReadFile(e.reason);
        return out;
    }
    return decodeTexture(bytes, path.string());
}

}  // namespace penumbra
