#include "app/viewer/png_output.h"

#include <stdexcept>
#include <string>

#include "engine/io/atomic_file.h"
#include "engine/io/image_io.h"

namespace penumbra::viewer {

void writeRgbaPng(const std::filesystem::path& path, int width, int height,
                  const std::vector<uint8_t>& rgba) {
    if (rgba.size() != static_cast<size_t>(width) * static_cast<size_t>(height) * 4)
        throw std::invalid_argument("image data does not match " + std::to_string(width) + "x" +
                                    std::to_string(height));
    writeFileAtomically(path, encodePng(width, height, 4, rgba.data()));
}

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
    writeFileAtomically(path, text);
}

}  // namespace penumbra::viewer
