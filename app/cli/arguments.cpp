#include "app/cli/arguments.h"

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "app/cli/commands.h"
#include "engine/io/text_input.h"
#include "engine/scene/scene_validation.h"

namespace penumbra::cli {
namespace {

// Up to maxCount finite numbers separated by commas, blanks allowed around each; nullopt when
// one is not a number or there are more.
std::optional<std::vector<double>> numbers(std::string_view text, size_t maxCount) {
    std::vector<double> out;
    std::string_view rest = text;
    while (true) {
        const size_t comma = rest.find(',');
        const std::optional<double> v = parseFinite(trim(rest.substr(0, comma)));
        if (!v || out.size() == maxCount) return std::nullopt;
        out.push_back(*v);
        if (comma == std::string_view::npos) return out;
        rest.remove_prefix(comma + 1);
    }
}

}  // namespace

std::vector<double> parseNumberList(std::string_view flag, std::string_view text, size_t count) {
    const auto v = numbers(text, count);
    if (!v || v->size() != count)
        throw usageError(std::string(flag) + ": expected " + std::to_string(count) +
                         " finite numbers separated by commas, got " + quoteForMessage(text));
    return *v;
}

std::array<int, 2> parseSize(std::string_view flag, std::string_view text, SizeRange range) {
    const size_t x = text.find('x');
    const IntegerRange side{range.min, range.max};
    NumberFault wFault = NumberFault::kMalformed, hFault = NumberFault::kMalformed;
    std::optional<int64_t> w, h;
    if (x != std::string_view::npos) {
        w = parseInteger(text.substr(0, x), side, &wFault);
        h = parseInteger(text.substr(x + 1), side, &hFault);
    }
    if ((!w && wFault == NumberFault::kMalformed) || (!h && hFault == NumberFault::kMalformed))
        throw usageError(std::string(flag) + ": expected WxH (e.g. 1280x800), got " +
                         quoteForMessage(text));
    if (!w || !h)
        throw usageError(std::string(flag) + ": " + quoteForMessage(text) + " out of range (" +
                         std::to_string(range.min) + ".." + std::to_string(range.max) +
                         " pixels a side)");
    return {static_cast<int>(*w), static_cast<int>(*h)};
}

Camera parseCamera(std::string_view flag, std::string_view text) {
    const auto v = numbers(text, 7);
    if (!v || (v->size() != 6 && v->size() != 7))
        throw usageError(std::string(flag) +
                         ": expected EX,EY,EZ,TX,TY,TZ[,FOV] (eye, target, vertical field of "
                         "view in degrees), got " +
                         quoteForMessage(text));
    Camera c;
    c.eye = {(*v)[0], (*v)[1], (*v)[2]};
    c.target = {(*v)[3], (*v)[4], (*v)[5]};
    if (v->size() == 7) c.fovYDegrees = (*v)[6];
    if (c.eye == c.target)
        throw usageError(std::string(flag) + ": the eye and the target are the same point");
    if (!(c.fovYDegrees > 0 && c.fovYDegrees < 180))
        throw usageError(std::string(flag) + ": field of view " + std::to_string(c.fovYDegrees) +
                         " out of range (0, 180) degrees");
    for (const Vec3* p : {&c.eye, &c.target})
        if (const auto problem = coordinateProblem(*p))
            throw usageError(std::string(flag) + ": " + *problem);
    return c;
}

Vec3 parseDirection(std::string_view flag, std::string_view text) {
    const std::vector<double> v = parseNumberList(flag, text, 3);
    if (v[0] == 0 && v[1] == 0 && v[2] == 0)
        throw usageError(std::string(flag) + ": expected a nonzero vector X,Y,Z, got " +
                         quoteForMessage(text));
    return {v[0], v[1], v[2]};
}

LoadOptions SceneOptions::load() const {
    LoadOptions o = strict ? LoadOptions::strictMode() : LoadOptions{};
    o.defaultLight = !noDefaultLight;
    return o;
}

void addSceneOptions(CLI::App& sub, SceneOptions& options) {
    sub.add_flag("--strict", options.strict,
                 "Refuse what the loaders would repair with a warning (degenerate faces, "
                 "non-planar or non-convex polygons, missing OBJ materials, unknown PLY header "
                 "lines): an error naming the file, the line and the problem");
    sub.add_flag("--no-default-light", options.noDefaultLight,
                 "Leave a scene without any light unlit (by default it gets a square area light "
                 "above it, facing down, announced on stderr)");
}

void addExactOptions(CLI::App& sub, ExactOptions& o, ExactOptionSet set) {
    sub.add_option("--max-lp-solves", o.maxLpSolves,
                   "Exact: build budget of one history tree in linear programs; a tree that "
                   "reaches it is partial, its remaining occluders clipped per point (the same "
                   "answer; 0 = no limit)")
        ->capture_default_str();
    if (set == ExactOptionSet::BuildOnly) return;
    sub.add_option("--min-tree-samples", o.minTreeSamples,
                   "Exact: a pair the image samples fewer times gets no history tree, its points "
                   "are evaluated directly (the same answer; 0 = a tree for every pair)")
        ->capture_default_str();
    sub.add_option("--grouped-shaft-min", o.groupedShaftMin,
                   "Exact: a pair whose shaft holds at least this many faces, a quarter of them "
                   "in face groups, gets no history tree: its points take the direct path with "
                   "the groups, as its partial tree's would (the same answer; 0 = build it)")
        ->capture_default_str();
    sub.add_option("--exact-work-limit", o.exactWorkLimit,
                   "Exact: plane tests one point's query may make; a point that needs more is "
                   "sampled with --light-samples rays and counted (0 = every point exact)")
        ->capture_default_str();
    sub.add_option("--light-edge-work-limit", o.lightEdgeWorkLimit,
                   "Exact: a point over --exact-work-limit first takes the light-edge path (the "
                   "light's silhouette edges near the point, the same answer) with this many "
                   "plane tests of its own, and is sampled only over them (0 = sampled at once)")
        ->capture_default_str();
    sub.add_option("--chain-min-occluders", o.chainMinOccluders,
                   "Exact: a point clipped against at least this many occluders, most of whose "
                   "edges cancel (closed, smooth meshes), is evaluated by their silhouette and "
                   "border edges only (the same answer; 0 = never)")
        ->capture_default_str();
    sub.add_option("--refine-levels", o.refineLevels,
                   "Exact: after each pass, a tree whose points reached the work limit has its "
                   "receiver patch split and the sub-patches holding those points get their own "
                   "trees, up to this many levels (the same answer; 0 = never)")
        ->check(CLI::Range(0, PatchLayout::kMaxRefineLevels))
        ->capture_default_str();
}

}  // namespace penumbra::cli
