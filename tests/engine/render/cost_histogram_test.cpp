// CostHistogram: quantiles of known distributions, by hand.
#include "engine/render/cost_histogram.h"

#include <gtest/gtest.h>

#include <cmath>

namespace penumbra {
namespace {

TEST(CostHistogram, QuantilesFallInTheBucketOfTheRankedCost) {
    CostHistogram h;
    EXPECT_EQ(h.quantile(0.5), 0.0);  // nothing counted
    // 98 costs of 100 and 2 of 10000: the median and the 98th value are 100, the 99th 10000.
    for (int i = 0; i < 98; ++i) h.add(100);
    h.add(10000);
    h.add(10000);
    EXPECT_EQ(h.count(), 100u);
    EXPECT_DOUBLE_EQ(h.mean(), (98 * 100.0 + 2 * 10000.0) / 100);
    // 100 lies in [2^(26/4), 2^(27/4)) = [90.5, 107.6): the bucket's middle 2^(26.5/4) = 98.7.
    EXPECT_NEAR(h.quantile(0.5), std::exp2(26.5 / 4), 1e-9);
    EXPECT_NEAR(h.quantile(0.98), std::exp2(26.5 / 4), 1e-9);
    // 10000 in [2^(53/4), 2^(54/4)) = [9741, 11585).
    EXPECT_NEAR(h.quantile(0.99), std::exp2(53.5 / 4), 1e-6);
    EXPECT_NEAR(h.quantile(1.0), std::exp2(53.5 / 4), 1e-6);
    // Every quantile within a factor 2^(1/4) of the cost it stands for.
    EXPECT_LT(std::fabs(std::log2(h.quantile(0.5) / 100)), 0.25);
}

TEST(CostHistogram, MergesAndKeepsZerosAndHugeCostsInTheEndBuckets) {
    CostHistogram a, b;
    a.add(0);
    a.add(0.5);
    b.add(1e30);
    b.add(-1);  // (no cost is negative; counted as the smallest)
    a += b;
    EXPECT_EQ(a.count(), 4u);
    EXPECT_EQ(a.quantile(0.5), 0.0);  // the two zeros and the -1 sit in bucket 0
    EXPECT_EQ(a.quantile(0.75), 0.0);
    // Beyond 2^64 the last bucket: its middle, 2^(255.5 / 4).
    EXPECT_NEAR(a.quantile(1.0), std::exp2(255.5 / 4), 1e6);
    CostHistogram c;
    c.add(1e15);  // a quarter of an hour in nanoseconds: still resolved
    EXPECT_LT(std::fabs(std::log2(c.quantile(0.5) / 1e15)), 0.25);
}

}  // namespace
}  // namespace penumbra
