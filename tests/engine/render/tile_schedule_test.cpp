// Tests of the tile schedule: the tiles cover the image once, each is handed out once across
// threads, and a pass after a whole one takes its tiles by decreasing cost of that pass.
#include "engine/render/tile_schedule.h"

#include <gtest/gtest.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <mutex>
#include <utility>
#include <vector>

namespace penumbra {
namespace {

std::vector<int> handedOut(TileSchedule& schedule) {
    std::vector<int> order;
    for (int t = schedule.next(); t >= 0; t = schedule.next()) order.push_back(t);
    return order;
}

TEST(TileSchedule, TilesCoverEveryPixelOnce) {
    const std::vector<std::pair<int, int>> sizes{{1, 1}, {7, 9}, {8, 8}, {17, 33}, {64, 8}, {9, 1}};
    for (const auto& [w, h] : sizes) {
        std::vector<int> covered(static_cast<size_t>(w) * h, 0);
        const int n = TileSchedule::tileCount(w, h);
        // Hand-derived: ceil(w / 8) * ceil(h / 8).
        EXPECT_EQ(n, ((w + 7) / 8) * ((h + 7) / 8)) << w << "x" << h;
        for (int i = 0; i < n; ++i) {
            const Tile t = TileSchedule::tileAt(i, w, h);
            ASSERT_TRUE(t.x0 < t.x1 && t.y0 < t.y1 && t.x1 <= w && t.y1 <= h) << w << "x" << h;
            EXPECT_LE(t.x1 - t.x0, TileSchedule::kTileSize);
            EXPECT_LE(t.y1 - t.y0, TileSchedule::kTileSize);
            for (int y = t.y0; y < t.y1; ++y)
                for (int x = t.x0; x < t.x1; ++x) ++covered[static_cast<size_t>(y) * w + x];
        }
        EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int c) { return c == 1; }))
            << w << "x" << h;
    }
}

TEST(TileSchedule, LaterPassesTakeTheMostExpensiveTilesFirst) {
    TileSchedule schedule;
    // 24 x 16 pixels: 3 x 2 tiles. The first pass has no estimate: image order.
    schedule.start(24, 16);
    EXPECT_EQ(handedOut(schedule), (std::vector<int>{0, 1, 2, 3, 4, 5}));
    const std::vector<int64_t> cost{5, 1, 9, 3, 9, 0};
    for (int t = 0; t < 6; ++t) schedule.record(t, cost[static_cast<size_t>(t)]);
    schedule.finish();
    // Decreasing cost, ties in image order.
    schedule.start(24, 16);
    EXPECT_EQ(handedOut(schedule), (std::vector<int>{2, 4, 0, 3, 1, 5}));
    // A pass that is not finished (cancelled) leaves the estimate as it was.
    for (int t = 0; t < 6; ++t) schedule.record(t, t == 5 ? 100 : 0);
    schedule.start(24, 16);
    EXPECT_EQ(handedOut(schedule), (std::vector<int>{2, 4, 0, 3, 1, 5}));
    // Another tile count has no estimate: image order.
    schedule.start(8, 16);
    EXPECT_EQ(handedOut(schedule), (std::vector<int>{0, 1}));
}

TEST(TileSchedule, HandsOutEachTileOnceAcrossThreads) {
    TileSchedule schedule;
    schedule.start(200, 120);  // 25 x 15 tiles
    std::mutex mutex;
    std::vector<int> all;
    tbb::parallel_for(0, 8, [&](int) {
        std::vector<int> mine = handedOut(schedule);
        std::lock_guard lock(mutex);
        all.insert(all.end(), mine.begin(), mine.end());
    });
    std::sort(all.begin(), all.end());
    ASSERT_EQ(all.size(), 375u);
    for (int i = 0; i < 375; ++i) EXPECT_EQ(all[static_cast<size_t>(i)], i);
    EXPECT_EQ(schedule.next(), -1);
}

}  // namespace
}  // namespace penumbra
