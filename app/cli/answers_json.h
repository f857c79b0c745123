// The exact render's answers (engine/render/answers.h) as JSON, for the bench's bench.json and the
// viewer's state (--state-out): {"fully visible": N, "no light": N, ...} over all pixels, every
// answer listed; null when there are none (a render that is not exact).
#pragma once

#include <array>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <span>

#include "engine/render/answers.h"

namespace penumbra::cli {

inline nlohmann::json answerTotalsJson(std::span<const AnswerCounts> pixels) {
    if (pixels.empty()) return nullptr;
    const std::array<uint64_t, kAnswers> total = totalAnswers(pixels);
    nlohmann::json out = nlohmann::json::object();
    for (size_t i = 0; i < kAnswers; ++i) out[toString(static_cast<Answer>(i))] = total[i];
    return out;
}

}  // namespace penumbra::cli
