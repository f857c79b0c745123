// Shared by the viewer tests: running the real `penumbra` executable (with the GL leak
// suppressions), reading its PNG and JSON outputs, and checking the fragment overlay of a
// screenshot against an independent point query.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/precompute/point_query.h"
#include "engine/scene/camera.h"
#include "tests/support/run_penumbra.h"

namespace penumbra::test {

struct Image {
    int width = 0, height = 0;
    std::vector<unsigned char> rgb;  // 3 bytes a pixel, top row first
    const unsigned char* at(int x, int y) const {
        return rgb.data() + (static_cast<size_t>(y) * width + x) * 3;
    }
};

std::filesystem::path sourceDir();
std::filesystem::path scratchDir(const std::string& name);  // empty, under the build tree
// runPenumbra (tests/support/run_penumbra.h) for the commands that open GL (screenshot, view):
// the child's LeakSanitizer first gets the GL suppressions, as runShell gives them.
ProcessResult runPenumbraGl(const std::vector<std::string>& args);
// Runs a shell command line, with the GL suppressions; returns its exit status (-1 if it did not
// exit).
int runShell(const std::string& command);
bool haveProgram(const std::string& name);

// assets/cornell_box.obj of the source tree, the scene most viewer tests shoot.
std::filesystem::path cornellObj();
// `penumbra screenshot` of the Cornell box at `size` without the preview (the panels and their
// layout do not depend on it), the PNG into dir/shot.png and the state into dir/state.json, with
// `extra` options after those; runs it (runPenumbraGl, its exit status expected 0) and returns the
// state (an empty object when the command failed). The process's result in *result if given.
nlohmann::json shootCornell(const std::filesystem::path& dir, const std::vector<std::string>& extra,
                            const std::string& size = "1280x800", ProcessResult* result = nullptr);
Image readPng(const std::filesystem::path& path);  // ADD_FAILURE and empty on error
nlohmann::json readJson(const std::filesystem::path& path);

// For every fragment of light `light` at point x (face `face`) as an independent queryPoint finds
// it, whose projection covers at least 60 pixels: the pixel at its projected centroid (or one of
// its 8 neighbours) in `image` has the fragment's palette colour. `viewport` is the 3D view's
// rectangle in the image (x, y, width, height). Returns the number of fragments checked.
int checkFragmentOverlay(const Image& image, const Camera& camera, const int viewport[4],
                         const std::filesystem::path& scene, uint32_t face, const Vec3& x,
                         uint32_t light);

}  // namespace penumbra::test
