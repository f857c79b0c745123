// Tests of `penumbra render`, run as a real process (PENUMBRA_EXE): the files it writes, what it
// prints, and its exit codes for bad input.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "engine/render/answers.h"
#include "tests/app/viewer/viewer_test_support.h"
#include "tests/support/closed_forms.h"
#include "tests/support/read_exr.h"
#include "tests/support/read_pfm.h"
#include "tests/support/run_penumbra.h"

namespace {

namespace fs = std::filesystem;

// Floor [-2,2]^2 at z=0 facing up, a light [-0.5,0.5]^2 at z=2 facing down, a blocker at z=1.
const char* kObj =
    "mtllib scene.mtl\n"
    "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
    "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"
    "v 0 -0.5 1\nv 0 0.5 1\nv 1 0.5 1\nv 1 -0.5 1\n"
    "usemtl white\nf 1 2 3 4\n"
    "usemtl lamp\nf 5 6 7 8\n"
    "usemtl white\nf 9 10 11 12\n";
const char* kMtl = "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKd 0 0 0\nKe 10 10 10\n";

using penumbra::test::ProcessResult;

// Runs `penumbra render ARGS... MORE...`.
ProcessResult run(std::vector<std::string> args, const std::vector<std::string>& more = {}) {
    args.insert(args.begin(), "render");
    args.insert(args.end(), more.begin(), more.end());
    return penumbra::test::runPenumbra(args);
}

// Everything the command printed: stdout, then stderr.
std::string output(const ProcessResult& r) { return r.out + r.err; }

class RenderCommand : public ::testing::Test {
  protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("penumbra_render_cmd_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::create_directories(dir_);
        std::ofstream(dir_ / "scene.obj") << kObj;
        std::ofstream(dir_ / "scene.mtl") << kMtl;
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    // The scene and a small, fast view: the arguments most renders here start with.
    std::vector<std::string> base() const {
        std::vector<std::string> args = {path("scene.obj"), "--camera", "0.3,-5,1.5,0,0,0.3,40"};
        args.insert(args.end(), {"--up", "0,0,1", "--size", "16x12", "--spp", "2"});
        // A tree for every pair, however few samples (what the --visibility tests count).
        args.insert(args.end(), {"--min-tree-samples", "0"});
        return args;
    }
    fs::path dir_;
};

TEST_F(RenderCommand, WritesPngAndPfmAndExplainsItself) {
    const ProcessResult r = run(base(), {"--out", path("a.png"), "--out", path("a.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("time: precompute"), std::string::npos) << output(r);
    EXPECT_NE(output(r).find("shading"), std::string::npos) << output(r);
    EXPECT_NE(output(r).find("pairs never seen"), std::string::npos) << output(r);
    EXPECT_NE(output(r).find("materials analytic"), std::string::npos) << output(r);
    std::ifstream pfm(path("a.pfm"), std::ios::binary);
    std::string magic;
    int w = 0, h = 0;
    double scale = 0;
    pfm >> magic >> w >> h >> scale;
    EXPECT_EQ(magic, "PF");
    EXPECT_EQ(w, 16);
    EXPECT_EQ(h, 12);
    EXPECT_EQ(scale, -1.0);
    pfm.get();
    const std::string data((std::istreambuf_iterator<char>(pfm)), std::istreambuf_iterator<char>());
    EXPECT_EQ(data.size(), 16u * 12 * 3 * 4);
    std::ifstream png(path("a.png"), std::ios::binary);
    std::string sig(8, '\0');
    png.read(sig.data(), 8);
    EXPECT_EQ(sig, std::string("\x89PNG\r\n\x1a\n", 8));
}

// --out FILE.exr: OpenEXR, read back by the library's own reader, 32-bit float RGB holding the
// very floats of the PFM written by the same render.
TEST_F(RenderCommand, WritesOpenExrWithThePfmsValues) {
    const ProcessResult r = run(base(), {"--out", path("a.exr"), "--out", path("a.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("wrote " + path("a.exr")), std::string::npos) << output(r);
    const penumbra::test::ExrImage exr = penumbra::test::readExr(path("a.exr"));
    EXPECT_EQ(exr.width, 16);
    EXPECT_EQ(exr.height, 12);
    EXPECT_EQ(exr.channelTypes, (std::vector<std::string>{"float", "float", "float"}));
    int w = 0, h = 0;
    const std::vector<float> pfm = penumbra::test::readPfm(path("a.pfm"), w, h);
    ASSERT_EQ(exr.rgb.size(), pfm.size());
    size_t differ = 0, lit = 0;
    for (size_t i = 0; i < pfm.size(); ++i) {
        differ += exr.rgb[i] != pfm[i];
        lit += pfm[i] > 0;
    }
    EXPECT_EQ(differ, 0u);
    EXPECT_GT(lit, 0u);
}

// --out-answers writes how each pixel was answered (engine/render/answers.h) and prints the
// shares: without a work limit nothing is sampled; with a limit of one plane test and no
// light-edge path after it the blocker's penumbra is, and those pixels are drawn in the sampled
// colour; with the path after it (the default) they are its, and none is sampled.
TEST_F(RenderCommand, WritesHowEachPixelWasAnswered) {
    auto pixelsOf = [&](const std::string& file, penumbra::Answer answer) {
        const penumbra::vis::Vec3 colour = penumbra::answerColour(answer).rgb;
        const penumbra::test::Image img = penumbra::test::readPng(file);
        EXPECT_EQ(img.width, 16);
        EXPECT_EQ(img.height, 12);
        int n = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const unsigned char* p = img.at(x, y);
                n += p[0] == std::lround(255 * colour.x) && p[1] == std::lround(255 * colour.y) &&
                     p[2] == std::lround(255 * colour.z);
            }
        return n;
    };
    auto sampledPixels = [&](const std::string& file) {
        return pixelsOf(file, penumbra::Answer::Sampled);
    };
    ProcessResult r = run(base(), {"--exact-work-limit", "0", "--out", path("a.png"),
                                   "--out-answers", path("exact.png")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("exact.png: how each pixel was answered"), std::string::npos)
        << output(r);
    EXPECT_NE(output(r).find("sampled (red) 0.0%"), std::string::npos) << output(r);
    EXPECT_EQ(sampledPixels(path("exact.png")), 0);
    r = run(base(), {"--exact-work-limit", "1", "--light-edge-work-limit", "0", "--out",
                     path("a.png"), "--out-answers", path("limited.png")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_EQ(output(r).find("sampled (red) 0.0%"), std::string::npos) << output(r);
    EXPECT_GT(sampledPixels(path("limited.png")), 0);
    r = run(base(), {"--exact-work-limit", "1", "--out", path("a.png"), "--out-answers",
                     path("edges.png")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("sampled (red) 0.0%"), std::string::npos) << output(r);
    EXPECT_EQ(output(r).find("light-edge path (cyan) 0.0%"), std::string::npos) << output(r);
    EXPECT_EQ(sampledPixels(path("edges.png")), 0);
    EXPECT_GT(pixelsOf(path("edges.png"), penumbra::Answer::LightEdges), 0);
}

// Two occluders standing on the floor with vertices below it by less than a rounding unit (2^-60,
// and the residue 0.1 * 3 - 0.3 = 5.55e-17 written out in full): the exact render used to lose
// such an occluder whole and light its shadow. No pixel of `render --method exact` may be brighter
// than the converged shadow-ray reference shows it (beyond that reference's noise).
TEST_F(RenderCommand, ExactRenderKeepsTheShadowsOfHairCrossingOccluders) {
    std::ofstream(path("hair.obj")) << "mtllib scene.mtl\n"
                                       "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
                                       "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"
                                       "v -0.9 -0.5 -8.6736173798840355e-19\n"
                                       "v -0.2 -0.6 1.1\nv -0.5 0.1 0.9\n"
                                       "v 0.2 -0.3 -5.5511151231257827e-17\n"
                                       "v 0.9 -0.2 1.2\nv 0.5 0.4 1.0\n"
                                       "usemtl white\nf 1 2 3 4\n"
                                       "usemtl lamp\nf 5 6 7 8\n"
                                       "usemtl white\nf 9 10 11\nf 12 13 14\n";
    const std::vector<std::string> view = {
        path("hair.obj"), "--camera", "0.3,-5,3,0,0,0,40",  "--up", "0,0,1", "--size", "24x18",
        "--spp",          "2",        "--min-tree-samples", "0"};
    const ProcessResult exact = run(view, {"--method", "exact", "--out", path("exact.pfm")});
    ASSERT_EQ(exact.exitCode, 0) << output(exact);
    const ProcessResult ref = run(view, {"--method", "reference", "--reference-samples", "2048",
                                         "--out", path("reference.pfm")});
    ASSERT_EQ(ref.exitCode, 0) << output(ref);
    int w = 0, h = 0, w2 = 0, h2 = 0;
    const std::vector<float> e = penumbra::test::readPfm(path("exact.pfm"), w, h);
    const std::vector<float> r = penumbra::test::readPfm(path("reference.pfm"), w2, h2);
    ASSERT_EQ(w, w2);
    ASSERT_EQ(h, h2);
    float brightest = 0;
    for (float v : r) brightest = std::max(brightest, v);
    ASSERT_GT(brightest, 0.f);
    int shadowed = 0;
    for (size_t i = 0; i < e.size(); ++i) {
        // 2048 rays per light and 2 primary samples: the reference's noise is below 2% of the
        // brightest pixel; an occluder lost whole lights a shadowed pixel by far more.
        EXPECT_LE(e[i], r[i] + 0.05f * brightest) << "channel " << i % 3 << " of pixel " << i / 3;
        shadowed += r[i] < 0.5f * brightest && r[i] > 0;
    }
    EXPECT_GT(shadowed, 10);  // the occluders do cast shadows in this view
}

// The sampled method against the exact render of the same view, its expectation: the primary
// samples are the same, so a pixel differs only by the noise of its 2 x 16 stratified shadow rays
// (under 0.04 here, a tenth of the brightest reflection). Black pixels (background, umbra) stay
// black, the lamp seen directly is the same, each lit pixel is within a quarter of the brightest
// reflection and their mean within 3% (some 4 standard errors).
TEST_F(RenderCommand, SampledMethodAgreesWithTheExactRender) {
    ProcessResult r = run(base(), {"--out-pfm", path("e.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    r = run(base(), {"--method", "sampled", "--light-samples", "16", "--out-pfm", path("s.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("16 stratified shadow rays"), std::string::npos) << output(r);
    int w = 0, h = 0, w2 = 0, h2 = 0;
    const std::vector<float> e = penumbra::test::readPfm(path("e.pfm"), w, h);
    const std::vector<float> s = penumbra::test::readPfm(path("s.pfm"), w2, h2);
    ASSERT_EQ(w, w2);
    ASSERT_EQ(h, h2);
    // Reflected light is below 0.6 here (kd 0.8 times Le 10 times the lamp's form factor, at most
    // 0.074 right under it); the lamp seen directly is 10, or 5 where one of a pixel's two samples
    // meets it.
    double brightest = 0, exactSum = 0, sampledSum = 0;
    int lit = 0;
    for (float v : e)
        if (v < 1) brightest = std::max(brightest, double(v));
    for (size_t i = 0; i < e.size(); ++i) {
        const std::string where = "channel " + std::to_string(i % 3) + " of pixel " +
                                  std::to_string(i / 3) + ": exact " + std::to_string(e[i]) +
                                  ", sampled " + std::to_string(s[i]);
        if (e[i] == 0 || e[i] >= 1) {
            EXPECT_EQ(s[i], e[i]) << where;
            continue;
        }
        EXPECT_NEAR(s[i], e[i], 0.25 * brightest) << where;
        exactSum += e[i];
        sampledSum += s[i];
        ++lit;
    }
    ASSERT_GT(lit, 100);  // the channels of some 70 lit pixels of the floor and the blocker
    EXPECT_NEAR(sampledSum / lit, exactSum / lit, 0.03 * exactSum / lit);
}

std::string slurp(const std::string& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// --visibility: the trees are written, read back by the next render (nothing rebuilt, the same
// image bit for bit as a render without the file), extended by another camera, and a damaged file
// is reported, recomputed and replaced.
TEST_F(RenderCommand, VisibilityFileIsReusedExtendedAndRepaired) {
    const std::string pvis = path("scene.pvis");
    ProcessResult r = run(base(), {"--out-pfm", path("plain.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    r = run(base(), {"--visibility", pvis, "--out-pfm", path("first.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("0 trees read"), std::string::npos) << output(r);
    ASSERT_TRUE(fs::exists(pvis));
    const auto firstSize = fs::file_size(pvis);

    r = run(base(), {"--visibility", pvis, "--out-pfm", path("second.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("none added"), std::string::npos) << output(r);
    EXPECT_EQ(slurp(path("second.pfm")), slurp(path("plain.pfm")));
    EXPECT_EQ(slurp(path("first.pfm")), slurp(path("plain.pfm")));

    // Another view sees other receiver patches: their trees are added to the file.
    r = run({path("scene.obj"), "--camera", "-3,4,2.5,0,0,0", "--up", "0,0,1", "--size", "16x12",
             "--spp", "2", "--min-tree-samples", "0", "--visibility", pvis, "--out-pfm",
             path("other.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("added, wrote"), std::string::npos) << output(r);
    EXPECT_GT(fs::file_size(pvis), firstSize);

    // One flipped byte in the payload: reported, recomputed, the file replaced by a valid one.
    {
        std::fstream f(pvis, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(60);
        const char c = static_cast<char>(f.get());
        f.seekp(60);
        f.put(static_cast<char>(c ^ 0x10));
    }
    r = run(base(), {"--visibility", pvis, "--out-pfm", path("repaired.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("scene.pvis"), std::string::npos) << output(r);
    EXPECT_NE(output(r).find("recomputing"), std::string::npos) << output(r);
    EXPECT_EQ(slurp(path("repaired.pfm")), slurp(path("plain.pfm")));
    r = run(base(), {"--visibility", pvis, "--out-pfm", path("again.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("none added"), std::string::npos) << output(r);

    // A corrupt file and a render that builds no tree (every pair evaluated directly): the file
    // is rewritten all the same, so the next run does not report it again.
    std::ofstream(pvis, std::ios::binary | std::ios::trunc) << "garbage";
    std::vector<std::string> direct = base();
    direct.back() = "1000000000";  // --min-tree-samples
    r = run(direct, {"--visibility", pvis, "--out-pfm", path("direct.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(output(r).find("recomputing"), std::string::npos) << output(r);
    EXPECT_NE(output(r).find("wrote"), std::string::npos) << output(r);
    r = run(direct, {"--visibility", pvis, "--out-pfm", path("direct2.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_EQ(output(r).find("recomputing"), std::string::npos) << output(r);
    EXPECT_EQ(slurp(path("direct2.pfm")), slurp(path("direct.pfm")));
}

TEST_F(RenderCommand, BadInputGetsAClearErrorAndExitCode) {
    ProcessResult r = run(base(), {"--size", "16by12", "--out", path("a.png")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("--size"), std::string::npos) << output(r);
    r = run(base(), {"--out", path("a.jpg")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find(".png, .pfm or .exr"), std::string::npos) << output(r);
    // A file that cannot be written: an input error naming it.
    r = run(base(), {"--out", path("missing/x.exr")});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(output(r).find("x.exr"), std::string::npos) << output(r);
    r = run(base(), {"--out", path("a.png"), "--out-answers", path("answers.jpg")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("--out-answers"), std::string::npos) << output(r);
    r = run(base(),
            {"--method", "sampled", "--out", path("a.png"), "--out-answers", path("answers.png")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("only the exact method"), std::string::npos) << output(r);
    EXPECT_FALSE(fs::exists(path("answers.png")));
    r = run(base(), {"--refine-levels", "4", "--out", path("a.png")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("--refine-levels"), std::string::npos) << output(r);
    r = run(base(), {"--method", "fancy", "--out", path("a.png")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("fancy"), std::string::npos) << output(r);
    r = run({path("scene.obj"), "--camera", "1,2,3,1,2", "--out", path("a.png")});
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("--camera"), std::string::npos) << output(r);
    r = run(base());
    EXPECT_EQ(r.exitCode, 2);
    EXPECT_NE(output(r).find("--out"), std::string::npos) << output(r);
    r = run({path("missing.obj"), "--out", path("a.png")});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(output(r).find("missing.obj"), std::string::npos) << output(r);
    r = run(base(), {"--out", path("no_such_dir/a.png")});
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(output(r).find("a.png"), std::string::npos) << output(r);
    EXPECT_FALSE(fs::exists(path("a.png")));
}

// A 2 x 2 floor at y = 0 facing up and a tile at y = 0.4 over its corner, no material (kd 0.8),
// no light.
const char* kUnlitObj =
    "v -1 0 -1\nv -1 0 1\nv 1 0 1\nv 1 0 -1\n"
    "v 0.5 0.4 0.5\nv 0.5 0.4 0.9\nv 0.9 0.4 0.9\nv 0.9 0.4 0.5\n"
    "f 1 2 3 4\nf 5 6 7 8\n";

// The scene has no light: the default light (engine/scene/default_light.h) lights it, and says
// so. By the rule, for bounds [-1, 1] x [0, 0.4] x [-1, 1] (diagonal D = sqrt(8.16)), the light is
// a 0.5 x 0.5 square centred on the y axis, D / 2 above y = 0.4, facing down, with emission
// E = 1 / F(D / 2), F(c) the form factor of the square from a point c below its centre facing it
// (Howell's closed form, four corner rectangles). The floor's centre, D / 2 + 0.4 below it and
// seen by nothing in between, then has radiance kd E F(D / 2 + 0.4): derived by hand, not
// captured from a run. No receiver sees more of the light than the top of the scene's centre:
// every pixel is at most kd.
TEST_F(RenderCommand, SceneWithoutLightsGetsTheDefaultLightAndSaysSo) {
    std::ofstream(path("unlit.obj")) << kUnlitObj;
    // Looking down at the floor's centre: the centre pixel of an odd-sized image is the ray to it.
    const std::vector<std::string> view = {
        path("unlit.obj"), "--camera", "0,2,1,0,0,0,30", "--size", "33x33", "--spp", "4"};
    ProcessResult r = run(view, {"--out", path("lit.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(r.err.find("penumbra: warning: " + path("unlit.obj") +
                         " has no lights: added a default area light"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("--no-default-light turns it off"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("area lights: 1 (the default light: the scene has none of its own; "
                         "--no-default-light turns it off) - one-sided"),
              std::string::npos)
        << r.out;
    int w = 0, h = 0;
    const std::vector<float> lit = penumbra::test::readPfm(path("lit.pfm"), w, h);
    ASSERT_EQ(w, 33);
    ASSERT_EQ(h, 33);
    const double kd = 0.8, half = 0.25, above = std::sqrt(8.16) / 2;
    const double expected = kd * penumbra::test::cornerFormFactor(half, half, above + 0.4) /
                            penumbra::test::cornerFormFactor(half, half, above);
    const size_t centre = (16 * 33 + 16) * 3;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(lit[centre + c], expected, 1e-3 * expected) << c;
    double sum = 0, most = 0;
    for (float v : lit) {
        sum += v;
        most = std::max<double>(most, v);
    }
    EXPECT_GT(sum / lit.size(), 0.1 * expected) << "the whole view is lit";
    EXPECT_LE(most, kd * (1 + 1e-9));

    // Turned off: the old black image and "area lights: none".
    r = run(view, {"--out", path("dark.pfm"), "--no-default-light"});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_EQ(r.err.find("default"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("area lights: none"), std::string::npos) << r.out;
    const std::vector<float> dark = penumbra::test::readPfm(path("dark.pfm"), w, h);
    EXPECT_EQ(std::count(dark.begin(), dark.end(), 0.0f), static_cast<ptrdiff_t>(dark.size()));
}

// The lamp's vertices in the other order: it faces up, away from the floor and the blocker. The
// render says which light and why; the image is black.
TEST_F(RenderCommand, FlippedLightIsNamedInAWarning) {
    std::string flipped = kObj;
    const std::string lamp = "usemtl lamp\nf 5 6 7 8\n";
    flipped.replace(flipped.find(lamp), lamp.size(), "usemtl lamp\nf 5 8 7 6\n");
    std::ofstream(path("flipped.obj")) << flipped;
    std::vector<std::string> args = base();
    args[0] = path("flipped.obj");
    const ProcessResult r = run(args, {"--out", path("f.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(r.err.find("penumbra: warning: " + path("flipped.obj") +
                         ": light 0 (face 1, material 'lamp', line 17): its normal points away "
                         "from every other face: flipped winding?"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("default light"), std::string::npos) << "it has a light: " << r.err;
}

// Lights the image gets nothing from: every pair it used back-facing or hidden. A lamp hung
// above the ceiling (z up: floor at 0, ceiling at 1 facing down, lamp at 2 facing down), and the
// default light over a closed room (a cube of inward faces, no light: y up, the light over its
// ceiling). The render names the light and says why, on stderr and in its summary (from the
// pairs' trees: a tree for every pair here; a pair evaluated without one is taken as lit).
TEST_F(RenderCommand, LightTheImageGetsNothingFromIsNamed) {
    std::ofstream(path("above.obj")) << "mtllib scene.mtl\n"
                                        "v -2 -2 0\nv 2 -2 0\nv 2 2 0\nv -2 2 0\n"
                                        "v -3 -3 1\nv -3 3 1\nv 3 3 1\nv 3 -3 1\n"
                                        "v -0.5 -0.5 2\nv -0.5 0.5 2\nv 0.5 0.5 2\nv 0.5 -0.5 2\n"
                                        "usemtl white\nf 1 2 3 4\nf 5 6 7 8\n"
                                        "usemtl lamp\nf 9 10 11 12\n";
    ProcessResult r =
        run({path("above.obj"), "--camera", "0,-2.5,0.5,0,0,0,60", "--up", "0,0,1", "--size",
             "16x12", "--spp", "1", "--min-tree-samples", "0", "--out", path("above.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    const std::string hidden =
        ": light 0 (face 2, material 'lamp', line 18) is hidden from every "
        "receiver the image sees";
    EXPECT_NE(r.err.find("penumbra: warning: " + path("above.obj") + hidden), std::string::npos)
        << r.err;
    EXPECT_NE(r.out.find("warning: " + path("above.obj") + hidden), std::string::npos) << r.out;

    std::ofstream(path("room.obj")) << "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\n"
                                       "v -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
                                       "f 2 3 4 1\nf 8 7 6 5\nf 5 6 2 1\nf 6 7 3 2\n"
                                       "f 7 8 4 3\nf 8 5 1 4\n";
    r = run({path("room.obj"), "--camera", "0,0,0.9,0,-0.5,-1,60", "--size", "16x12", "--spp", "1",
             "--min-tree-samples", "0", "--out", path("room.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_NE(r.err.find("has no lights: added a default area light"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("light 0 (face 6, material 'penumbra_default_light'), the default light, "
                         "is hidden from every receiver the image sees"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("a closed room's ceiling"), std::string::npos) << r.err;
    // And a lit scene says nothing of the kind.
    r = run(base(), {"--out", path("lit.pfm")});
    ASSERT_EQ(r.exitCode, 0) << output(r);
    EXPECT_EQ(r.err.find("hidden from"), std::string::npos) << r.err;
}

}  // namespace
