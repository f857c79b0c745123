#include "app/viewer/png_output.h"

#include <stb_image_write.h>

#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace penumbra::viewer {
namespace {

std::filesystem::path temporaryBeside(const std::filesystem::path& path) {
    std::filesystem::path tmp = path;
    tmp += ".tmp";
    return tmp;
}

void renameInto(const std::filesystem::path& tmp, const std::filesystem::path& path) {
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot write '" + path.string() + "': rename failed");
    }
}

}  // namespace

void writeRgbaPng(const std::filesystem::path& path, int width, int height,
                  const std::vector<uint8_t>& rgba) {
    if (rgba.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 4)
        throw std::invalid_argument("image data does not match " + std::to_string(width) + "x" +
                                    std::to_string(height));
    const std::filesystem::path tmp = temporaryBeside(path);
    if (stbi_write_png(tmp.c_str(), width, height, 4, rgba.data(), width * 4) == 0) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot write PNG file '" + path.string() + "'");
    }
    renameInto(tmp, path);
}

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
    const std::filesystem::path tmp = temporaryBeside(path);
    {
        std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
        out << text;
        out.flush();
        if (!out) throw std::runtime_error("cannot write file '" + path.string() + "'");
    }
    renameInto(tmp, path);
}

}  // namespace penumbra::viewer
