// Nearest-rank quantiles (engine/scene/quantiles.h) of samples whose order statistics are
// counted by hand: the k-th smallest value, k = ceil(q * n).
#include "engine/scene/quantiles.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace penumbra {
namespace {

TEST(Quantiles, AreTheRankedValuesOfTheSample) {
    // n = 5: the median is the ceil(2.5) = 3rd smallest, the 99th percentile the ceil(4.95) =
    // 5th.
    Quantiles q = quantiles({5, 1, 4, 2, 3});
    EXPECT_EQ(q.median, 3);
    EXPECT_EQ(q.p99, 5);
    EXPECT_EQ(q.max, 5);
    // n = 10, even: the 5th smallest (no mean of the 5th and 6th), and the ceil(9.9) = 10th.
    q = quantiles({10, 9, 8, 7, 6, 5, 4, 3, 2, 1});
    EXPECT_EQ(q.median, 5);
    EXPECT_EQ(q.p99, 10);
    // n = 200, shuffled: the 100th and the 198th smallest of 1..200.
    std::vector<double> v(200);
    for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(i + 1);
    std::shuffle(v.begin(), v.end(), std::mt19937(7));
    q = quantiles(v);
    EXPECT_EQ(q.median, 100);
    EXPECT_EQ(q.p99, 198);
    EXPECT_EQ(q.max, 200);
}

TEST(Quantiles, OfOneValueAndOfNone) {
    const Quantiles one = quantiles({7.25});
    EXPECT_EQ(one.median, 7.25);
    EXPECT_EQ(one.p99, 7.25);
    EXPECT_EQ(one.max, 7.25);
    const Quantiles none = quantiles({});
    EXPECT_EQ(none.median, 0);
    EXPECT_EQ(none.p99, 0);
    EXPECT_EQ(none.max, 0);
}

}  // namespace
}  // namespace penumbra
