// `penumbra query SCENE (--point X,Y,Z | --points FILE) [--face F] [--light K]`
//
// For each point: the face it lies on (given, or found with findFaceContaining), then for every
// light (or only light K) the exactly visible fragments of the light and the quantities derived
// from them (engine/precompute/point_query.h). One JSON object per point, one line each, on
// stdout, in the schema of a point's answer (engine/precompute/point_answer_json.h, the viewer's
// too). A point strictly behind its face's plane (a rounding: a point within findFaceContaining's
// tolerance of the face, or given with --face) is answered from the nearest point the filter
// certifies in front, some ulps away ("answered_point"). A pair with a partial tree (its build
// stopped at the budget, --max-lp-solves) adds "deferred_occluders" and "deferred_clipped".
//
// The points file holds one point a line, "x y z [face]"; blank lines and '#' comments are
// skipped. A face on the line wins over --face; without either the face is found. Every point is
// read and located before anything is printed, so an error leaves stdout empty.
#include <CLI/CLI.hpp>
#include <cmath>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "app/cli/arguments.h"
#include "app/cli/commands.h"
#include "engine/io/finite_output.h"
#include "engine/io/text_input.h"
#include "engine/precompute/point_answer_json.h"
#include "engine/precompute/point_query.h"

namespace penumbra::cli {
namespace {

struct QueryOptions {
    std::string scene;
    std::string point;
    std::string pointsFile;
    std::string face;
    std::string light;
    ExactOptions exact;
    SceneOptions sceneOptions;
};

// One point to query, and where it came from ("--point" or "FILE:LINE") for messages.
struct QueryPoint {
    Vec3 x;
    std::optional<uint32_t> face;
    std::string where;
};

// A face or light number: a non-negative integer that fits in 32 bits (text_input's rules), the
// whole of s but for blanks around it.
std::optional<uint32_t> parseIndex(std::string_view s) {
    const std::optional<int64_t> v = parseInteger(trim(s), {0, UINT32_MAX});
    if (!v) return std::nullopt;
    return static_cast<uint32_t>(*v);
}

std::optional<uint32_t> parseIndexFlag(const CLI::App& sub, const char* flag,
                                       const std::string& value) {
    if (sub.count(flag) == 0) return std::nullopt;
    const std::optional<uint32_t> v = parseIndex(value);
    if (!v)
        throw usageError(std::string(flag) + ": expected a non-negative integer, got " +
                         quoteForMessage(value));
    return v;
}

std::vector<QueryPoint> readPointsFile(const std::string& file) {
    std::string content;
    try {
        content = readWholeFile(file);
    } catch (const FileReadError& e) {
        throw inputError(e.what());
    }
    std::vector<QueryPoint> points;
    std::string_view rest = content;
    for (int64_t lineNumber = 1; !rest.empty(); ++lineNumber) {
        const std::string_view line = rest.substr(0, rest.find('\n'));
        rest.remove_prefix(std::min(rest.size(), line.size() + 1));
        const std::string where = file + ":" + std::to_string(lineNumber);
        std::vector<std::string_view> tokens;
        appendWords(line.substr(0, line.find('#')), tokens);
        if (tokens.empty()) continue;
        const auto fail = [&](const std::string& why) {
            return inputError(where + ": " + why + " (expected 'x y z [face]'), got " +
                              quoteForMessage(trim(line)));
        };
        if (tokens.size() < 3 || tokens.size() > 4)
            throw fail(std::to_string(tokens.size()) + " fields");
        QueryPoint p;
        double xyz[3];
        for (int i = 0; i < 3; ++i) {
            const std::optional<double> v = parseFinite(tokens[static_cast<size_t>(i)]);
            if (!v)
                throw fail("coordinate " + quoteForMessage(tokens[static_cast<size_t>(i)]) +
                           " is not a finite number");
            xyz[i] = *v;
        }
        p.x = {xyz[0], xyz[1], xyz[2]};
        if (tokens.size() == 4) {
            p.face = parseIndex(tokens[3]);
            if (!p.face)
                throw fail("face " + quoteForMessage(tokens[3]) + " is not a non-negative integer");
        }
        p.where = where;
        points.push_back(std::move(p));
    }
    return points;
}

void runQuery(const CLI::App& sub, const QueryOptions& options) {
    // Command-line problems first (exit 2), before any file is read.
    const bool hasPoint = sub.count("--point") > 0, hasPoints = sub.count("--points") > 0;
    if (hasPoint == hasPoints) throw usageError("query: give exactly one of --point or --points");
    const std::optional<uint32_t> faceFlag = parseIndexFlag(sub, "--face", options.face);
    const std::optional<uint32_t> lightFlag = parseIndexFlag(sub, "--light", options.light);
    std::vector<QueryPoint> points;
    if (hasPoint) {
        const std::vector<double> x = parseNumberList("--point", options.point, 3);
        points.push_back({{x[0], x[1], x[2]}, faceFlag, "--point"});
    }

    const Scene scene = loadSceneFile(options.scene, options.sceneOptions.load());
    if (hasPoints) {
        points = readPointsFile(options.pointsFile);
        for (QueryPoint& p : points)
            if (!p.face) p.face = faceFlag;
    }
    if (faceFlag && *faceFlag >= scene.faceCount())
        throw inputError("--face " + std::to_string(*faceFlag) + " out of range: " + options.scene +
                         " has " + std::to_string(scene.faceCount()) + " faces");
    if (lightFlag && *lightFlag >= scene.lights.size())
        throw inputError("--light " + std::to_string(*lightFlag) + " out of range: " +
                         options.scene + " has " + std::to_string(scene.lights.size()) +
                         (scene.lights.size() == 1 ? " light" : " lights"));

    // Locate every point before printing anything.
    std::vector<uint32_t> faces;
    faces.reserve(points.size());
    for (const QueryPoint& p : points) {
        if (p.face) {
            if (*p.face >= scene.faceCount())
                throw inputError(p.where + ": face " + std::to_string(*p.face) +
                                 " out of range: " + options.scene + " has " +
                                 std::to_string(scene.faceCount()) + " faces");
            if (const auto problem = pointOffFace(scene, *p.face, p.x))
                throw inputError(p.where + ": " + *problem);
            faces.push_back(*p.face);
            continue;
        }
        const FaceLookup lookup = findFaceContaining(scene, p.x);
        if (!lookup.ok()) throw inputError(p.where + ": " + lookup.error);
        faces.push_back(*lookup.face);
    }

    VisibilityStore::Options storeOptions;
    options.exact.applyTo(storeOptions);
    VisibilityStore store(scene, nullptr, storeOptions);
    for (size_t i = 0; i < points.size(); ++i) {
        const std::vector<LightAtPoint> lights =
            queryPoint(store, faces[i], points[i].x, lightFlag);
        const nlohmann::json answer = pointAnswerJson(scene, faces[i], points[i].x, lights);
        requireFinite(answer, "the answer for point " + std::to_string(i));
        std::cout << answer.dump() << '\n';
    }
    std::cout.flush();
    if (!std::cout) throw inputError("cannot write to standard output");
}

}  // namespace

void registerQueryCommand(CLI::App& app) {
    auto options = std::make_shared<QueryOptions>();
    CLI::App* sub = app.add_subcommand(
        "query",
        "Exact light visibility at points: for each light, the visible fragments of the light, "
        "the outline of the visible region, the visible fraction of its area and the form "
        "factor. One JSON object per point on stdout.");
    sub->add_option("scene", options->scene,
                    "Scene file: .obj (with its .mtl), .ply, .off, .stl, .gltf, .glb or .json")
        ->required()
        ->type_name("SCENE");
    CLI::Option* point =
        sub->add_option("--point", options->point, "The point, on a face of the scene")
            ->type_name("X,Y,Z");
    CLI::Option* points =
        sub->add_option("--points", options->pointsFile,
                        "File of points, one 'x y z [face]' a line ('#' comments)")
            ->type_name("FILE");
    point->excludes(points);
    sub->add_option("--face", options->face,
                    "Receiver face of the point(s) (default: the face the point lies on)")
        ->type_name("F");
    sub->add_option("--light", options->light, "Only light K (default: every light)")
        ->type_name("K");
    addExactOptions(*sub, options->exact, ExactOptionSet::BuildOnly);
    addSceneOptions(*sub, options->sceneOptions);
    sub->callback([sub, options] { runQuery(*sub, *options); });
}

}  // namespace penumbra::cli
