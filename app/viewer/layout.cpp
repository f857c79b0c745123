#include "app/viewer/layout.h"

#include <algorithm>

namespace penumbra::viewer {

Layout computeLayout(int width, int height, const LayoutSettings& settings) {
    Layout l;
    l.width = width;
    l.height = height;
    const float scale = std::clamp(settings.scale, 0.5f, 4.0f);
    const int leftDefault = std::clamp(width / 4, 0, static_cast<int>(340 * scale));
    const int rightDefault = std::clamp(width / 3, 0, static_cast<int>(440 * scale));
    l.leftWidth = settings.leftWidth > 0 ? settings.leftWidth : leftDefault;
    l.rightWidth = settings.rightWidth > 0 ? settings.rightWidth : rightDefault;
    // Columns never squeeze the view below its minimum (nor below zero on a tiny framebuffer):
    // the excess comes off both columns in proportion.
    const int minView = std::min(width, static_cast<int>(kMinViewWidth * scale));
    const int columns = l.leftWidth + l.rightWidth;
    if (columns > width - minView && columns > 0) {
        const int room = std::max(0, width - minView);
        l.leftWidth = static_cast<int>(static_cast<long>(l.leftWidth) * room / columns);
        l.rightWidth = room - l.leftWidth;
    }
    const int top = std::clamp(settings.top, 0, std::max(0, height - 1));
    l.view.x = l.leftWidth;
    l.view.y = top;
    l.view.width = std::max(1, width - l.leftWidth - l.rightWidth);
    l.view.height = std::max(1, height - top);

    const float y0 = static_cast<float>(top);
    const float h = static_cast<float>(height - top);
    const float left = static_cast<float>(l.leftWidth);
    const float precomputeTop = y0 + std::min(150.0f * scale, 0.19f * h);
    const float treeTop = precomputeTop + std::min(150.0f * scale, 0.19f * h);
    const float previewTop =
        settings.tree ? treeTop + std::min(190.0f * scale, 0.24f * h) : treeTop;
    l.scene = {0, y0, left, precomputeTop - y0};
    l.precompute = {0, precomputeTop, left, treeTop - precomputeTop};
    l.tree = {0, treeTop, left, previewTop - treeTop};
    l.preview = {0, previewTop, left, y0 + h - previewTop};

    const float x = static_cast<float>(width - l.rightWidth);
    const float right = static_cast<float>(l.rightWidth);
    l.point = {x, y0, right, 0.3f * h};
    l.lightPlane = {x, y0 + 0.3f * h, right, 0.3f * h};
    l.path = {x, y0 + 0.6f * h, right, h - 0.6f * h};
    l.help = l.path;
    const float margin = 0.04f * std::min(static_cast<float>(width), h);
    l.enlarged = {margin, y0 + margin, std::max(1.0f, static_cast<float>(width) - 2 * margin),
                  std::max(1.0f, h - 2 * margin)};
    return l;
}

}  // namespace penumbra::viewer
