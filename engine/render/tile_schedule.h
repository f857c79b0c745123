// TileSchedule: the tiles of an image and the order in which a pass hands them to the cores.
//
// With every point exact, the cost of a pixel spans five orders of magnitude (a lit floor pixel
// is a tree walk of a microsecond, a pixel under foliage a boundary chain of tens of
// milliseconds), and the expensive ones bunch: a few tiles hold most of a pass's work. A pass
// that hands out tiles in image order ends with one core finishing the last expensive tile while
// the others wait. So:
//   - tiles are small (kTileSize, one region cell of the exact method: the groups of points that
//     share the query's region decisions are the same as with larger tiles);
//   - each worker takes the next tile of one shared list (greedy list scheduling, not a static
//     split), and from a pass's second one on the list is ordered by the previous pass's cost of
//     each tile, the most expensive first (longest processing time first: the tail of a pass is
//     then at most about its cheapest tiles). Passes of one image differ only in their jitter, so
//     a tile's cost in the last pass predicts the next one's well; the first pass, with no
//     estimate, runs in image order.
// The order changes only which core shades a pixel and when: a pixel's value depends on its own
// random streams alone (renderer.h), so the image is the same for any order and thread count.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <numeric>
#include <vector>

namespace penumbra {

struct Tile {
    int x0, y0, x1, y1;
};

class TileSchedule {
  public:
    // Tiles are kTileSize pixels square (the last row and column cut by the image's edge).
    static constexpr int kTileSize = 8;

    static int tileCount(int width, int height) {
        return ((width + kTileSize - 1) / kTileSize) * ((height + kTileSize - 1) / kTileSize);
    }
    static Tile tileAt(int index, int width, int height) {
        const int tilesX = (width + kTileSize - 1) / kTileSize;
        const int tx = index % tilesX, ty = index / tilesX;
        return {tx * kTileSize, ty * kTileSize, std::min(width, (tx + 1) * kTileSize),
                std::min(height, (ty + 1) * kTileSize)};
    }

    // Starts a pass over a width x height image: the order of its tiles is by decreasing cost of
    // the last finished pass of the same tile count, image order when there is none.
    void start(int width, int height) {
        const size_t count = static_cast<size_t>(tileCount(width, height));
        order_.resize(count);
        std::iota(order_.begin(), order_.end(), 0u);
        if (estimate_.size() == count)
            std::stable_sort(order_.begin(), order_.end(), [this](uint32_t a, uint32_t b) {
                return estimate_[a] > estimate_[b];
            });
        cost_.assign(count, 0);
        next_.store(0, std::memory_order_relaxed);
    }
    // The next tile to shade, or -1 when every tile of the pass is handed out. Thread-safe.
    int next() {
        const size_t i = next_.fetch_add(1, std::memory_order_relaxed);
        return i < order_.size() ? static_cast<int>(order_[i]) : -1;
    }
    // How many tiles of the pass are not handed out yet (about, while others take them).
    size_t remaining() const {
        const size_t taken = next_.load(std::memory_order_relaxed);
        return taken < order_.size() ? order_.size() - taken : 0;
    }
    // What tile `index` cost in this pass (nanoseconds of its thread). Each tile is recorded by
    // the one thread that shaded it.
    void record(int index, int64_t ns) { cost_[static_cast<size_t>(index)] = ns; }
    // The pass is whole: its costs order the next pass. (A cancelled pass is not finished: its
    // unshaded tiles would read as free.)
    void finish() { estimate_.swap(cost_); }

  private:
    std::vector<uint32_t> order_;
    std::vector<int64_t> cost_, estimate_;
    std::atomic<size_t> next_{0};
};

}  // namespace penumbra
