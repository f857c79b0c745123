#include "engine/scene/procedural_scenes.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "engine/scene/random.h"

namespace penumbra {

namespace {

using vis::cross;
using vis::dot;

// Deterministic scene randomness: engine/scene/random.h's SplitMix64, with a range helper.
struct Rng : SplitMix64 {
    explicit Rng(uint64_t seed) : SplitMix64{seed} {}
    using SplitMix64::uniform;
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
};

enum MaterialId : int32_t { kWhite = 0, kLight = 1, kRed = 2, kGreen = 3, kWood = 4, kLeaf = 5 };

Vec3 newellNormal(const std::vector<Vec3>& p) {
    Vec3 n{};
    for (size_t i = 0; i < p.size(); ++i) n += cross(p[i], p[(i + 1) % p.size()]);
    return n;
}

Vec3 centroid(const std::vector<Vec3>& p) {
    Vec3 c{};
    for (const Vec3& v : p) c += v;
    return c / static_cast<double>(p.size());
}

class Builder {
  public:
    Builder() {
        auto mat = [](const char* name, Vec3 kd, Vec3 ke) {
            Material m;
            m.name = name;
            m.kd = kd;
            m.ke = ke;
            return m;
        };
        scene_.materials = {
            mat("white", {0.8, 0.8, 0.8}, {}),   mat("light", {0.8, 0.8, 0.8}, {15, 15, 15}),
            mat("red", {0.63, 0.065, 0.05}, {}), mat("green", {0.14, 0.45, 0.091}, {}),
            mat("wood", {0.5, 0.3, 0.15}, {}),   mat("leaf", {0.1, 0.5, 0.1}, {}),
        };
    }

    // Index of the vertex at exactly p (vertices with identical coordinates are shared).
    uint32_t vertex(const Vec3& p) {
        const std::array<double, 3> key{p.x, p.y, p.z};
        auto it = index_.find(key);
        if (it != index_.end()) return it->second;
        const auto i = static_cast<uint32_t>(scene_.mesh.vertices.size());
        scene_.mesh.vertices.push_back(p);
        index_.emplace(key, i);
        return i;
    }

    // One face with the vertices in the given order.
    void face(const std::vector<Vec3>& pts, int32_t material) {
        std::vector<uint32_t> idx;
        idx.reserve(pts.size());
        for (const Vec3& p : pts) idx.push_back(vertex(p));
        scene_.mesh.faces.push_back(std::move(idx));
        scene_.faceMaterial.push_back(material);
    }

    // One face, its vertex order reversed if needed so that its normal points along `front`.
    void faceToward(std::vector<Vec3> pts, Vec3 front, int32_t material) {
        if (dot(newellNormal(pts), front) < 0) std::reverse(pts.begin(), pts.end());
        face(pts, material);
    }

    // A convex polygon as a fan of triangles, oriented toward `front`.
    void fanToward(std::vector<Vec3> pts, Vec3 front, int32_t material) {
        if (dot(newellNormal(pts), front) < 0) std::reverse(pts.begin(), pts.end());
        for (size_t i = 1; i + 1 < pts.size(); ++i) face({pts[0], pts[i], pts[i + 1]}, material);
    }

    // A parallelepiped o + s*a + t*b + u*c (s,t,u in [0,1]) as triangles facing outward.
    // skipBottom omits the face u = 0 (the face resting on something).
    void parallelepiped(Vec3 o, Vec3 a, Vec3 b, Vec3 c, int32_t material, bool skipBottom = false) {
        const Vec3 center = o + (a + b + c) * 0.5;
        auto quad = [&](Vec3 p, Vec3 e1, Vec3 e2) {
            std::vector<Vec3> q{p, p + e1, p + e1 + e2, p + e2};
            fanToward(q, centroid(q) - center, material);
        };
        if (!skipBottom) quad(o, a, b);
        quad(o + c, a, b);
        quad(o, a, c);
        quad(o + b, a, c);
        quad(o, b, c);
        quad(o + a, b, c);
    }

    // Axis-aligned box [lo, hi], triangles facing outward.
    void box(Vec3 lo, Vec3 hi, int32_t material, bool skipBottom = false) {
        parallelepiped(lo, {hi.x - lo.x, 0, 0}, {0, hi.y - lo.y, 0}, {0, 0, hi.z - lo.z}, material,
                       skipBottom);
    }

    // Axis-aligned quad in the plane z = const, facing +z (up) or -z.
    void quadZ(double x0, double x1, double y0, double y1, double z, bool up, int32_t material) {
        faceToward({{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}}, {0, 0, up ? 1.0 : -1.0},
                   material);
    }

    uint32_t triangles() const { return triangleCount(scene_); }

    Scene finish() {
        scene_.faceSourceLine.assign(scene_.mesh.faces.size(), 0);
        scene_.collectLights();
        return std::move(scene_);
    }

  private:
    Scene scene_;
    std::map<std::array<double, 3>, uint32_t> index_;
};

// Rotation by k quarter turns about the z axis, then a translation: exact for any k.
struct Placement {
    int quarterTurns = 0;
    Vec3 offset{};
    Vec3 operator()(Vec3 p) const {
        for (int i = 0; i < ((quarterTurns % 4) + 4) % 4; ++i) p = {-p.y, p.x, p.z};
        return p + offset;
    }
};

// Box given in local coordinates, placed with a quarter-turn placement (stays axis-aligned).
void placedBox(Builder& b, const Placement& pl, Vec3 lo, Vec3 hi, int32_t material,
               bool skipBottom = false) {
    const Vec3 p = pl(lo), q = pl(hi);
    b.box({std::min(p.x, q.x), std::min(p.y, q.y), std::min(p.z, q.z)},
          {std::max(p.x, q.x), std::max(p.y, q.y), std::max(p.z, q.z)}, material, skipBottom);
}

// A chair seen in local coordinates facing -y (the table is at -y): seat, four legs, two back
// posts, a top rail and three slats. 120 triangles.
void chair(Builder& b, const Placement& pl) {
    const double s = 0.2;                                        // half seat width
    placedBox(b, pl, {-s, -s, 0.4375}, {s, s, 0.46875}, kWood);  // seat
    for (double x : {-s, s - 0.03125})
        for (double y : {-s, s - 0.03125})
            placedBox(b, pl, {x, y, 0}, {x + 0.03125, y + 0.03125, 0.4375}, kWood, true);
    for (double x : {-s, s - 0.03125})  // back posts, standing on the seat
        placedBox(b, pl, {x, s - 0.03125, 0.46875}, {x + 0.03125, s, 0.96875}, kWood, true);
    // top rail between the posts (touching them)
    placedBox(b, pl, {-s + 0.03125, s - 0.03125, 0.875}, {s - 0.03125, s, 0.9375}, kWood);
    for (int i = 0; i < 3; ++i) {  // slats between seat and rail
        const double x = -0.09375 + 0.078125 * i;
        placedBox(b, pl, {x, s - 0.0234375, 0.46875}, {x + 0.03125, s - 0.0078125, 0.875}, kWood);
    }
}

}  // namespace

uint32_t triangleCount(const Scene& scene) {
    uint32_t n = 0;
    for (const auto& f : scene.mesh.faces)
        n += f.size() >= 3 ? static_cast<uint32_t>(f.size() - 2) : 0;
    return n;
}

Scene makeStairs() {
    Builder b;
    b.quadZ(-1, 5, -1, 7, 0, true, kWhite);  // floor, face 0
    const int steps = 20;
    const double depth = 0.25, rise = 0.125;
    for (int i = 0; i < steps; ++i)
        b.box({0, depth * i, 0}, {2, depth * (i + 1), rise * (i + 1)}, kWhite, true);
    // back wall (y = 6, facing -y) and side wall (x = -0.5, facing +x)
    b.fanToward({{-1, 6, 0}, {5, 6, 0}, {5, 6, 4}, {-1, 6, 4}}, {0, -1, 0}, kWhite);
    b.fanToward({{-0.5, -1, 0}, {-0.5, 7, 0}, {-0.5, 7, 4}, {-0.5, -1, 4}}, {1, 0, 0}, kRed);
    // second side wall (x = 4.5, facing -x) and a ceiling above the light (z = 4, facing down)
    b.fanToward({{4.5, -1, 0}, {4.5, 7, 0}, {4.5, 7, 4}, {4.5, -1, 4}}, {-1, 0, 0}, kWhite);
    b.fanToward({{-1, -1, 4}, {5, -1, 4}, {5, 7, 4}, {-1, 7, 4}}, {0, 0, -1}, kWhite);
    // two posts standing on steps 2 and 17, a slanted handrail resting on them
    const int postSteps[2] = {2, 17};
    const double postTop = 1.0;
    for (int s : postSteps) {
        const double y = depth * s + 0.0625, z = rise * (s + 1);
        b.box({1.75, y, z}, {1.875, y + 0.125, z + postTop}, kWood, true);
    }
    const Vec3 railStart{1.75, depth * postSteps[0] + 0.0625, rise * (postSteps[0] + 1) + postTop};
    const Vec3 railRun{0, depth * (postSteps[1] - postSteps[0]) + 0.125,
                       rise * (postSteps[1] - postSteps[0])};
    b.parallelepiped(railStart, {0.125, 0, 0}, railRun, {0, 0, 0.0625}, kWood);
    b.quadZ(0.5, 2.5, 2, 3, 3.75, false, kLight);  // light
    return b.finish();
}

Scene makeTable() {
    Builder b;
    b.quadZ(-3, 3, -3, 3, 0, true, kWhite);  // floor, face 0
    // table: top, four legs, four apron boards
    const double tx = 0.75, ty = 0.5, top = 0.71875, thick = 0.03125;
    b.box({-tx, -ty, top}, {tx, ty, top + thick}, kWood);
    const double leg = 0.0625;
    for (double x : {-tx, tx - leg})
        for (double y : {-ty, ty - leg}) b.box({x, y, 0}, {x + leg, y + leg, top}, kWood, true);
    const double apronLow = top - 0.09375, apronT = 0.015625;
    b.box({-tx + leg, -ty, apronLow}, {tx - leg, -ty + apronT, top}, kWood);
    b.box({-tx + leg, ty - apronT, apronLow}, {tx - leg, ty, top}, kWood);
    b.box({-tx, -ty + leg, apronLow}, {-tx + apronT, ty - leg, top}, kWood);
    b.box({tx - apronT, -ty + leg, apronLow}, {tx, ty - leg, top}, kWood);
    // four chairs around it, each facing the table
    chair(b, {0, {0, 0.8125, 0}});
    chair(b, {1, {-1.0625, 0, 0}});
    chair(b, {2, {0, -0.8125, 0}});
    chair(b, {3, {1.0625, 0, 0}});
    // plant: a 12-sided pot standing on the table, soil disc, a triangular stem, leaves
    const double tableTop = top + thick;
    const int sides = 12;
    const double potR = 0.09375, potH = 0.125;
    const Vec3 potC{0.25, 0.125, tableTop};
    std::vector<Vec3> ringLo, ringHi;
    for (int i = 0; i < sides; ++i) {
        const double a = 2 * std::numbers::pi * i / sides;
        const Vec3 p{potC.x + potR * std::cos(a), potC.y + potR * std::sin(a), 0};
        ringLo.push_back({p.x, p.y, tableTop});
        ringHi.push_back({p.x, p.y, tableTop + potH});
    }
    for (int i = 0; i < sides; ++i) {
        const int j = (i + 1) % sides;
        std::vector<Vec3> q{ringLo[i], ringLo[j], ringHi[j], ringHi[i]};
        const Vec3 out = centroid(q) - Vec3{potC.x, potC.y, centroid(q).z};
        b.fanToward(q, out, kRed);
    }
    b.fanToward(ringHi, {0, 0, 1}, kWood);  // soil
    const double stemTop = tableTop + potH + 0.375;
    std::vector<Vec3> stemLo, stemHi;
    for (int i = 0; i < 3; ++i) {
        const double a = 2 * std::numbers::pi * i / 3;
        const Vec3 p{potC.x + 0.015625 * std::cos(a), potC.y + 0.015625 * std::sin(a), 0};
        stemLo.push_back({p.x, p.y, tableTop + potH});
        stemHi.push_back({p.x, p.y, stemTop});
    }
    for (int i = 0; i < 3; ++i) {
        const int j = (i + 1) % 3;
        std::vector<Vec3> q{stemLo[i], stemLo[j], stemHi[j], stemHi[i]};
        const Vec3 out = centroid(q) - Vec3{potC.x, potC.y, centroid(q).z};
        b.fanToward(q, out, kLeaf);
    }
    // leaves: fill up to 1,350 triangles in total (the light quad counts as two)
    Rng rng(0x7AB1E5EEDull);
    const uint32_t target = 1350 - 2;
    uint32_t have = b.triangles();
    while (have < target) {
        const double h = rng.uniform(tableTop + potH + 0.0625, stemTop + 0.125);
        const double ang = rng.uniform(0, 2 * std::numbers::pi);
        const double r = rng.uniform(0.02, 0.3);
        const Vec3 base{potC.x + r * std::cos(ang), potC.y + r * std::sin(ang), h};
        const double len = rng.uniform(0.04, 0.09), wid = rng.uniform(0.015, 0.035);
        const double tilt = rng.uniform(-0.6, 0.6), twist = rng.uniform(0, 2 * std::numbers::pi);
        const Vec3 along{std::cos(ang) * std::cos(tilt), std::sin(ang) * std::cos(tilt),
                         std::sin(tilt)};
        const Vec3 side{-std::sin(ang) * std::cos(twist), std::cos(ang) * std::cos(twist),
                        std::sin(twist) * 0.5};
        const Vec3 p0 = base - side * wid, p1 = base + side * wid, p2 = base + along * len;
        const Vec3 n = cross(p1 - p0, p2 - p0);
        const double e =
            std::max({vis::length(p1 - p0), vis::length(p2 - p1), vis::length(p0 - p2)});
        if (vis::length(n) < 0.1 * e * e) continue;  // keep leaves well shaped
        b.faceToward({p0, p1, p2}, n, kLeaf);
        ++have;
    }
    b.quadZ(-0.5, 0.5, -0.5, 0.5, 2.5, false, kLight);  // light
    return b.finish();
}

Scene makeGrids() {
    Builder b;
    for (double x0 : {-1.0, 0.0})  // floor: 2x2 quads, faces 0..3
        for (double y0 : {-1.0, 0.0}) b.quadZ(x0, x0 + 1, y0, y0 + 1, 0, true, kWhite);
    const double hw = 0.0625;
    for (int j = 0; j < 6; ++j) {
        const double c = -0.625 + 0.25 * j;
        b.box({-1, c - hw, 1.0}, {1, c + hw, 1.0625}, kWood);  // lower grid: bars along x
    }
    for (int j = 0; j < 6; ++j) {
        const double c = -0.625 + 0.25 * j;
        b.box({c - hw, -1, 1.5}, {c + hw, 1, 1.5625}, kWood);  // upper grid: bars along y
    }
    b.quadZ(-0.5, 0.5, -0.5, 0.5, 2.5, false, kLight);
    return b.finish();
}

Scene makeCornellBox() {
    Builder b;
    const Vec3 center{278, 274.4, 279.6};
    auto inward = [&](std::vector<Vec3> q, int32_t m, bool asQuad) {
        const Vec3 dir = center - centroid(q);
        if (asQuad)
            b.faceToward(std::move(q), dir, m);
        else
            b.fanToward(std::move(q), dir, m);
    };
    inward({{552.8, 0, 0}, {0, 0, 0}, {0, 0, 559.2}, {549.6, 0, 559.2}}, kWhite, true);  // floor
    inward({{556, 548.8, 0}, {556, 548.8, 559.2}, {0, 548.8, 559.2}, {0, 548.8, 0}}, kWhite, false);
    inward({{549.6, 0, 559.2}, {0, 0, 559.2}, {0, 548.8, 559.2}, {556, 548.8, 559.2}}, kWhite,
           false);
    inward({{0, 0, 559.2}, {0, 0, 0}, {0, 548.8, 0}, {0, 548.8, 559.2}}, kGreen, false);
    // the left wall of the measured data is not planar: triangulated
    inward({{552.8, 0, 0}, {549.6, 0, 559.2}, {556, 548.8, 559.2}, {556, 548.8, 0}}, kRed, false);
    auto block = [&](const std::array<Vec3, 4>& topRing) {
        const double h = topRing[0].y;
        Vec3 c{};
        for (const Vec3& p : topRing) c += p;
        c = c / 4.0;
        c.y = h / 2;
        b.fanToward({topRing.begin(), topRing.end()}, {0, 1, 0}, kWhite);
        for (int i = 0; i < 4; ++i) {
            const Vec3 p = topRing[i], q = topRing[(i + 1) % 4];
            std::vector<Vec3> side{{p.x, 0, p.z}, {q.x, 0, q.z}, q, p};
            b.fanToward(side, centroid(side) - c, kWhite);
        }
    };
    block({Vec3{130, 165, 65}, Vec3{82, 165, 225}, Vec3{240, 165, 272}, Vec3{290, 165, 114}});
    block({Vec3{423, 330, 247}, Vec3{265, 330, 296}, Vec3{314, 330, 456}, Vec3{472, 330, 406}});
    b.faceToward({{343, 548, 227}, {343, 548, 332}, {213, 548, 332}, {213, 548, 227}}, {0, -1, 0},
                 kLight);
    return b.finish();
}

namespace {

// The common frame of the hard cases: floor [-2,2]^2 at z = 0 (face 0, up), light
// [-0.5,0.5]^2 at z = 2 (face 1, down).
void hardFrame(Builder& b) {
    b.quadZ(-2, 2, -2, 2, 0, true, kWhite);
    b.quadZ(-0.5, 0.5, -0.5, 0.5, 2, false, kLight);
}

Scene hardSharedVertices() {
    Builder b;
    hardFrame(b);
    // a tent of two triangles sharing an edge, and a third sharing a vertex with the tent
    b.face({{-0.5, -0.5, 1}, {0.5, -0.5, 1}, {0, 0, 1.5}}, kWhite);
    b.face({{0.5, -0.5, 1}, {0.5, 0.5, 1}, {0, 0, 1.5}}, kWhite);
    b.face({{0.5, 0.5, 1}, {0, 0.75, 0.75}, {-0.25, 0.25, 1}}, kWhite);
    // shares the light's edge y = -0.5
    b.face({{0.5, -0.5, 2}, {-0.5, -0.5, 2}, {0, -1, 1}}, kWhite);
    // shares a light vertex and a receiver vertex
    b.face({{-0.5, 0.5, 2}, {-2, 2, 0}, {-2, 1, 0}}, kWhite);
    // shares the receiver's edge x = 2
    b.face({{2, -2, 0}, {2, 2, 0}, {1.5, 0, 1}}, kWhite);
    // shares a light vertex and the tent's apex
    b.face({{0.5, 0.5, 2}, {0, 0, 1.5}, {0.5, 0.25, 1.5}}, kWhite);
    return b.finish();
}

Scene hardCollinear() {
    Builder b;
    hardFrame(b);
    // vertical quad hanging below the light edge y = -0.5: top edge collinear with (and longer
    // than) that edge, plane containing it
    b.face({{-1, -0.5, 1}, {1, -0.5, 1}, {1, -0.5, 2}, {-1, -0.5, 2}}, kWhite);
    // tilted quad through the light edge x = -0.5 (plane x = 0.5 z - 1.5)
    b.face({{-0.5, -1, 2}, {-1, -1, 1}, {-1, 1, 1}, {-0.5, 1, 2}}, kWhite);
    // coplanar with the light, sharing its edge x = 0.5
    b.face({{0.5, -0.5, 2}, {1, -0.5, 2}, {1, 0.5, 2}, {0.5, 0.5, 2}}, kWhite);
    // an edge on the line of the light edge y = 0.5, beyond the light
    b.face({{1, 0.5, 2}, {1.5, 0.5, 2}, {1.25, 0.25, 1}}, kWhite);
    // an edge on the supporting line of the light edge x = 0.5, beyond the light
    b.face({{0.5, 0.75, 2}, {0.5, 1.25, 2}, {0.25, 1, 1.5}}, kWhite);
    return b.finish();
}

Scene hardThroughLightVertices() {
    Builder b;
    hardFrame(b);
    // edge on the line through (0,0,1) and the light vertex (0.5,0.5,2)
    b.face({{-0.25, -0.25, 0.5}, {0.25, 0.25, 1.5}, {0.5, -0.5, 1}}, kWhite);
    // edge on the light's diagonal line, beyond the light
    b.face({{0.75, 0.75, 2}, {1, 1, 2}, {1, 0.75, 1.5}}, kWhite);
    // edge in the light's plane along its diagonal through the vertices (-0.5,0.5,2) and
    // (0.5,-0.5,2), longer than the light: the triangle touches the light along the diagonal
    b.face({{-1, 1, 2}, {1, -1, 2}, {0, 0, 1.25}}, kWhite);
    // edge whose line passes through the light vertex (-0.5,-0.5,2) and the receiver corner
    // (-2,-2,0): points (-1.25,-1.25,1) and (-0.875,-0.875,1.5)
    b.face({{-1.25, -1.25, 1}, {-0.875, -0.875, 1.5}, {-1.25, -0.5, 1.25}}, kWhite);
    return b.finish();
}

Scene hardTouchingLight() {
    Builder b;
    hardFrame(b);
    // box whose top face lies in the light's plane, inside the light (touching it)
    b.box({-0.25, -0.25, 1}, {0.25, 0.125, 2}, kWhite);
    // triangle touching the light's interior at one point
    b.face({{0.25, 0.375, 2}, {0, 0.25, 1}, {0.5, 0.25, 1}}, kWhite);
    // quad touching the light along a segment of its boundary edge x = 0.5
    b.face({{0.5, -0.25, 2}, {0.5, 0.25, 2}, {0.75, 0.25, 1.5}, {0.75, -0.25, 1.5}}, kWhite);
    return b.finish();
}

Scene hardStandingOnReceiver() {
    Builder b;
    hardFrame(b);
    b.box({-0.5, -0.25, 0}, {0.5, 0.25, 1}, kWhite);     // with its bottom face on the floor
    b.face({{1, -1, 0}, {1, 1, 0}, {1, 0, 1}}, kWhite);  // standing on an edge
    b.face({{-1, 1, 0}, {-1.5, 1.25, 0.5}, {-0.75, 1.5, 0.75}}, kWhite);  // on a vertex
    b.box({1.5, 1.5, 0}, {2, 2, 0.5}, kWhite, true);  // in the receiver's corner, sharing it
    return b.finish();
}

Scene hardCoplanarOverlap() {
    Builder b;
    hardFrame(b);
    // two overlapping coplanar quads at z = 1
    b.quadZ(-0.5, 0.25, -0.5, 0.5, 1, true, kWhite);
    b.quadZ(-0.25, 0.5, -0.25, 0.75, 1, false, kWhite);
    // T-junction at z = 1.25: the second quad's vertex (-0.5,-0.5) is interior to the first's
    // edge y = -0.5
    b.quadZ(-1, 0, -1, -0.5, 1.25, true, kWhite);
    b.quadZ(-0.5, 0.5, -0.5, 0, 1.25, true, kWhite);
    // T-junction between triangles of a strip
    b.face({{0, 0.5, 1.5}, {0.5, 0.5, 1.5}, {0.25, 1, 1.5}}, kWhite);
    b.face({{0.5, 0.5, 1.5}, {1, 0.5, 1.5}, {0.75, 1, 1.5}}, kWhite);
    b.face({{0, 0.25, 1.5}, {1, 0.25, 1.5}, {1, 0.5, 1.5}, {0, 0.5, 1.5}}, kWhite);
    return b.finish();
}

Scene hardSlivers() {
    Builder b;
    hardFrame(b);
    const double eps = 0x1.0p-20;  // ~9.5e-7: aspect ratio ~1e6
    b.face({{-0.5, 0, 1}, {0.5, 0, 1}, {0, eps, 1}}, kWhite);
    b.face({{-1, 0.125, 1.5}, {0, 0.125, 1.5 - eps}, {1, 0.125, 1.5}}, kWhite);
    b.face({{0, -1, 1.25}, {eps, -1, 1.25}, {0, 1, 1.25}}, kWhite);  // needle
    // sliver along the light's diagonal, just below it
    b.face({{-0.5, -0.5, 1.75}, {0.5, 0.5, 1.75}, {0.5 - eps, 0.5, 1.75}}, kWhite);
    return b.finish();
}

Scene hardGrazing() {
    Builder b;
    b.quadZ(-2, 2, -2, 2, 0, true, kWhite);
    // low light far to the side, facing the receiver (-x): elevation about 5 degrees
    b.faceToward({{4, -0.5, 0.125}, {4, 0.5, 0.125}, {4, 0.5, 0.375}, {4, -0.5, 0.375}}, {-1, 0, 0},
                 kLight);
    b.face({{3, -1, 0}, {3, 1, 0}, {3, 1, 0.25}, {3, -1, 0.25}}, kWhite);  // low wall
    b.face({{2.5, 0, 0.125}, {2.5, 0.25, 0.125}, {2.5, 0.125, 0.375}}, kWhite);
    return b.finish();
}

Scene hardStraddling() {
    Builder b;
    b.quadZ(-2, 2, -2, 2, 0, true, kWhite);
    // vertical light crossing the receiver's plane, facing -x
    b.faceToward({{3, -0.5, -0.5}, {3, 0.5, -0.5}, {3, 0.5, 0.5}, {3, -0.5, 0.5}}, {-1, 0, 0},
                 kLight);
    b.box({2.25, -0.25, -0.25}, {2.5, 0.25, 0.125}, kWhite);  // crossing the plane too
    b.face({{2, 0.125, 0.25}, {2, 0.5, 0.25}, {2, 0.25, 0.5}}, kWhite);
    return b.finish();
}

}  // namespace

std::vector<std::pair<std::string, Scene>> makeHardCases() {
    std::vector<std::pair<std::string, Scene>> cases;
    cases.emplace_back("shared_vertices", hardSharedVertices());
    cases.emplace_back("collinear_with_light_edges", hardCollinear());
    cases.emplace_back("through_light_vertices", hardThroughLightVertices());
    cases.emplace_back("touching_light", hardTouchingLight());
    cases.emplace_back("standing_on_receiver", hardStandingOnReceiver());
    cases.emplace_back("coplanar_overlap_tjunction", hardCoplanarOverlap());
    cases.emplace_back("slivers", hardSlivers());
    const Scene base = hardSharedVertices();
    cases.emplace_back("translated_1e5", transformed(base, 1.0, {1e5, 1e5, 1e5}));
    cases.emplace_back("scaled_1e-3", transformed(base, 1e-3, {}));
    cases.emplace_back("scaled_1e3", transformed(base, 1e3, {}));
    cases.emplace_back("grazing_light", hardGrazing());
    cases.emplace_back("straddling_horizon", hardStraddling());
    return cases;
}

Scene makeRandomSoup(int triangles, uint64_t seed) {
    Builder b;
    b.quadZ(0, 1, 0, 1, 0, true, kWhite);
    b.quadZ(0.25, 0.75, 0.25, 0.75, 2, false, kLight);
    Rng rng(seed);
    int made = 0;
    while (made < triangles) {
        const Vec3 c{rng.uniform(-0.25, 1.25), rng.uniform(-0.25, 1.25), rng.uniform(0.3, 1.7)};
        std::vector<Vec3> p;
        for (int k = 0; k < 3; ++k) {
            Vec3 d{rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)};
            const double l = vis::length(d);
            if (l < 0.1 || l > 1) {
                --k;
                continue;
            }
            p.push_back(c + d * (rng.uniform(0.05, 0.2) / l));
        }
        const Vec3 n = cross(p[1] - p[0], p[2] - p[0]);
        const double e = std::max(
            {vis::length(p[1] - p[0]), vis::length(p[2] - p[1]), vis::length(p[0] - p[2])});
        if (e < 0.05 || vis::length(n) < 0.1 * e * e) continue;
        b.face(p, kWhite);
        ++made;
    }
    return b.finish();
}

Scene transformed(const Scene& scene, double scale, Vec3 translate) {
    Scene out = scene;
    for (Vec3& v : out.mesh.vertices) v = v * scale + translate;
    return out;
}

}  // namespace penumbra
