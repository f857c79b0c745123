// OpenEXR output (engine/io/exr_io.h, writeExr in engine/render/renderer.h): a known film written
// and read back with the OpenEXR library's reader (tests/support/read_exr.h) holds, pixel for
// pixel, exactly the floats of the film's mean radiance, as the PFM of the same film does; values
// a half could not hold (beyond 65504, below its smallest subnormal, more than 11 significant
// bits) tell float from half. Bad paths and bad films get errors naming the file.
#include "engine/io/exr_io.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/io/finite_output.h"
#include "engine/io/image_io.h"
#include "engine/render/renderer.h"
#include "tests/support/read_exr.h"
#include "tests/support/read_pfm.h"

namespace penumbra {
namespace exr_io_test {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() /
                         ("penumbra_exr_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

// 7x5 pixels, 3 passes: the mean is sum / 3, so most values are no short binary fractions.
Film knownFilm() {
    Film film;
    film.reset(7, 5);
    film.passes = 3;
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 7; ++x)
            film.sum[y * 7 + x] = {x + 0.1 * y, 1e-7 * (1 + x * y), 3e5 / (1 + x + 7 * y)};
    return film;
}

TEST(ExrOutput, WritesTheFilmsMeanAsFloatsExactly) {
    const fs::path dir = scratch("round_trip");
    const Film film = knownFilm();
    const std::string path = (dir / "image.exr").string();
    writeExr(film, path);

    const test::ExrImage exr = test::readExr(path);
    ASSERT_EQ(exr.width, 7);
    ASSERT_EQ(exr.height, 5);
    EXPECT_EQ(exr.channelTypes, (std::vector<std::string>{"float", "float", "float"}));
    EXPECT_TRUE(exr.zipCompressed);
    EXPECT_TRUE(exr.topDown);
    size_t beyondHalf = 0;
    for (int y = 0; y < 5; ++y) {
        for (int x = 0; x < 7; ++x) {
            const Vec3 m = film.mean(x, y);
            const float* p = &exr.rgb[(y * 7 + x) * 3];
            EXPECT_EQ(p[0], static_cast<float>(m.x)) << x << "," << y;
            EXPECT_EQ(p[1], static_cast<float>(m.y)) << x << "," << y;
            EXPECT_EQ(p[2], static_cast<float>(m.z)) << x << "," << y;
            // A half stops at 65504 and its smallest subnormal is 2^-24 (6e-8): these pixels
            // would have come back as infinity or zero or a step of 6e-8.
            beyondHalf += m.z > 65504;
            beyondHalf += m.y < std::ldexp(1.0, -24);
        }
    }
    EXPECT_GT(beyondHalf, 5u);

    // The PFM of the same film holds the same floats.
    writePfm(film, (dir / "image.pfm").string());
    int w = 0, h = 0;
    const std::vector<float> pfm = test::readPfm((dir / "image.pfm").string(), w, h);
    ASSERT_EQ(pfm.size(), exr.rgb.size());
    for (size_t i = 0; i < pfm.size(); ++i) EXPECT_EQ(pfm[i], exr.rgb[i]) << i;

    // Written atomically: no temporary left beside the two files.
    size_t files = 0;
    for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++files;
    EXPECT_EQ(files, 2u);
    fs::remove_all(dir);
}

TEST(ExrOutput, ChosenByTheExtension) {
    EXPECT_EQ(imageFormatOf("a/b.exr"), ImageFormat::Exr);
    EXPECT_EQ(imageFormatOf("B.EXR"), ImageFormat::Exr);
    EXPECT_EQ(imageFormatOf("b.pfm"), ImageFormat::Pfm);
    EXPECT_EQ(imageFormatOf("b.Png"), ImageFormat::Png);
    EXPECT_EQ(imageFormatOf("b.jpg"), std::nullopt);
    EXPECT_EQ(imageFormatOf("exr"), std::nullopt);

    const fs::path dir = scratch("dispatch");
    const Film film = knownFilm();
    writeImage(film, (dir / "x.exr").string(), ImageFormat::Exr);
    const test::ExrImage exr = test::readExr((dir / "x.exr").string());
    EXPECT_EQ(exr.rgb[3 * 8 + 2], static_cast<float>(film.mean(1, 1).z));
    fs::remove_all(dir);
}

TEST(ExrOutput, BadPathsAndFilmsGetErrorsNamingTheFile) {
    const fs::path dir = scratch("errors");
    const Film film = knownFilm();
    // A directory that does not exist.
    try {
        writeExr(film, (dir / "missing" / "x.exr").string());
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("x.exr"), std::string::npos) << e.what();
    }
    // A file that cannot be replaced (the path is a directory): the directory stays.
    fs::create_directories(dir / "taken.exr");
    try {
        writeExr(film, (dir / "taken.exr").string());
        ADD_FAILURE() << "no error";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("taken.exr"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::is_directory(dir / "taken.exr"));
    // An empty film, and one with a pixel that is not finite: nothing written.
    Film empty;
    EXPECT_THROW(writeExr(empty, (dir / "empty.exr").string()), std::runtime_error);
    Film nan = knownFilm();
    nan.sum[3].y = NAN;
    try {
        writeExr(nan, (dir / "nan.exr").string());
        ADD_FAILURE() << "no error";
    } catch (const NonFiniteOutput& e) {
        EXPECT_NE(std::string(e.what()).find("nan.exr"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir / "empty.exr"));
    EXPECT_FALSE(fs::exists(dir / "nan.exr"));
    // The encoder refuses pixels that do not match the size.
    const std::vector<float> six(6, 1.0f);
    EXPECT_THROW(encodeExr(3, 1, six), std::runtime_error);
    EXPECT_NO_THROW(encodeExr(2, 1, six));
    fs::remove_all(dir);
}

}  // namespace exr_io_test
}  // namespace penumbra
