#include "app/viewer/layout.h"

#include <algorithm>

namespace penumbra::viewer {

Layout computeLayout(int width, int height) {
    Layout l;
    l.width = width;
    l.height = height;
    l.leftWidth = std::clamp(width / 4, 0, 340);
    l.rightWidth = std::clamp(width / 3, 0, 440);
    l.view.x = l.leftWidth;
    l.view.y = 0;
    l.view.width = std::max(1, width - l.leftWidth - l.rightWidth);
    l.view.height = std::max(1, height);

    const float h = static_cast<float>(height);
    const float left = static_cast<float>(l.leftWidth);
    const float precomputeTop = std::min(150.0f, 0.19f * h);
    const float treeTop = precomputeTop + std::min(150.0f, 0.19f * h);
    const float previewTop = treeTop + std::min(190.0f, 0.24f * h);
    l.scene = {0, 0, left, precomputeTop};
    l.precompute = {0, precomputeTop, left, treeTop - precomputeTop};
    l.tree = {0, treeTop, left, previewTop - treeTop};
    l.preview = {0, previewTop, left, h - previewTop};

    const float x = static_cast<float>(width - l.rightWidth);
    const float right = static_cast<float>(l.rightWidth);
    l.point = {x, 0, right, 0.3f * h};
    l.lightPlane = {x, 0.3f * h, right, 0.3f * h};
    l.path = {x, 0.6f * h, right, h - 0.6f * h};
    return l;
}

}  // namespace penumbra::viewer
