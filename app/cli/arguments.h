// The command line's values, parsed once for every command: numbers, number lists, sizes,
// cameras, and the exact-visibility option group. Malformed values throw cli::CommandError (a
// usage error) naming the flag and quoting the value.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/io/load_options.h"
#include "engine/render/exact_options.h"
#include "engine/scene/camera.h"
#include "engine/scene/light_move.h"

namespace CLI {
class App;
}  // namespace CLI

namespace penumbra::cli {

// Exactly `count` finite numbers separated by commas, blanks allowed around each
// (engine/io/text_input.h parseFinite: locale-independent, one leading '+' allowed).
std::vector<double> parseNumberList(std::string_view flag, std::string_view text, size_t count);

// The sides an image or a window may have, in pixels.
struct SizeRange {
    int min = 1, max = 16384;
};
inline constexpr SizeRange kImageSize{1, 16384};   // rendered images (render, bench)
inline constexpr SizeRange kWindowSize{16, 8192};  // the viewer's window and screenshots
// "WxH" (an 'x'; nothing before, between or after but the two whole numbers), each in `range`.
std::array<int, 2> parseSize(std::string_view flag, std::string_view text, SizeRange range);

// "EX,EY,EZ,TX,TY,TZ" or with ",FOV" (vertical, degrees, in (0, 180)); up is +y. The eye must
// differ from the target; both within the coordinate contract.
Camera parseCamera(std::string_view flag, std::string_view text);

// A nonzero direction "X,Y,Z".
Vec3 parseDirection(std::string_view flag, std::string_view text);

// The exact-visibility option group (engine/render/exact_options.h), registered on a subcommand
// with the same names, help and defaults everywhere: --max-lp-solves always; --min-tree-samples
// and --exact-work-limit where the command renders images.
enum class ExactOptionSet { BuildOnly, Render };
void addExactOptions(CLI::App& sub, ExactOptions& options, ExactOptionSet set);

// How every subcommand that loads a scene loads it, registered once (addSceneOptions):
//   --strict: what the loaders repair with a warning by default (degenerate faces, non-planar
//     and non-convex polygons, missing OBJ materials, unknown PLY header lines;
//     engine/io/load_options.h) is an error instead;
//   --no-default-light: a scene with no light at all stays unlit (by default it gets the default
//     area light, engine/scene/default_light.h, announced on stderr).
struct SceneOptions {
    bool strict = false;
    bool noDefaultLight = false;
    LoadOptions load() const;
};
void addSceneOptions(CLI::App& sub, SceneOptions& options);

// Moving an area light as the viewer's Move light window does (engine/scene/light_move.h), the
// same in `view` and `screenshot` (addLightMoveOptions): --move-light N, and --translate X,Y,Z,
// --rotate AX,AY,AZ (degrees about x, then y, then z) and --scale S|SX,SY,SZ, which need it.
struct LightMoveOptions {
    int64_t light = -1;
    std::string translate, rotate, scale;
};
void addLightMoveOptions(CLI::App& sub, LightMoveOptions& options);
// The light and its move, or nullopt without --move-light. Throws a usage error for --translate,
// --rotate or --scale without --move-light, a negative light number, a malformed value or a move
// lightMoveProblem refuses (a scale factor of 0), naming the option. `command` names the
// subcommand in the message ("screenshot", "view").
std::optional<std::pair<uint32_t, LightMove>> parseLightMove(const CLI::App& sub,
                                                             const LightMoveOptions& options,
                                                             std::string_view command);

}  // namespace penumbra::cli
