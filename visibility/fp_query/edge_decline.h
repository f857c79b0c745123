// EdgeDecline: why the light-edge path (edge_path.h) was not taken at a point, for the counts a
// render reports (the user sees why a point was answered otherwise, or sampled).
#pragma once

#include <cstddef>
#include <cstdint>

namespace penumbra::vis {

// Why the light-edge path was not taken at a point (FromPointQuery::lightEdgeDecline): taken
// (None); the boundary chain switched off; an index of another light or mesh; x strictly behind
// B's plane; a face cut by L's plane (Across) may meet the cone; too few of the edges found near
// the cone cancel (more than 1 / ChainOptions::gain of them keep a weight).
enum class EdgeDecline : uint8_t {
    None,
    ChainOff,
    OtherIndex,
    BehindReceiver,
    AcrossFace,
    FewCancel
};
inline constexpr size_t kEdgeDeclines = 6;

constexpr const char* toString(EdgeDecline d) {
    switch (d) {
        case EdgeDecline::None:
            return "taken";
        case EdgeDecline::ChainOff:
            return "boundary chain off";
        case EdgeDecline::OtherIndex:
            return "index of another light";
        case EdgeDecline::BehindReceiver:
            return "point behind its receiver's plane";
        case EdgeDecline::AcrossFace:
            return "a face cut by the light's plane near the cone";
        case EdgeDecline::FewCancel:
            return "few of the edges near the cone cancel";
    }
    return "?";
}

}  // namespace penumbra::vis
