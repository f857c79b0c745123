// Parsing of the viewer's command-line values (`penumbra view`, `penumbra screenshot`): number
// lists, sizes and cameras. Malformed values throw cli::CommandError (usage error) naming the
// flag and quoting the value.
#pragma once

#include <array>
#include <string_view>
#include <vector>

#include "engine/scene/camera.h"

namespace penumbra::cli {

// Exactly `count` finite numbers separated by commas.
std::vector<double> parseNumberList(std::string_view flag, std::string_view text, size_t count);
// "WxH", each in 16..8192.
std::array<int, 2> parseSize(std::string_view flag, std::string_view text);
// "EX,EY,EZ,TX,TY,TZ" or with ",FOV" (vertical, degrees, in (0, 180)); up is +y. The eye must
// differ from the target.
Camera parseCamera(std::string_view flag, std::string_view text);

}  // namespace penumbra::cli
