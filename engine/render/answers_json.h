// How the exact renderer answered its evaluations (engine/render/answers.h) as JSON, for the
// bench's bench.json and the viewer's state (--state-out): {"fully visible": N, "no light": N,
// ...}, every answer listed.
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>

#include "engine/render/answers.h"

namespace penumbra {

// The evaluations by answer (totalAnswers).
inline nlohmann::json answerTotalsJson(const std::array<uint64_t, kAnswers>& total) {
    nlohmann::json out = nlohmann::json::object();
    for (size_t i = 0; i < kAnswers; ++i) out[toString(static_cast<Answer>(i))] = total[i];
    return out;
}

// Over all pixels; null when there are none (a render that is not exact).
inline nlohmann::json answerTotalsJson(std::span<const AnswerCounts> pixels) {
    if (pixels.empty()) return nullptr;
    return answerTotalsJson(totalAnswers(pixels));
}

}  // namespace penumbra
