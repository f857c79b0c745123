// CostHistogram: the distribution of a per-evaluation cost (nanoseconds, or plane tests) on a
// log scale, four buckets per doubling (each bucket spans a factor 2^(1/4), some 19%), so that
// renderer threads can count every evaluation cheaply and merge, and the summary can give the
// median and the 99th percentile, not only the mean. Quantiles are approximate to that factor
// (a bucket's geometric middle); the count and the sum are exact.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace penumbra {

class CostHistogram {
  public:
    static constexpr int kPerDoubling = 4;
    static constexpr size_t kBuckets = 64 * kPerDoubling;  // up to 2^64

    void add(double cost) {
        ++buckets_[bucketOf(cost)];
        ++count_;
        sum_ += cost;
    }
    // The nanoseconds elapsed since `start` (steady clock), as one cost.
    void addSince(std::chrono::steady_clock::time_point start) {
        add(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start)
                .count());
    }
    CostHistogram& operator+=(const CostHistogram& o) {
        for (size_t i = 0; i < kBuckets; ++i) buckets_[i] += o.buckets_[i];
        count_ += o.count_;
        sum_ += o.sum_;
        return *this;
    }
    uint64_t count() const { return count_; }
    double mean() const { return count_ == 0 ? 0.0 : sum_ / static_cast<double>(count_); }
    double sum() const { return sum_; }
    // The cost below which a fraction q (0..1) of the evaluations lie: the geometric middle of
    // the bucket holding the ceil(q * count)-th smallest; 0 without evaluations.
    double quantile(double q) const {
        if (count_ == 0) return 0;
        const auto rank = static_cast<uint64_t>(
            std::max(1.0, std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(count_))));
        uint64_t seen = 0;
        for (size_t i = 0; i < kBuckets; ++i) {
            seen += buckets_[i];
            if (seen >= rank) return i == 0 ? 0.0 : std::exp2((i + 0.5) / kPerDoubling);
        }
        return std::exp2(static_cast<double>(kBuckets) / kPerDoubling);
    }

  private:
    // Bucket 0 holds costs below 2^(1/4) (zero included); bucket i >= 1, [2^(i/4), 2^((i+1)/4)).
    static size_t bucketOf(double cost) {
        if (!(cost >= std::exp2(1.0 / kPerDoubling))) return 0;
        const double b = std::floor(std::log2(cost) * kPerDoubling);
        return static_cast<size_t>(std::min(b, static_cast<double>(kBuckets - 1)));
    }
    std::array<uint64_t, kBuckets> buckets_{};
    uint64_t count_ = 0;
    double sum_ = 0;
};

}  // namespace penumbra
