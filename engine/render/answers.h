// Answer: how the exact renderer answered one (shading point, area light) evaluation, so that a
// user sees per pixel which path the image took (the third promise: each decision visible) and
// where the work limit sampled instead (the one answer that is not exact).
//
// The film keeps, per pixel, how many of its evaluations (all passes, all area lights) took each
// answer (Film::answers); `penumbra render --out-answers`, the bench's Table 1 and the viewer's
// preview draw them with answerColour, each pixel the mean of its evaluations' colours.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

#include "visibility/vec3.h"

namespace penumbra {

enum class Answer : uint8_t {
    FullyVisible,    // a pair with nothing in its shaft and the light wholly above x's horizon:
                     // the whole light, no query
    HorizonClipped,  // a pair with nothing in its shaft whose light x's horizon (the receiver's
                     // plane) cuts: the part of the light above it, no query
    NoLight,         // a back-facing or fully hidden pair, or x behind the light's plane (or the
                     // light behind x's): no light, and no plane test beyond those signs
    TreeWalk,    // the pair's history tree walked from x (its deferred occluders clipped from x)
    Direct,      // no tree: the faces in x's pyramid to the light clipped from x (with or
                 // without face groups and solids)
    Chain,       // the boundary chain (silhouettes and borders) cut the light into cells
    Sampled,     // over the work limit, and the light-edge path's too: shadow rays, not exact
    LightEdges,  // over the work limit on the paths above, answered exactly by the light-edge
                 // path: the chain from the light's silhouette edges near x's cone
                 // (vis::LightEdgeIndex), no face activated
};
inline constexpr size_t kAnswers = 8;

// Per pixel: how many evaluations took each answer (indexed by Answer).
using AnswerCounts = std::array<uint32_t, kAnswers>;

constexpr const char* toString(Answer a) {
    switch (a) {
        case Answer::FullyVisible:
            return "fully visible";
        case Answer::HorizonClipped:
            return "horizon-clipped";
        case Answer::NoLight:
            return "no light";
        case Answer::TreeWalk:
            return "tree walk";
        case Answer::Direct:
            return "direct";
        case Answer::Chain:
            return "boundary chain";
        case Answer::Sampled:
            return "sampled";
        case Answer::LightEdges:
            return "light-edge path";
    }
    return "?";
}

// The colour an answer is drawn in (display values in [0, 1], written as they are: no tone
// curve), and its name for a legend.
struct AnswerColour {
    vis::Vec3 rgb;
    const char* name;
};
constexpr AnswerColour answerColour(Answer a) {
    switch (a) {
        case Answer::FullyVisible:
            return {{0.95, 0.85, 0.35}, "yellow"};
        case Answer::HorizonClipped:
            return {{0.90, 0.55, 0.15}, "orange"};
        case Answer::NoLight:
            return {{0.25, 0.25, 0.30}, "dark grey"};
        case Answer::TreeWalk:
            return {{0.20, 0.70, 0.30}, "green"};
        case Answer::Direct:
            return {{0.20, 0.50, 0.95}, "blue"};
        case Answer::Chain:
            return {{0.65, 0.35, 0.90}, "purple"};
        case Answer::Sampled:
            return {{0.95, 0.10, 0.10}, "red"};
        case Answer::LightEdges:
            return {{0.20, 0.85, 0.85}, "cyan"};
    }
    return {{0, 0, 0}, "black"};
}

// The mean colour of a pixel's evaluations; black where it has none (background, an emitter seen
// from behind, a light's own face).
inline vis::Vec3 answerPixel(const AnswerCounts& counts) {
    vis::Vec3 sum{};
    uint64_t n = 0;
    for (size_t i = 0; i < kAnswers; ++i) {
        sum = sum + answerColour(static_cast<Answer>(i)).rgb * static_cast<double>(counts[i]);
        n += counts[i];
    }
    return n == 0 ? vis::Vec3{} : sum / static_cast<double>(n);
}

// The evaluations of all pixels by answer.
inline std::array<uint64_t, kAnswers> totalAnswers(std::span<const AnswerCounts> pixels) {
    std::array<uint64_t, kAnswers> total{};
    for (const AnswerCounts& c : pixels)
        for (size_t i = 0; i < kAnswers; ++i) total[i] += c[i];
    return total;
}

// Each answer's share of all the evaluations, in percent (all 0 when there is none).
inline std::array<double, kAnswers> answerShares(const std::array<uint64_t, kAnswers>& total) {
    uint64_t all = 0;
    for (uint64_t n : total) all += n;
    std::array<double, kAnswers> share{};
    for (size_t i = 0; all > 0 && i < kAnswers; ++i)
        share[i] = 100.0 * static_cast<double>(total[i]) / static_cast<double>(all);
    return share;
}

// A legend with the shares: "fully visible (yellow) 41.2%, horizon-clipped (orange) 3.0%, ..." over
// all evaluations, every answer listed; "no evaluation" when there is none.
std::string describeAnswers(std::span<const AnswerCounts> pixels);

}  // namespace penumbra
