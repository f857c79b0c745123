#include "app/viewer/overlay_geometry.h"

namespace penumbra::viewer {
namespace {

void push(std::vector<float>& out, const Vec3& p, Rgb c, float alpha = 1.0f) {
    out.insert(out.end(),
               {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z),
                c.r / 255.0f, c.g / 255.0f, c.b / 255.0f, alpha});
}

void segment(std::vector<float>& out, const Vec3& a, const Vec3& b, Rgb c) {
    push(out, a, c);
    push(out, b, c);
}

}  // namespace

OverlayGeometry buildOverlay(const PointInspection& inspection, double sceneSize,
                             std::optional<size_t> selectedLight) {
    OverlayGeometry g;
    const double r = 0.01 * sceneSize;
    const Vec3 x = inspection.point;
    for (const Vec3 axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
        segment(g.linesOnTop, x - axis * r, x + axis * r, kMarkerColour);
    segment(g.linesOnTop, x, x + inspection.normal * (6 * r), kMarkerColour);
    for (size_t k = 0; k < inspection.lights.size(); ++k) {
        const LightInspection& li = inspection.lights[k];
        for (size_t i = 0; i < li.result.fragments.size(); ++i) {
            const vis::Polygon3& f = li.result.fragments[i];
            const Rgb c = fragmentColour(i);
            for (size_t j = 1; j + 1 < f.size(); ++j) {
                push(g.fragmentTriangles, f[0], c);
                push(g.fragmentTriangles, f[j], c);
                push(g.fragmentTriangles, f[j + 1], c);
            }
            for (size_t j = 0; j < f.size(); ++j)
                segment(g.lines, f[j], f[(j + 1) % f.size()], kPieceEdgeColour);
        }
        // The visible region's boundary over the pieces' edges (drawn after them).
        for (const vis::Polygon3& loop : li.result.outline.loops)
            for (size_t j = 0; j < loop.size(); ++j)
                segment(g.lines, loop[j], loop[(j + 1) % loop.size()], kOutlineColour);
        if (selectedLight && *selectedLight != k) continue;
        for (const PathStep& s : li.steps) segment(g.linesOnTop, s.a, s.b, kPathEdgeColour);
    }
    return g;
}

}  // namespace penumbra::viewer
