// Affine3: an affine map of 3D space, p -> L p + t, used to place meshes (glTF node transforms,
// JSON scene transforms). Plain doubles: applying it rounds, so transformed geometry is validated
// again after it is placed.
#pragma once

#include <array>
#include <cmath>

#include "visibility/vec3.h"

namespace penumbra {

using vis::Vec3;

struct Affine3 {
    // Row-major 3x4: the linear part in columns 0..2, the translation in column 3.
    std::array<std::array<double, 4>, 3> m{{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};

    static Affine3 translation(const Vec3& t) {
        Affine3 a;
        a.m[0][3] = t.x;
        a.m[1][3] = t.y;
        a.m[2][3] = t.z;
        return a;
    }
    static Affine3 scaling(const Vec3& s) {
        Affine3 a;
        a.m[0][0] = s.x;
        a.m[1][1] = s.y;
        a.m[2][2] = s.z;
        return a;
    }
    // Rotation by `radians` counter-clockwise about `axis` (any nonzero length; right-hand rule).
    static Affine3 rotation(const Vec3& axis, double radians) {
        const Vec3 u = vis::normalize(axis);
        const double c = std::cos(radians), s = std::sin(radians), k = 1 - c;
        Affine3 a;
        a.m[0] = {c + u.x * u.x * k, u.x * u.y * k - u.z * s, u.x * u.z * k + u.y * s, 0};
        a.m[1] = {u.y * u.x * k + u.z * s, c + u.y * u.y * k, u.y * u.z * k - u.x * s, 0};
        a.m[2] = {u.z * u.x * k - u.y * s, u.z * u.y * k + u.x * s, c + u.z * u.z * k, 0};
        return a;
    }
    // Rotation by the unit quaternion (x, y, z, w) (normalised here).
    static Affine3 quaternion(double x, double y, double z, double w) {
        const double n = std::sqrt(x * x + y * y + z * z + w * w);
        x /= n, y /= n, z /= n, w /= n;
        Affine3 a;
        a.m[0] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w), 0};
        a.m[1] = {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w), 0};
        a.m[2] = {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y), 0};
        return a;
    }

    Vec3 point(const Vec3& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3 vector(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    // Determinant of the linear part: negative for a mirroring map, which must reverse the
    // vertex order of faces to keep them counter-clockwise seen from the front.
    double determinant() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    bool isFinite() const {
        for (const auto& row : m)
            for (double x : row)
                if (!std::isfinite(x)) return false;
        return true;
    }
    // The map "first o, then this".
    Affine3 operator*(const Affine3& o) const {
        Affine3 r;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 4; ++j) {
                double s = j == 3 ? m[i][3] : 0.0;
                for (int k = 0; k < 3; ++k) s += m[i][k] * o.m[k][j];
                r.m[i][j] = s;
            }
        }
        return r;
    }
};

}  // namespace penumbra
