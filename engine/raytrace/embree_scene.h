// EmbreeScene: an Embree 3 BVH over a vis::PolygonMesh, used as the ray-traced baseline
// ("RT sampled" in the paper) and for picking / shaft culling in the engine.
//
// Geometry: each convex face with n >= 3 vertices becomes the n - 2 fan triangles
// (v0, v_i, v_i+1), stored contiguously; faces with fewer than 3 vertices get no triangles.
// Vertices are converted to float for Embree; all results are reported in doubles.
//
// Conventions (scene.h): faces are counter-clockwise seen from the front, so the Newell normal
// (PolygonMesh::faceAreaNormal) points to the front. A receiving point sees only the open front
// half-space of its receiver face; a light emits only into the open front half-space of its face.
//
// Errors: Embree reports errors through a per-device callback. The callback only records the
// first message (it must not throw through Embree's C frames); every public method checks the
// record when its Embree calls return and throws std::runtime_error("Embree error ...") there.
// Invalid arguments (bad face ids, vertex ids out of range, samples <= 0) throw
// std::invalid_argument / std::out_of_range.
//
// Thread safety: after construction every const method may be called from many threads at once.
// The object is move-only; a moved-from EmbreeScene may only be destroyed or assigned to.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/face_clusters.h"
#include "visibility/polygon_mesh.h"

// Embree's opaque handle types (RTCDevice = RTCDeviceTy*, RTCScene = RTCSceneTy*), declared here
// so that this header does not pull in <embree3/rtcore.h>.
struct RTCDeviceTy;
struct RTCSceneTy;

namespace penumbra {

namespace detail {
struct EmbreeErrorState;  // defined in embree_scene.cpp
}

using vis::Vec3;

class EmbreeScene {
  public:
    // Face id meaning "no face" (e.g. an ignore slot of occluded() that ignores nothing).
    static constexpr uint32_t kNoFace = std::numeric_limits<uint32_t>::max();
    // occluded() tests the segment from + t (to - from) for t in [kSegmentEpsilon,
    // 1 - kSegmentEpsilon]: the ends are pulled in by this fraction of the segment's length so that
    // faces touching the end points (e.g. a neighbour sharing an edge with the receiver) do not
    // count as blockers.
    static constexpr double kSegmentEpsilon = 1e-4;

    struct Hit {
        uint32_t face = kNoFace;  // face id of the mesh
        double t = 0;  // ray parameter: point = org + t * dir (dir as given, not normalised)
        Vec3 point;    // org + t * dir
    };

    struct Options {
        // Passed to rtcNewDevice (e.g. "threads=1"); empty means Embree's defaults.
        std::string deviceConfig;
        // RTC_SCENE_FLAG_ROBUST: watertight traversal, no rays slipping through the shared edge of
        // two fan triangles or two faces. Costs about a third of the shadow-ray throughput
        // (random 1000-triangle scene: ~3.1 vs ~4.1 Mrays/s on one core).
        bool robust = true;
    };

    // Builds the BVH (RTC_BUILD_QUALITY_HIGH).
    explicit EmbreeScene(const vis::PolygonMesh& mesh) : EmbreeScene(mesh, Options{}) {}
    EmbreeScene(const vis::PolygonMesh& mesh, const Options& options);
    ~EmbreeScene();
    EmbreeScene(EmbreeScene&&) noexcept;
    EmbreeScene& operator=(EmbreeScene&&) noexcept;
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    uint32_t faceCount() const { return static_cast<uint32_t>(faceFirstPrim_.size() - 1); }
    size_t triangleCount() const { return primToFace_.size(); }
    // The face an Embree primitive (fan triangle) belongs to.
    uint32_t faceOfPrimitive(uint32_t prim) const { return primToFace_.at(prim); }

    // Closest hit of the ray org + t dir with t in [tnear, tfar], both faces of every triangle.
    std::optional<Hit> intersect(Vec3 org, Vec3 dir, double tnear = 0,
                                 double tfar = std::numeric_limits<double>::infinity()) const;

    // True if the segment from -> to (shortened by kSegmentEpsilon at both ends) hits any face
    // other than ignoreFaceA and ignoreFaceB (typically the receiver and the light; kNoFace ignores
    // nothing). Uses rtcOccluded1 with a context filter that rejects the two faces' triangles.
    bool occluded(Vec3 from, Vec3 to, uint32_t ignoreFaceA = kNoFace,
                  uint32_t ignoreFaceB = kNoFace) const;

    // The paper's "RT sampled" baseline: the fraction of the light face's area visible from point
    // x on face `receiver`, estimated with `samples` stratified, area-uniform points on the light.
    //  - Stratification: samples = a * b with a the largest divisor of `samples` not above its
    //    square root, one jittered sample per cell of an a x b grid over the unit square (a square
    //    count gives the sqrt(N) x sqrt(N) grid; a prime count degenerates to N jittered 1D
    //    strata). The unit square maps onto the light area-uniformly: u picks a fan triangle by its
    //    share of the area and, within it, the distance from v0 (sqrt warp); v the position across
    //    it.
    //  - If x is not strictly in front of the light's plane the result is 0. A sample behind (or
    //    on) the receiver's plane counts as not visible (weight 0). Every other sample counts 1 if
    //    occluded(x, sample, receiver, light) is false.
    //  - Returns (visible samples) / samples, in [0, 1]. Deterministic for a given seed.
    double sampledFraction(uint32_t receiver, uint32_t light, Vec3 x, int samples,
                           uint64_t seed) const;

    // Faces other than `receiver` and `light` whose axis-aligned bounding box is not certainly
    // outside a supporting plane of the convex hull of receiver and light (PlaneOrient::boxNegative
    // against vis::hullPlanes): a conservative superset of the faces that can cut the shaft between
    // them (the shaft lies inside that hull). Faces with fewer than 3 vertices (no triangles,
    // invisible to the rays too) are left out. Returned in increasing face order.
    // Cost: a query of a bounding-volume hierarchy over the face boxes (visibility/box_tree.h,
    // exact double-precision box tests, built with the scene): O(log faces + candidates), not
    // O(faces).
    std::vector<uint32_t> shaftCandidates(uint32_t receiver, uint32_t light) const;
    // The same for a part of the receiver (a patch, receiver_patches.h): the hull of `region` and
    // the light instead of the receiver's.
    std::vector<uint32_t> shaftCandidates(uint32_t receiver, std::span<const Vec3> region,
                                          uint32_t light) const;
    // Whether `face` may cut the shaft between `region` (a part of a receiver, or all of it) and
    // `light`: its box is not certainly outside a supporting plane of their hull (the
    // PlaneOrient::boxNegative test; the box overlap in the degenerate case), as shaftCandidates
    // decides for every face. False proves that the face meets no segment from the region to the
    // light (a moved light that no tree of another light can have seen, light_move.h).
    bool mayCutShaft(uint32_t face, std::span<const Vec3> region, uint32_t light) const;
    // That hierarchy of face boxes (faces with triangles), for the direct per-point query
    // (vis::FromPointQuery::runDirect).
    const vis::BoxTree& faceBoxes() const { return shaftTree_; }
    // The groups of that hierarchy's faces that a point may see all one way, with their
    // boundaries (vis::FaceClusters), for the same query.
    const vis::FaceClusters& faceClusters() const { return faceClusters_; }
    // A face's vertices as Embree holds them (double precision, the input's), from its triangles.
    std::vector<Vec3> facePolygon(uint32_t face) const;

    // Face data kept by the scene (double precision, from the input mesh).
    Vec3 faceAreaNormal(uint32_t face) const { return faceNormal_.at(face); }
    double faceArea(uint32_t face) const { return faceArea_.at(face); }

    struct Box {
        Vec3 lo, hi;
    };
    const Box& faceBox(uint32_t face) const { return faceBox_.at(face); }

  private:
    struct DeviceDeleter {
        void operator()(RTCDeviceTy* device) const noexcept;
    };
    struct SceneDeleter {
        void operator()(RTCSceneTy* scene) const noexcept;
    };

    // The constructor's steps: the faces fanned into triangles with their per-face data (returns
    // the triangles' vertex ids), then the Embree device and scene over those triangles.
    std::vector<uint32_t> triangulate(const vis::PolygonMesh& mesh);
    void buildScene(const vis::PolygonMesh& mesh, const std::vector<uint32_t>& triIndex,
                    const Options& options);
    void attachTriangles(const vis::PolygonMesh& mesh, const std::vector<uint32_t>& triIndex);
    void throwIfError(const char* where) const;
    void checkFace(uint32_t face, const char* what) const;
    // What bounds the shaft between `region` and `light`: the supporting planes of their hull, or
    // where that is degenerate (fewer than 3 points on a side, or no hull) none and the box of
    // both. The faces not certainly outside it are the shaft's candidates.
    struct ShaftBound {
        std::vector<vis::PlaneOrient> hull;
        vis::Bounds3 box;
    };
    ShaftBound shaftBound(std::span<const Vec3> region, uint32_t light) const;
    bool occludedRaw(Vec3 from, Vec3 to, uint32_t ignoreA, uint32_t ignoreB) const;
    Vec3 pointOnFace(uint32_t face, double u, double v) const;

    // Declaration order = reverse destruction order: the scene is released before its device,
    // and the device before the error record its callback writes to.
    std::unique_ptr<detail::EmbreeErrorState> errors_;
    std::unique_ptr<RTCDeviceTy, DeviceDeleter> device_;
    std::unique_ptr<RTCSceneTy, SceneDeleter> scene_;

    std::vector<uint32_t> primToFace_;  // per triangle: its face
    std::vector<uint32_t>
        faceFirstPrim_;               // faces + 1 entries: face f owns triangles [f], .. [f+1] - 1
    std::vector<Vec3> primVertex_;    // 3 per triangle, double precision
    std::vector<double> primArea_;    // per triangle
    std::vector<Vec3> faceNormal_;    // per face: Newell area normal
    std::vector<double> faceArea_;    // per face: sum of its triangles' areas
    std::vector<Box> faceBox_;        // per face
    vis::BoxTree shaftTree_;          // over faceBox_, for shaftCandidates
    vis::FaceClusters faceClusters_;  // over shaftTree_'s nodes
};

}  // namespace penumbra
