#include "engine/render/answers.h"

#include <cstdio>

namespace penumbra {

std::string describeAnswers(std::span<const AnswerCounts> pixels) {
    const std::array<uint64_t, kAnswers> total = totalAnswers(pixels);
    uint64_t all = 0;
    for (uint64_t n : total) all += n;
    if (all == 0) return "no evaluation";
    const std::array<double, kAnswers> shares = answerShares(total);
    std::string out;
    for (size_t i = 0; i < kAnswers; ++i) {
        const auto a = static_cast<Answer>(i);
        char share[32];
        std::snprintf(share, sizeof share, " %.1f%%", shares[i]);
        if (!out.empty()) out += ", ";
        out += std::string(toString(a)) + " (" + answerColour(a).name + ")" + share;
    }
    return out;
}

}  // namespace penumbra
