// CostSamples: the costs of the renderer's timed evaluations themselves (nanoseconds), so that a
// summary gives their median and 99th percentile as exact order statistics (nearest rank,
// engine/scene/quantiles.h), not only the mean. Renderer threads each fill their own and merge.
//
// Memory is bounded: up to kCapacity costs are kept, every one of them; past that only one in
// 2, then 4, ... (stride()) is kept, spread evenly over the order they came in, and the
// quantiles are those of the kept ones, a subsample that whoever reports them says is one.
// Costs are kept in single precision: whole nanoseconds exactly up to 2^24 ns (16.8 ms), to 1
// part in 2^24 beyond, and rounding keeps their order. The count and the sum, and so the mean,
// are of every cost added, in double precision.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/scene/quantiles.h"

namespace penumbra {

class CostSamples {
  public:
    // 2^20 costs, 4 MiB: every timed evaluation of a 512x512 render at 16 samples per pixel
    // with two lights (one evaluation in 8 timed) is kept.
    static constexpr size_t kCapacity = size_t{1} << 20;

    void add(double cost) {
        if (count_ % stride_ == 0) {
            kept_.push_back(static_cast<float>(cost));
            if (kept_.size() > kCapacity) thin();
        }
        ++count_;
        sum_ += cost;
    }
    // The nanoseconds elapsed since `start` (steady clock), as one cost.
    void addSince(std::chrono::steady_clock::time_point start) {
        add(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start)
                .count());
    }
    // Both sides' kept costs at the larger stride of the two (thinner again past kCapacity).
    CostSamples& operator+=(const CostSamples& o);

    uint64_t count() const { return count_; }
    double sum() const { return sum_; }
    double mean() const { return count_ == 0 ? 0.0 : sum_ / static_cast<double>(count_); }
    // 1 while every cost added is kept; n: about one in n is.
    uint64_t stride() const { return stride_; }
    size_t kept() const { return kept_.size(); }
    // Nearest-rank quantiles of the kept costs: of every cost added while stride() is 1. Zeros
    // when none was added.
    Quantiles quantiles() const;

    // Its whole state, to send it to another process (the cluster's render gathers the workers'
    // timed evaluations: engine/cluster/cluster_render.cpp), and back.
    struct Parts {
        std::vector<float> kept;
        uint64_t count = 0, stride = 1;
        double sum = 0;
    };
    Parts parts() const { return {kept_, count_, stride_, sum_}; }
    static CostSamples fromParts(Parts p) {
        CostSamples c;
        c.kept_ = std::move(p.kept);
        c.count_ = p.count;
        c.stride_ = p.stride;
        c.sum_ = p.sum;
        return c;
    }

  private:
    // Keeps every other kept cost and doubles the stride.
    void thin();

    std::vector<float> kept_;
    uint64_t count_ = 0, stride_ = 1;
    double sum_ = 0;
};

}  // namespace penumbra
