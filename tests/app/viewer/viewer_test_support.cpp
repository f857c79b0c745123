#include "tests/app/viewer/viewer_test_support.h"

#include <stb_image.h>
#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "app/viewer/palette.h"
#include "engine/io/obj_io.h"
#include "engine/raytrace/embree_scene.h"
#include "visibility/polygon_clip.h"

#ifndef PENUMBRA_EXE
#error "PENUMBRA_EXE must name the penumbra executable"
#endif
#ifndef PENUMBRA_SOURCE_DIR
#error "PENUMBRA_SOURCE_DIR must name the source tree"
#endif

namespace penumbra::test {

namespace fs = std::filesystem;

fs::path sourceDir() { return PENUMBRA_SOURCE_DIR; }

fs::path scratchDir(const std::string& name) {
    const fs::path dir = fs::path(PENUMBRA_EXE).parent_path().parent_path() / "test_scratch" / name;
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir;
}

static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// Under the sanitizer build, the child processes' LeakSanitizer ignores what the GL libraries
// keep at exit (tests/app/viewer/lsan_gl.supp); an LSAN_OPTIONS set by the caller wins.
static void suppressGlLeaksInChildren() {
    const std::string supp = (sourceDir() / "tests" / "app" / "viewer" / "lsan_gl.supp").string();
    setenv("LSAN_OPTIONS", ("suppressions=" + supp).c_str(), /*overwrite=*/0);
}

int runShell(const std::string& command) {
    suppressGlLeaksInChildren();
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

ProcessResult runPenumbraGl(const std::vector<std::string>& args) {
    suppressGlLeaksInChildren();
    return runPenumbra(args);
}

fs::path cornellObj() { return sourceDir() / "assets" / "cornell_box.obj"; }

nlohmann::json shootCornell(const fs::path& dir, const std::vector<std::string>& extra,
                            const std::string& size, ProcessResult* result) {
    std::vector<std::string> args = {"screenshot",
                                     cornellObj().string(),
                                     "--size",
                                     size,
                                     "--no-preview",
                                     "--out",
                                     (dir / "shot.png").string(),
                                     "--state-out",
                                     (dir / "state.json").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    fs::remove(dir / "state.json");  // never the state of a shot before
    const ProcessResult r = runPenumbraGl(args);
    EXPECT_EQ(r.exitCode, 0) << r.err;
    if (result != nullptr) *result = r;
    if (r.exitCode != 0) return nlohmann::json::object();
    return readJson(dir / "state.json");
}

bool haveProgram(const std::string& name) {
    return runShell("command -v " + shellQuote(name) + " >/dev/null 2>&1") == 0;
}

Image readPng(const fs::path& path) {
    Image img;
    int channels = 0;
    unsigned char* data = stbi_load(path.c_str(), &img.width, &img.height, &channels, 3);
    if (data == nullptr) {
        ADD_FAILURE() << "cannot read PNG " << path;
        return {};
    }
    img.rgb.assign(data, data + static_cast<size_t>(img.width) * img.height * 3);
    stbi_image_free(data);
    return img;
}

nlohmann::json readJson(const fs::path& path) {
    try {
        return nlohmann::json::parse(slurp(path));
    } catch (const std::exception& e) {
        ADD_FAILURE() << "cannot parse JSON " << path << ": " << e.what();
        return {};
    }
}

int checkFragmentOverlay(const Image& image, const Camera& camera, const int viewport[4],
                         const fs::path& scenePath, uint32_t face, const Vec3& x, uint32_t light) {
    const Scene scene = loadObj(scenePath);
    VisibilityStore store(scene);
    const std::vector<LightAtPoint> r = queryPoint(store, face, x, light);
    int checked = 0;
    for (size_t i = 0; i < r.front().fragments.size(); ++i) {
        const vis::Polygon3& f = r.front().fragments[i];
        // Projected polygon: its area and centroid in pixels.
        std::vector<std::pair<double, double>> p;
        bool visible = true;
        for (const Vec3& v : f) {
            double px = 0, py = 0;
            visible = visible && camera.project(v, viewport[2], viewport[3], px, py);
            p.emplace_back(viewport[0] + px, viewport[1] + py);
        }
        if (!visible) continue;
        double area2 = 0, cx = 0, cy = 0;
        for (size_t j = 0; j < p.size(); ++j) {
            const auto [x0, y0] = p[j];
            const auto [x1, y1] = p[(j + 1) % p.size()];
            const double c = x0 * y1 - x1 * y0;
            area2 += c;
            cx += (x0 + x1) * c;
            cy += (y0 + y1) * c;
        }
        if (std::abs(area2) / 2 < 60) continue;
        cx /= 3 * area2;
        cy /= 3 * area2;
        const viewer::Rgb want = viewer::fragmentColour(i);
        bool found = false;
        for (int dy = -1; dy <= 1 && !found; ++dy)
            for (int dx = -1; dx <= 1 && !found; ++dx) {
                const int px = static_cast<int>(cx) + dx, py = static_cast<int>(cy) + dy;
                if (px < 0 || py < 0 || px >= image.width || py >= image.height) continue;
                const unsigned char* c = image.at(px, py);
                found = std::abs(c[0] - want.r) <= 3 && std::abs(c[1] - want.g) <= 3 &&
                        std::abs(c[2] - want.b) <= 3;
            }
        const unsigned char* c = image.at(std::clamp(static_cast<int>(cx), 0, image.width - 1),
                                          std::clamp(static_cast<int>(cy), 0, image.height - 1));
        EXPECT_TRUE(found) << "fragment " << i << " at pixel (" << cx << ", " << cy
                           << "): expected colour " << int(want.r) << "," << int(want.g) << ","
                           << int(want.b) << ", found " << int(c[0]) << "," << int(c[1]) << ","
                           << int(c[2]);
        ++checked;
    }
    return checked;
}

}  // namespace penumbra::test
