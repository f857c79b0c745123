#include "engine/raytrace/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <mutex>
#include <stdexcept>
#include <type_traits>
#include <utility>

#include "engine/scene/random.h"
#include "visibility/pair_occluders.h"

namespace penumbra {

namespace {

const char* errorName(RTCError code) {
    switch (code) {
        case RTC_ERROR_NONE:
            return "RTC_ERROR_NONE";
        case RTC_ERROR_UNKNOWN:
            return "RTC_ERROR_UNKNOWN";
        case RTC_ERROR_INVALID_ARGUMENT:
            return "RTC_ERROR_INVALID_ARGUMENT";
        case RTC_ERROR_INVALID_OPERATION:
            return "RTC_ERROR_INVALID_OPERATION";
        case RTC_ERROR_OUT_OF_MEMORY:
            return "RTC_ERROR_OUT_OF_MEMORY";
        case RTC_ERROR_UNSUPPORTED_CPU:
            return "RTC_ERROR_UNSUPPORTED_CPU";
        case RTC_ERROR_CANCELLED:
            return "RTC_ERROR_CANCELLED";
    }
    return "RTC_ERROR_?";
}

// The intersect context handed to rtcOccluded1: Embree's context first (so Embree's pointer to it
// is also a pointer to this struct), then what the filter needs.
struct IgnoreFacesContext {
    RTCIntersectContext base;
    const uint32_t* primToFace;
    uint32_t ignoreA;
    uint32_t ignoreB;
};
static_assert(std::is_standard_layout_v<IgnoreFacesContext>);

// Context filter: rejects every candidate hit on a triangle of one of the two ignored faces.
void ignoreFacesFilter(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const IgnoreFacesContext*>(args->context);
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const uint32_t face = ctx->primToFace[RTCHitN_primID(args->hit, args->N, i)];
        if (face == ctx->ignoreA || face == ctx->ignoreB) args->valid[i] = 0;
    }
}

void setRay(RTCRay& ray, Vec3 org, Vec3 dir, double tnear, double tfar) {
    ray.org_x = static_cast<float>(org.x);
    ray.org_y = static_cast<float>(org.y);
    ray.org_z = static_cast<float>(org.z);
    ray.tnear = static_cast<float>(tnear);
    ray.dir_x = static_cast<float>(dir.x);
    ray.dir_y = static_cast<float>(dir.y);
    ray.dir_z = static_cast<float>(dir.z);
    ray.time = 0.0f;
    ray.tfar = static_cast<float>(tfar);
    ray.mask = 0xFFFFFFFFu;  // Debian's Embree is built with ray masks: mask 0 hits nothing
    ray.id = 0;
    ray.flags = 0;
}

}  // namespace

// What the device's error callback writes and throwIfError() reads; heap-allocated so that its
// address (the callback's user pointer) survives moves of the EmbreeScene.
struct detail::EmbreeErrorState {
    std::mutex mutex;
    std::string message;              // first error since the last throw
    std::atomic<bool> failed{false};  // cheap check on the query paths
};

namespace {
void onEmbreeError(void* user, RTCError code, const char* str) {
    // Called from inside Embree (possibly on a TBB worker thread): record, never throw.
    auto* state = static_cast<detail::EmbreeErrorState*>(user);
    std::lock_guard lock(state->mutex);
    if (state->failed.load(std::memory_order_relaxed)) return;
    state->message = std::string(errorName(code)) + (str ? std::string(": ") + str : std::string());
    state->failed.store(true, std::memory_order_release);
}
}  // namespace

void EmbreeScene::DeviceDeleter::operator()(RTCDeviceTy* device) const noexcept {
    rtcReleaseDevice(device);
}
void EmbreeScene::SceneDeleter::operator()(RTCSceneTy* scene) const noexcept {
    rtcReleaseScene(scene);
}

void EmbreeScene::throwIfError(const char* where) const {
    if (!errors_->failed.load(std::memory_order_acquire)) return;
    std::string message;
    {
        std::lock_guard lock(errors_->mutex);
        message = std::move(errors_->message);
        errors_->message.clear();
        errors_->failed.store(false, std::memory_order_relaxed);
    }
    throw std::runtime_error(std::string("Embree error in ") + where + ": " + message);
}

void EmbreeScene::checkFace(uint32_t face, const char* what) const {
    if (face >= faceCount())
        throw std::out_of_range(std::string("EmbreeScene: ") + what + " face " +
                                std::to_string(face) + " out of range (" +
                                std::to_string(faceCount()) + " faces)");
}

EmbreeScene::EmbreeScene(const vis::PolygonMesh& mesh, const Options& options)
    : errors_(std::make_unique<detail::EmbreeErrorState>()) {
    const size_t nf = mesh.faces.size();
    if (nf >= kNoFace) throw std::invalid_argument("EmbreeScene: too many faces");
    const std::vector<uint32_t> triIndex = triangulate(mesh);
    buildScene(mesh, triIndex, options);

    // The shaft-candidate hierarchy over the face boxes (faces with triangles only).
    std::vector<vis::Bounds3> boxes(nf);
    std::vector<bool> include(nf);
    for (uint32_t f = 0; f < nf; ++f) {
        boxes[f].add(faceBox_[f].lo);
        boxes[f].add(faceBox_[f].hi);
        include[f] = faceFirstPrim_[f + 1] > faceFirstPrim_[f];
    }
    shaftTree_ = vis::BoxTree(boxes, include);
    faceClusters_ = vis::FaceClusters(mesh, shaftTree_);
}

std::vector<uint32_t> EmbreeScene::triangulate(const vis::PolygonMesh& mesh) {
    const size_t nv = mesh.vertices.size();
    const size_t nf = mesh.faces.size();
    faceFirstPrim_.reserve(nf + 1);
    faceNormal_.reserve(nf);
    faceArea_.reserve(nf);
    faceBox_.reserve(nf);
    std::vector<uint32_t> triIndex;  // 3 mesh vertex ids per triangle
    for (uint32_t f = 0; f < nf; ++f) {
        const auto& idx = mesh.faces[f];
        for (uint32_t v : idx)
            if (v >= nv)
                throw std::invalid_argument("EmbreeScene: face " + std::to_string(f) +
                                            " uses vertex " + std::to_string(v) + " of " +
                                            std::to_string(nv));
        faceFirstPrim_.push_back(static_cast<uint32_t>(primToFace_.size()));
        faceNormal_.push_back(mesh.faceAreaNormal(f));
        Box box{{0, 0, 0}, {0, 0, 0}};
        if (!idx.empty()) {
            box.lo = box.hi = mesh.vertices[idx[0]];
            for (uint32_t v : idx) {
                const Vec3& p = mesh.vertices[v];
                box.lo = {std::min(box.lo.x, p.x), std::min(box.lo.y, p.y),
                          std::min(box.lo.z, p.z)};
                box.hi = {std::max(box.hi.x, p.x), std::max(box.hi.y, p.y),
                          std::max(box.hi.z, p.z)};
            }
        }
        faceBox_.push_back(box);
        double area = 0;
        for (size_t i = 1; i + 1 < idx.size(); ++i) {
            const Vec3 a = mesh.vertices[idx[0]], b = mesh.vertices[idx[i]],
                       c = mesh.vertices[idx[i + 1]];
            const double triArea = 0.5 * vis::length(vis::cross(b - a, c - a));
            primToFace_.push_back(f);
            primVertex_.insert(primVertex_.end(), {a, b, c});
            primArea_.push_back(triArea);
            triIndex.insert(triIndex.end(), {idx[0], idx[i], idx[i + 1]});
            area += triArea;
        }
        faceArea_.push_back(area);
    }
    faceFirstPrim_.push_back(static_cast<uint32_t>(primToFace_.size()));
    return triIndex;
}

void EmbreeScene::buildScene(const vis::PolygonMesh& mesh, const std::vector<uint32_t>& triIndex,
                             const Options& options) {
    // Device, with the error callback installed before anything else can fail.
    const std::string& deviceConfig = options.deviceConfig;
    device_.reset(rtcNewDevice(deviceConfig.empty() ? nullptr : deviceConfig.c_str()));
    if (!device_)
        throw std::runtime_error(
            std::string("Embree error in rtcNewDevice: ") + errorName(rtcGetDeviceError(nullptr)) +
            (deviceConfig.empty() ? "" : " (config \"" + deviceConfig + "\")"));
    rtcSetDeviceErrorFunction(device_.get(), &onEmbreeError, errors_.get());

    scene_.reset(rtcNewScene(device_.get()));
    throwIfError("rtcNewScene");
    if (!scene_) throw std::runtime_error("Embree error in rtcNewScene: no scene");
    // The context filter flag is what makes Embree call IgnoreFacesContext's filter.
    rtcSetSceneFlags(scene_.get(),
                     options.robust ? RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST
                                    : RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION);
    rtcSetSceneBuildQuality(scene_.get(), RTC_BUILD_QUALITY_HIGH);
    if (!primToFace_.empty()) attachTriangles(mesh, triIndex);
    rtcCommitScene(scene_.get());
    throwIfError("rtcCommitScene");
}

void EmbreeScene::attachTriangles(const vis::PolygonMesh& mesh,
                                  const std::vector<uint32_t>& triIndex) {
    const size_t nv = mesh.vertices.size();
    const size_t nt = primToFace_.size();
    // The geometry handle is only needed until it is attached (the scene then holds it).
    RTCGeometry geom = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
    throwIfError("rtcNewGeometry");
    struct GeometryRelease {
        RTCGeometry g;
        ~GeometryRelease() {
            if (g) rtcReleaseGeometry(g);
        }
    } release{geom};
    // rtcSetNewGeometryBuffer allocates with the padding Embree's SIMD loads need.
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), nv));
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), nt));
    throwIfError("rtcSetNewGeometryBuffer");
    if (!vb || !ib) throw std::runtime_error("Embree error in rtcSetNewGeometryBuffer: no buffer");
    for (size_t v = 0; v < nv; ++v) {
        vb[3 * v + 0] = static_cast<float>(mesh.vertices[v].x);
        vb[3 * v + 1] = static_cast<float>(mesh.vertices[v].y);
        vb[3 * v + 2] = static_cast<float>(mesh.vertices[v].z);
    }
    std::copy(triIndex.begin(), triIndex.end(), ib);
    rtcCommitGeometry(geom);
    rtcAttachGeometry(scene_.get(), geom);
    throwIfError("rtcAttachGeometry");
}

EmbreeScene::~EmbreeScene() = default;
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&& o) noexcept {
    if (this == &o) return *this;
    // Release the old handles in destruction order: scene, device, then the error record the
    // old device's callback points to.
    shaftTree_ = std::move(o.shaftTree_);
    faceClusters_ = std::move(o.faceClusters_);
    scene_ = std::move(o.scene_);
    device_ = std::move(o.device_);
    errors_ = std::move(o.errors_);
    primToFace_ = std::move(o.primToFace_);
    faceFirstPrim_ = std::move(o.faceFirstPrim_);
    primVertex_ = std::move(o.primVertex_);
    primArea_ = std::move(o.primArea_);
    faceNormal_ = std::move(o.faceNormal_);
    faceArea_ = std::move(o.faceArea_);
    faceBox_ = std::move(o.faceBox_);
    return *this;
}

std::optional<EmbreeScene::Hit> EmbreeScene::intersect(Vec3 org, Vec3 dir, double tnear,
                                                       double tfar) const {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);  // filter = NULL: nothing is ignored
    RTCRayHit rh;
    setRay(rh.ray, org, dir, tnear, tfar);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene_.get(), &context, &rh);
    throwIfError("rtcIntersect1");
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
    Hit hit;
    hit.face = primToFace_[rh.hit.primID];
    hit.t = rh.ray.tfar;
    hit.point = org + dir * hit.t;
    return hit;
}

bool EmbreeScene::occludedRaw(Vec3 from, Vec3 to, uint32_t ignoreA, uint32_t ignoreB) const {
    const Vec3 d = to - from;
    if (d.x == 0 && d.y == 0 && d.z == 0) return false;
    IgnoreFacesContext ctx;
    rtcInitIntersectContext(&ctx.base);
    ctx.base.filter = &ignoreFacesFilter;
    ctx.primToFace = primToFace_.data();
    ctx.ignoreA = ignoreA;
    ctx.ignoreB = ignoreB;
    RTCRay ray;
    setRay(ray, from, d, kSegmentEpsilon, 1.0 - kSegmentEpsilon);
    rtcOccluded1(scene_.get(), &ctx.base, &ray);
    return ray.tfar < 0;  // Embree sets tfar = -inf when it finds a (non-rejected) hit
}

bool EmbreeScene::occluded(Vec3 from, Vec3 to, uint32_t ignoreFaceA, uint32_t ignoreFaceB) const {
    const bool result = occludedRaw(from, to, ignoreFaceA, ignoreFaceB);
    throwIfError("rtcOccluded1");
    return result;
}

// Area-uniform map of the unit square onto a face: u selects the fan triangle by area share and
// the (sqrt-warped) distance from v0 inside it, v the position between the triangle's other two
// vertices. Each triangle's slice of u maps area-uniformly onto it, so equal-area cells of the
// square map to equal-area pieces of the face (stratification is preserved).
Vec3 EmbreeScene::pointOnFace(uint32_t face, double u, double v) const {
    const uint32_t first = faceFirstPrim_[face], last = faceFirstPrim_[face + 1];
    double target = u * faceArea_[face];
    uint32_t p = first;
    while (p + 1 < last && target >= primArea_[p]) {
        target -= primArea_[p];
        ++p;
    }
    const double local = primArea_[p] > 0 ? std::clamp(target / primArea_[p], 0.0, 1.0) : 0.0;
    const double s = std::sqrt(local);
    const Vec3& a = primVertex_[3 * p];
    const Vec3& b = primVertex_[3 * p + 1];
    const Vec3& c = primVertex_[3 * p + 2];
    return a + (b - a) * (s * (1 - v)) + (c - a) * (s * v);
}

double EmbreeScene::sampledFraction(uint32_t receiver, uint32_t light, Vec3 x, int samples,
                                    uint64_t seed) const {
    checkFace(receiver, "receiver");
    checkFace(light, "light");
    if (samples <= 0) throw std::invalid_argument("EmbreeScene::sampledFraction: samples <= 0");
    const uint32_t first = faceFirstPrim_[light];
    if (faceFirstPrim_[light + 1] == first || !(faceArea_[light] > 0)) return 0.0;

    // The light emits only to its front: x behind (or in) its plane sees none of it.
    const Vec3 nL = faceNormal_[light];
    if (!(vis::dot(x - primVertex_[3 * first], nL) > 0)) return 0.0;
    const Vec3 nR = faceNormal_[receiver];

    // samples = a * b, a the largest divisor <= sqrt(samples); one jittered sample per cell.
    int a = static_cast<int>(std::sqrt(static_cast<double>(samples)));
    while (a > 1 && (a + 1) * (a + 1) <= samples) ++a;  // guard sqrt rounding
    while (a > 1 && samples % a != 0) --a;
    const int b = samples / a;

    SplitMix64 rng{seed};  // local to each call: the same seed gives the same strata
    int visible = 0;
    for (int i = 0; i < b; ++i) {
        for (int j = 0; j < a; ++j) {
            const double u = (i + rng.uniform()) / b;
            const double v = (j + rng.uniform()) / a;
            const Vec3 y = pointOnFace(light, u, v);
            // x sees only its receiver's open front half-space.
            if (!(vis::dot(y - x, nR) > 0)) continue;
            if (!occludedRaw(x, y, receiver, light)) ++visible;
        }
    }
    throwIfError("rtcOccluded1");
    return static_cast<double>(visible) / samples;
}

std::vector<Vec3> EmbreeScene::facePolygon(uint32_t face) const {
    // The fan triangles (v0, v_i, v_i+1) of the face, in order: v0, v1, v2, then each third.
    std::vector<Vec3> out;
    for (uint32_t p = faceFirstPrim_[face]; p < faceFirstPrim_[face + 1]; ++p) {
        if (out.empty()) out.insert(out.end(), {primVertex_[3 * p], primVertex_[3 * p + 1]});
        out.push_back(primVertex_[3 * p + 2]);
    }
    return out;
}

std::vector<uint32_t> EmbreeScene::shaftCandidates(uint32_t receiver, uint32_t light) const {
    checkFace(receiver, "receiver");  // before facePolygon reads it
    return shaftCandidates(receiver, facePolygon(receiver), light);
}

std::vector<uint32_t> EmbreeScene::shaftCandidates(uint32_t receiver, std::span<const Vec3> region,
                                                   uint32_t light) const {
    checkFace(receiver, "receiver");
    checkFace(light, "light");
    // The faces whose box is not certainly outside a supporting plane of the hull of the region
    // and the light (the segments between them lie in that hull): a box query of the hierarchy
    // with the hull's planes, certain skips only.
    const ShaftBound shaft = shaftBound(region, light);
    std::vector<uint32_t> out;
    if (shaft.hull.empty())
        shaftTree_.overlapping(shaft.box, out);
    else
        shaftTree_.notOutside(shaft.hull, out);
    std::erase_if(out, [&](uint32_t f) { return f == receiver || f == light; });
    std::sort(out.begin(), out.end());
    return out;
}

EmbreeScene::ShaftBound EmbreeScene::shaftBound(std::span<const Vec3> region,
                                                uint32_t light) const {
    const std::vector<Vec3> lightPoints = facePolygon(light);
    ShaftBound shaft;
    if (region.size() >= 3 && lightPoints.size() >= 3)
        shaft.hull = vis::hullPlanes(region, lightPoints);
    if (shaft.hull.empty()) {  // degenerate: the box
        for (const Vec3& p : region) shaft.box.add(p);
        for (const Vec3& p : lightPoints) shaft.box.add(p);
    }
    return shaft;
}

bool EmbreeScene::mayCutShaft(uint32_t face, std::span<const Vec3> region, uint32_t light) const {
    checkFace(face, "face");
    checkFace(light, "light");
    const vis::Bounds3 box{faceBox_[face].lo, faceBox_[face].hi};
    const ShaftBound shaft = shaftBound(region, light);
    return shaft.hull.empty() ? box.overlaps(shaft.box)
                              : !vis::BoxTree::outsideOne(shaft.hull, box);
}

}  // namespace penumbra
