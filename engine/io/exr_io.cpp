#include "engine/io/exr_io.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>

#include <algorithm>
#include <cstdint>
#include <exception>
#include <stdexcept>

namespace penumbra {
namespace exr_detail {

// An in-memory Imf::OStream: the library writes the header, the scanline blocks, then seeks back
// to fill in the offset table, so writes may overwrite what is already there.
class StringStream : public Imf::OStream {
  public:
    explicit StringStream(std::string& bytes) : Imf::OStream("memory"), bytes_(bytes) {}

    void write(const char c[], int n) override {
        const size_t end = pos_ + static_cast<size_t>(n);
        if (end > bytes_.size()) bytes_.resize(end);
        std::copy(c, c + n, bytes_.begin() + static_cast<std::ptrdiff_t>(pos_));
        pos_ = end;
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = static_cast<size_t>(pos); }

  private:
    std::string& bytes_;
    size_t pos_ = 0;
};

}  // namespace exr_detail

std::string encodeExr(int width, int height, std::span<const float> rgb) {
    const std::string what = "OpenEXR encoding failed (" + std::to_string(width) + "x" +
                             std::to_string(height) + ", " + std::to_string(rgb.size()) +
                             " floats)";
    if (width < 1 || height < 1 || rgb.size() != static_cast<size_t>(width) * height * 3)
        throw std::runtime_error(what + ": the image is empty or its size does not match");
    std::string bytes;
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        for (const char* name : {"R", "G", "B"})
            header.channels().insert(name, Imf::Channel(Imf::FLOAT));
        // The library reads through the frame buffer's pointers only (const_cast is its API).
        char* base = const_cast<char*>(reinterpret_cast<const char*>(rgb.data()));
        const size_t xStride = 3 * sizeof(float), yStride = xStride * static_cast<size_t>(width);
        Imf::FrameBuffer frame;
        frame.insert("R", Imf::Slice(Imf::FLOAT, base, xStride, yStride));
        frame.insert("G", Imf::Slice(Imf::FLOAT, base + sizeof(float), xStride, yStride));
        frame.insert("B", Imf::Slice(Imf::FLOAT, base + 2 * sizeof(float), xStride, yStride));
        exr_detail::StringStream stream(bytes);
        Imf::OutputFile file(stream, header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    } catch (const std::exception& e) {  // Iex::BaseExc is a std::exception
        throw std::runtime_error(what + ": " + e.what());
    }
    return bytes;
}

}  // namespace penumbra
