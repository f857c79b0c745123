// CostSamples: the medians and 99th percentiles of timed costs are order statistics of the costs
// themselves, counted here by hand, and its memory stays within kCapacity costs.
#include "engine/render/cost_samples.h"

#include <gtest/gtest.h>

#include <cstdint>

namespace penumbra {
namespace {

TEST(CostSamples, QuantilesAreTheRankedCosts) {
    CostSamples c;
    EXPECT_EQ(c.quantiles().median, 0.0);  // nothing added
    // 98 costs of 100 ns and 2 of 10000: the 50th and the 98th smallest are 100, the
    // ceil(0.99 * 100) = 99th is 10000.
    for (int i = 0; i < 98; ++i) c.add(100);
    c.add(10000);
    c.add(10000);
    EXPECT_EQ(c.count(), 100u);
    EXPECT_DOUBLE_EQ(c.mean(), (98 * 100.0 + 2 * 10000.0) / 100);
    const Quantiles q = c.quantiles();
    EXPECT_EQ(q.median, 100.0);
    EXPECT_EQ(q.p99, 10000.0);
    EXPECT_EQ(q.max, 10000.0);
    EXPECT_EQ(c.stride(), 1u);
    EXPECT_EQ(c.kept(), 100u);
}

TEST(CostSamples, TellApartCostsThatShareALogBucket) {
    // 1000 and 1010 ns differ by 1%, less than a bucket of the log histogram this replaced
    // (2^(1/4), 19%): both lay in [2^(39/4), 2^(40/4)) = [861, 1024) and read back as 912.
    CostSamples a, b;
    for (int i = 0; i < 3; ++i) {
        a.add(1000);
        b.add(1010);
    }
    EXPECT_EQ(a.quantiles().median, 1000.0);
    EXPECT_EQ(b.quantiles().median, 1010.0);
    // Whole nanoseconds up to 2^24 are kept exactly (single precision).
    CostSamples big;
    big.add(16777215);
    EXPECT_EQ(big.quantiles().median, 16777215.0);
}

TEST(CostSamples, MergedSamplesRankTheUnion) {
    CostSamples a, b;
    for (double v : {3.0, 1.0, 2.0}) a.add(v);
    for (double v : {7.0, 4.0, 6.0, 5.0}) b.add(v);
    a += b;
    // 1..7: the ceil(3.5) = 4th smallest, and the ceil(6.93) = 7th.
    EXPECT_EQ(a.count(), 7u);
    EXPECT_EQ(a.sum(), 28.0);
    EXPECT_EQ(a.quantiles().median, 4.0);
    EXPECT_EQ(a.quantiles().p99, 7.0);
    EXPECT_EQ(a.stride(), 1u);
}

TEST(CostSamples, PastItsCapacityKeepsOneInTwoAndSaysSo) {
    // The costs 0, 1, ..., kCapacity: one more than it keeps, so it keeps the even ones.
    CostSamples c;
    const uint64_t n = CostSamples::kCapacity + 1;
    for (uint64_t i = 0; i < n; ++i) c.add(static_cast<double>(i));
    EXPECT_EQ(c.stride(), 2u);
    EXPECT_EQ(c.kept(), CostSamples::kCapacity / 2 + 1);  // 0, 2, ..., 2^20
    EXPECT_EQ(c.count(), n);                              // the count and the mean: of all
    EXPECT_DOUBLE_EQ(c.mean(), static_cast<double>(CostSamples::kCapacity) / 2);
    // Of the 2^19 + 1 kept, the median is the ceil((2^19 + 1) / 2) = (2^18 + 1)-th smallest,
    // the cost 2 * 2^18; the largest is 2^20.
    EXPECT_EQ(c.quantiles().median, static_cast<double>(CostSamples::kCapacity / 2));
    EXPECT_EQ(c.quantiles().max, static_cast<double>(CostSamples::kCapacity));
    // The next cost, the (2^20 + 1)-th, is odd in the order: not kept.
    c.add(1e9);
    EXPECT_EQ(c.kept(), CostSamples::kCapacity / 2 + 1);
    EXPECT_EQ(c.quantiles().max, static_cast<double>(CostSamples::kCapacity));
    // Merged with a sample that kept every cost, it takes one in two of those too.
    CostSamples d;
    for (double v : {10.0, 11.0, 12.0, 13.0}) d.add(v);
    c += d;
    EXPECT_EQ(c.stride(), 2u);
    EXPECT_EQ(c.kept(), CostSamples::kCapacity / 2 + 3);  // 10 and 12
    EXPECT_EQ(c.count(), n + 1 + 4);
}

}  // namespace
}  // namespace penumbra
