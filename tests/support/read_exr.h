// Reading an OpenEXR file back for the tests with the OpenEXR library's own reader (the renderer's
// writer is engine/io/exr_io.h): the R, G, B channels converted to float by the library, top row
// first, 3 floats per pixel, and the header facts the tests check.
#pragma once

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <string>
#include <vector>

namespace penumbra::test {

struct ExrImage {
    int width = 0, height = 0;
    std::vector<float> rgb;  // top row first
    // Each of R, G, B as stored: "float", "half", "uint", or "missing".
    std::vector<std::string> channelTypes;
    bool zipCompressed = false;
    bool topDown = false;  // INCREASING_Y line order
};

// Throws what the library throws for a file it cannot read.
inline ExrImage readExr(const std::string& path) {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    ExrImage image;
    image.width = window.max.x - window.min.x + 1;
    image.height = window.max.y - window.min.y + 1;
    image.zipCompressed = header.compression() == Imf::ZIP_COMPRESSION;
    image.topDown = header.lineOrder() == Imf::INCREASING_Y;
    for (const char* name : {"R", "G", "B"}) {
        const Imf::Channel* c = header.channels().findChannel(name);
        image.channelTypes.push_back(!c                      ? "missing"
                                     : c->type == Imf::FLOAT ? "float"
                                     : c->type == Imf::HALF  ? "half"
                                                             : "uint");
    }
    image.rgb.assign(static_cast<size_t>(image.width) * image.height * 3, -1.0f);
    // The frame buffer is addressed by the data window's coordinates.
    const size_t xStride = 3 * sizeof(float), yStride = xStride * image.width;
    char* base = reinterpret_cast<char*>(image.rgb.data()) -
                 (static_cast<ptrdiff_t>(window.min.y) * yStride + window.min.x * xStride);
    Imf::FrameBuffer frame;
    frame.insert("R", Imf::Slice(Imf::FLOAT, base, xStride, yStride));
    frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xStride, yStride));
    frame.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xStride, yStride));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return image;
}

}  // namespace penumbra::test
