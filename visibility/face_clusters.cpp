#include "visibility/face_clusters.h"

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "visibility/boundary_chain.h"
#include "visibility/face_plane.h"
#include "visibility/predicates.h"

namespace penumbra::vis {

namespace {

// A face's rounded normal and an upper bound on its distance to the exact one.
struct FaceNormal {
    Vec3 n;
    double error = 0;
    bool known = false;  // the rounded normal is longer than four times its error
};

FaceNormal faceNormal(const PolygonMesh& mesh, uint32_t face) {
    const auto& ids = mesh.faces[face];
    if (ids.size() < 3) return {};
    // The cross product as the face's plane test forms it (activateFace's PlaneOrient): each
    // component is within 4u of its permanent of the exact one (two rounded differences, two
    // products and their difference); 8u is claimed, plus an absolute term for underflow.
    const PlaneOrient p = facePlane(mesh, face).orient();
    FaceNormal f;
    f.n = {p.n[0], p.n[1], p.n[2]};
    constexpr double kU = DBL_EPSILON / 2;
    f.error = 8 * kU * p.permanentL1() + 8 * DBL_MIN;
    f.known = length(f.n) > 4 * f.error;
    return f;
}

}  // namespace

FaceClusters::FaceClusters(const PolygonMesh& mesh, const BoxTree& faces) : surfaces_(mesh) {
    const uint32_t nodes = faces.nodeCount();
    clusterOfNode_.assign(nodes, kNone);
    std::vector<FaceNormal> normals(mesh.faces.size());
    for (uint32_t f = 0; f < mesh.faces.size(); ++f) normals[f] = faceNormal(mesh, f);
    BoundaryChain chain;
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    std::vector<uint32_t> refs;
    std::vector<int> weights;
    for (uint32_t node = 0; node < nodes; ++node) {
        const std::span<const uint32_t> items = faces.nodeItems(node);
        if (items.size() < kMinFaces || items.size() > kMaxFaces) continue;
        // The axis: the mean of the unit normals (any axis is sound; this one is narrow).
        Vec3 sum{};
        bool known = true;
        for (uint32_t f : items) {
            known = known && normals[f].known;
            if (!known) break;
            sum += normals[f].n / length(normals[f].n);
        }
        const double sumLength = length(sum);
        if (!known || !(sumLength > 0)) continue;
        const Vec3 u = sum / sumLength;
        const double uLength = length(u);
        // cos(angle(N, u)) >= (n.u / |u| - e) / (|n| + e) for the exact normal N within e of the
        // rounded n; 1e-12 below it covers the rounding of this bound (some 1e-15).
        double cosMin = 1;
        for (uint32_t f : items) {
            const FaceNormal& fn = normals[f];
            const double c =
                (dot(fn.n, u) / uLength - fn.error) / (length(fn.n) + fn.error) - 1e-12;
            cosMin = std::min(cosMin, c);
        }
        if (!(cosMin >= 0.1)) continue;  // a cone wider than 84 degrees: rarely certain
        // The boundary: the faces' directed edge uses, each face with weight +1.
        chain.clear();
        edges.clear();
        for (uint32_t f : items) {
            const auto& ids = mesh.faces[f];
            for (size_t i = 0; i < ids.size(); ++i) {
                const uint32_t a = ids[i], b = ids[(i + 1) % ids.size()];
                chain.add(a, b, 1, static_cast<uint32_t>(edges.size()));
                edges.emplace_back(a, b);
            }
        }
        chain.remaining(refs, weights);
        if (2 * refs.size() > edges.size()) continue;  // too few edges cancel to gain anything
        Cluster c;
        c.box = faces.nodeBox(node);
        c.axis = u;
        c.sinBound = std::min(1.0, std::sqrt(std::max(0.0, 1 - cosMin * cosMin)) + 1e-12);
        c.firstUse = static_cast<uint32_t>(uses_.size());
        c.useCount = static_cast<uint32_t>(refs.size());
        c.component = surfaces_.componentOf(items[0]);
        for (uint32_t f : items)
            if (surfaces_.componentOf(f) != c.component) c.component = kNone;
        for (size_t k = 0; k < refs.size(); ++k) {
            const auto [a, b] = edges[refs[k]];
            uses_.push_back({std::min(a, b), std::max(a, b), weights[k]});
        }
        clusterOfNode_[node] = static_cast<uint32_t>(clusters_.size());
        clusters_.push_back(c);
        if (groupedFace_.empty()) groupedFace_.assign(mesh.faces.size(), 0);
        for (uint32_t f : items) groupedFace_[f] = 1;
    }
}

int FaceClusters::facing(uint32_t cluster, const Vec3& x) const {
    const Cluster& c = clusters_[cluster];
    const Vec3& u = c.axis;
    // u.x against the box's extent along u, and |x - p| <= D for every p of the box.
    double ux = 0, hMax = 0, hMin = 0, magnitude = 0;
    for (int i = 0; i < 3; ++i) {
        const double lo = u[i] * c.box.lo[i], hi = u[i] * c.box.hi[i];
        ux += u[i] * x[i];
        hMax += std::max(lo, hi);
        hMin += std::min(lo, hi);
        magnitude += std::abs(u[i] * x[i]) + std::max(std::abs(lo), std::abs(hi));
    }
    if (!(ux - hMax > 0) && !(hMin - ux > 0)) return 0;  // (the usual answer, without a root)
    double d2 = 0;
    for (int i = 0; i < 3; ++i) {
        const double far = std::max(std::abs(x[i] - c.box.lo[i]), std::abs(x[i] - c.box.hi[i]));
        d2 += far * far;
    }
    const double d = std::sqrt(d2);
    const double need = c.sinBound * d + 1e-12 * (magnitude + d);
    if (ux - hMax > need) return 1;
    if (hMin - ux > need) return -1;
    return 0;
}

}  // namespace penumbra::vis
