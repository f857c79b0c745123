#include "app/cli/arguments.h"

#include <CLI/CLI.hpp>
#include <limits>
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
                   "Exact: plane tests one point's query may make on the tree and direct paths; "
                   "a point that needs more takes the light-edge path (the same answer), and is "
                   "sampled with --light-samples rays and counted only over its limit too (0 = "
                   "no limit: every point on the first paths, often slower)")
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

void addLightMoveOptions(CLI::App& sub, LightMoveOptions& o) {
    sub.add_option("--move-light", o.light,
                   "Move area light N (0 = the first) as the Move light window does, about its "
                   "centre: --scale, then --rotate, then --translate; the trees it leaves true are "
                   "kept, the others rebuilt")
        ->type_name("N");
    sub.add_option("--translate", o.translate, "With --move-light: translate it by this")
        ->type_name("X,Y,Z");
    sub.add_option("--rotate", o.rotate,
                   "With --move-light: rotate it about its centre, degrees about x, then y, then z")
        ->type_name("AX,AY,AZ");
    sub.add_option("--scale", o.scale,
                   "With --move-light: scale it about its centre along the axes (each > 0)")
        ->type_name("S|SX,SY,SZ");
}

std::optional<std::pair<uint32_t, LightMove>> parseLightMove(const CLI::App& sub,
                                                             const LightMoveOptions& o,
                                                             std::string_view command) {
    const bool parts =
        sub.count("--translate") > 0 || sub.count("--rotate") > 0 || sub.count("--scale") > 0;
    if (sub.count("--move-light") == 0) {
        if (parts)
            throw usageError(std::string(command) +
                             ": --translate, --rotate and --scale move a light: give "
                             "--move-light N");
        return std::nullopt;
    }
    if (o.light < 0)
        throw usageError("--move-light: expected a light number (0, 1, ...), got " +
                         std::to_string(o.light));
    if (o.light > std::numeric_limits<uint32_t>::max())
        throw usageError("--move-light: no light " + std::to_string(o.light));
    LightMove move;
    if (sub.count("--translate") > 0) {
        const auto v = parseNumberList("--translate", o.translate, 3);
        move.translate = {v[0], v[1], v[2]};
    }
    if (sub.count("--rotate") > 0) {
        const auto v = parseNumberList("--rotate", o.rotate, 3);
        move.rotateDegrees = {v[0], v[1], v[2]};
    }
    if (sub.count("--scale") > 0) {
        const bool one = o.scale.find(',') == std::string::npos;
        const auto v = parseNumberList("--scale", o.scale, one ? 1 : 3);
        move.scale = one ? Vec3{v[0], v[0], v[0]} : Vec3{v[0], v[1], v[2]};
    }
    if (const auto problem = lightMoveProblem(move))
        throw usageError("--move-light " + std::to_string(o.light) + ": " + *problem);
    return std::pair{static_cast<uint32_t>(o.light), move};
}

}  // namespace penumbra::cli
