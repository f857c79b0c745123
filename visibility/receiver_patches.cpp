#include "visibility/receiver_patches.h"

#include <algorithm>
#include <array>
#include <cfloat>
#include <cmath>
#include <limits>

#include "visibility/orient2d.h"

namespace penumbra::vis {
namespace {

double diameter(std::span<const Vec3> p) {
    double d = 0;
    for (size_t i = 0; i < p.size(); ++i)
        for (size_t j = i + 1; j < p.size(); ++j) d = std::max(d, length(p[i] - p[j]));
    return d;
}

// k, the cells per side of each fan triangle's grid: 1 (no subdivision) for a face of diameter
// d <= maxDiameter.
int cellsPerSide(double d, double maxDiameter) {
    if (maxDiameter <= 0 || d <= maxDiameter) return 1;
    return 1 << std::min(8, static_cast<int>(std::ceil(std::log2(d / maxDiameter))));
}

// The rounded barycentric coordinates of q in the projected fan triangle (a, b, c): u along
// a -> b, v along a -> c; false for a triangle of zero projected area.
bool barycentric(const Point2& a, const Point2& b, const Point2& c, const Point2& q, double& u,
                 double& v) {
    const double det = (b.u - a.u) * (c.v - a.v) - (b.v - a.v) * (c.u - a.u);
    if (det == 0) return false;
    u = ((q.u - a.u) * (c.v - a.v) - (q.v - a.v) * (c.u - a.u)) / det;
    v = ((b.u - a.u) * (q.v - a.v) - (b.v - a.v) * (q.u - a.u)) / det;
    return true;
}

}  // namespace

bool ReceiverPatches::contains(uint32_t patch, const Vec3& x) const {
    const Point2 q = projectDropping(x, dropAxis);
    if (patch < corners2d.size() && faceTurn != 0) {
        // A grid's triangle, projected once (subdivideReceiverGrid); it turns as the face does.
        const std::array<Point2, 3>& t = corners2d[patch];
        for (int i = 0; i < 3; ++i) {
            // The filter inline (a point of a patch is rarely within its rounding of an edge).
            int side = orient2dFiltered(t[i], t[(i + 1) % 3], q);
            if (side == 0) side = orient2d(t[i], t[(i + 1) % 3], q);
            if (side * faceTurn < 0) return false;
        }
        return true;
    }
    const std::vector<Vec3>& p = patches[patch];
    int turn = faceTurn;
    for (size_t i = 1; i + 1 < p.size() && turn == 0; ++i)
        turn = orient2d(projectDropping(p[0], dropAxis), projectDropping(p[i], dropAxis),
                        projectDropping(p[i + 1], dropAxis));
    if (turn == 0) return false;
    for (size_t i = 0; i < p.size(); ++i)
        if (orient2d(projectDropping(p[i], dropAxis),
                     projectDropping(p[(i + 1) % p.size()], dropAxis), q) *
                turn <
            0)
            return false;
    return true;
}

uint32_t ReceiverPatches::cellIndex(size_t fan, int i, int j, bool upper) const {
    // Patches were emitted per fan triangle, then per i, then per j: lower (i, j) then upper
    // (i, j) where there is one.
    const int k = cellsPerSide;
    uint32_t index = static_cast<uint32_t>(fan) * static_cast<uint32_t>(k * k);
    for (int r = 0; r < i; ++r) index += static_cast<uint32_t>(2 * (k - r) - 1);
    return index + static_cast<uint32_t>(2 * j) + (upper ? 1 : 0);
}

uint32_t ReceiverPatches::find(const Vec3& x, uint32_t hint) const {
    if (patches.size() <= 1) return 0;
    if (hint < patches.size() && contains(hint, x)) return hint;
    const int k = cellsPerSide;
    const Point2 q = projectDropping(x, dropAxis);
    // The cell of fan triangle t that x's rounded barycentric coordinates give (clamped into the
    // triangle), and how far outside the triangle they put x (<= 0 inside).
    struct Guess {
        int i = 0, j = 0;
        bool upper = false;
        double out = std::numeric_limits<double>::infinity();
    };
    const Point2 origin = projectDropping(face[0], dropAxis);
    auto guess = [&](size_t t) {
        Guess g;
        double u = 0, v = 0;
        if (!barycentric(origin, projectDropping(face[t], dropAxis),
                         projectDropping(face[t + 1], dropAxis), q, u, v))
            return g;
        g.out = std::max({-u, -v, u + v - 1});
        const double su = std::clamp(u, 0.0, 1.0) * k, sv = std::clamp(v, 0.0, 1.0) * k;
        g.i = std::min(k - 1, static_cast<int>(su));
        g.j = std::min(k - 1 - g.i, static_cast<int>(sv));
        g.upper = g.i + g.j + 1 < k && (su - g.i) + (sv - g.j) > 1;
        return g;
    };
    // The guess: the fan triangle x is least outside of (the nearest one when x is outside).
    uint32_t best = 0;
    double bestOut = std::numeric_limits<double>::infinity();
    for (size_t t = 1; t + 1 < face.size(); ++t) {
        const Guess g = guess(t);
        if (g.out < bestOut) {
            bestOut = g.out;
            best = cellIndex(t - 1, g.i, g.j, g.upper);
        }
        if (g.out <= 0) break;
    }
    // The answer must be a patch that contains x, decided exactly (contains()): its tree is exact
    // for the lines through that patch only. The guess is checked, then the cells around the
    // guesses of the fan triangles x is in or next to, then every patch: the patches overlap by
    // more than their corners' rounding (subdivideReceiverGrid), so one of them contains every
    // point of the face. Only a point outside the face (outside the contract: query --face
    // refuses it) falls through to the nearest guess.
    if (contains(best, x)) return best;
    for (size_t t = 1; t + 1 < face.size(); ++t) {
        const Guess g = guess(t);
        if (!(g.out <= 0x1p-20)) continue;
        for (int di = -1; di <= 1; ++di)
            for (int dj = -1; dj <= 1; ++dj) {
                const int i = g.i + di, j = g.j + dj;
                if (i < 0 || j < 0 || i + j >= k) continue;
                for (int upper = 0; upper < (i + j + 1 < k ? 2 : 1); ++upper) {
                    const uint32_t index = cellIndex(t - 1, i, j, upper != 0);
                    if (contains(index, x)) return index;
                }
            }
    }
    // The scan of every patch only for a point inside the face (a point outside it, e.g. a
    // float ray hit a hair past its edge, takes the nearest guess: scanning a face's thousands of
    // patches for each such point would cost more than its query).
    if (!(bestOut <= 0)) return best;
    for (uint32_t index = 0; index < patches.size(); ++index)
        if (contains(index, x)) return index;
    return best;
}

ReceiverPatches subdivideReceiver(std::span<const Vec3> face, double maxDiameter) {
    return subdivideReceiverGrid(face, cellsPerSide(diameter(face), maxDiameter));
}

ReceiverPatches subdivideReceiverGrid(std::span<const Vec3> face, int k, int dropAxis) {
    ReceiverPatches out;
    Vec3 n{};
    for (size_t i = 1; i + 1 < face.size(); ++i)
        n += cross(face[i] - face[0], face[i + 1] - face[0]);
    const double ax = std::fabs(n.x), ay = std::fabs(n.y), az = std::fabs(n.z);
    out.dropAxis =
        dropAxis >= 0 && dropAxis < 3 ? dropAxis : (ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2));
    out.face.assign(face.begin(), face.end());
    for (size_t i = 1; i + 1 < face.size() && out.faceTurn == 0; ++i)
        out.faceTurn =
            orient2d(projectDropping(face[0], out.dropAxis), projectDropping(face[i], out.dropAxis),
                     projectDropping(face[i + 1], out.dropAxis));
    if (k <= 1) {  // each fan triangle: k*k triangles
        out.patches.emplace_back(face.begin(), face.end());
        return out;
    }
    out.cellsPerSide = k;
    for (size_t t = 1; t + 1 < face.size(); ++t) {
        const Vec3 a = face[0], b = face[t], c = face[t + 1];
        auto at = [&](int i, int j) {  // barycentric grid point (i along ab, j along ac)
            const double u = static_cast<double>(i) / k, v = static_cast<double>(j) / k;
            return a * (1 - u - v) + b * u + c * v;
        };
        // Each patch grows about its centroid by a relative `grow`, which moves each of its
        // edges outwards by grow times the centroid's distance to it, a third of the patch's
        // height h = H / k (H the fan triangle's least height in the projection find() decides
        // in). The corners are rounded constructions, off by a few ulps of the largest coordinate
        // M (interpolation, centroid, growth: under 8 ulps); grow = max(1e-7, 2^6 ulp(M) k / H)
        // moves every edge out by at least 21 ulps of M, so neighbouring patches overlap and every
        // point of the face lies inside one of them at every magnitude (at 1e12 with a unit
        // face, patches grow by about 1e-2 of their size instead of 1e-7).
        const Point2 pa = projectDropping(a, out.dropAxis), pb = projectDropping(b, out.dropAxis),
                     pc = projectDropping(c, out.dropAxis);
        const double area2 =
            std::fabs((pb.u - pa.u) * (pc.v - pa.v) - (pb.v - pa.v) * (pc.u - pa.u));
        const double longest =
            std::max({std::hypot(pb.u - pa.u, pb.v - pa.v), std::hypot(pc.u - pb.u, pc.v - pb.v),
                      std::hypot(pa.u - pc.u, pa.v - pc.v)});
        const double height = longest > 0 ? area2 / longest : 0;
        const double magnitude = std::max({maxAbs(a), maxAbs(b), maxAbs(c), DBL_MIN});
        const double ulp = magnitude * 0x1p-52;
        double grow = height > 0 ? std::max(1e-7, 64 * ulp * k / height) : 0.5;
        grow = std::min(grow, 0.5);
        auto add = [&](Vec3 p, Vec3 q, Vec3 r) {
            const Vec3 centroid = (p + q + r) / 3.0;
            out.patches.push_back(
                {p + (p - centroid) * grow, q + (q - centroid) * grow, r + (r - centroid) * grow});
            const std::vector<Vec3>& added = out.patches.back();
            out.corners2d.push_back({projectDropping(added[0], out.dropAxis),
                                     projectDropping(added[1], out.dropAxis),
                                     projectDropping(added[2], out.dropAxis)});
        };
        for (int i = 0; i < k; ++i)
            for (int j = 0; i + j < k; ++j) {
                add(at(i, j), at(i + 1, j), at(i, j + 1));
                if (i + j + 1 < k) add(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            }
    }
    return out;
}

size_t receiverPatchCount(std::span<const Vec3> face, double maxDiameter) {
    const size_t k = static_cast<size_t>(cellsPerSide(diameter(face), maxDiameter));
    return k == 1 ? 1 : (face.size() >= 3 ? face.size() - 2 : 0) * k * k;
}

}  // namespace penumbra::vis
