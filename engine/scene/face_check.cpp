#include "engine/scene/face_check.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <optional>
#include <vector>

#include "engine/scene/polygon_triangulation.h"
#include "engine/scene/scene_error.h"
#include "engine/scene/scene_validation.h"
#include "visibility/form_factor.h"

namespace penumbra {
namespace {

using Kind = FaceDefect::Kind;

// A face's status: 0 ok, else 1 + its defect's kind.
constexpr uint8_t kOk = 0;
uint8_t statusOf(Kind kind) { return static_cast<uint8_t>(1 + static_cast<int>(kind)); }

// Below this many faces the check runs on the calling thread.
constexpr size_t kParallelThreshold = 20000;

// The statuses of faces [begin, end) of the mesh (in parallel for many).
void checkFaces(const vis::PolygonMesh& mesh, size_t begin, size_t end,
                std::vector<uint8_t>& status) {
    const auto checkRange = [&](size_t b, size_t e) {
        FaceCheckScratch scratch;
        for (size_t f = b; f < e; ++f) {
            if (const std::optional<FaceDefect> d =
                    checkFace(mesh, static_cast<uint32_t>(f), scratch)) {
                status[f] = statusOf(d->kind);
            }
        }
    };
    if (end - begin < kParallelThreshold) {
        checkRange(begin, end);
    } else {
        tbb::parallel_for(
            tbb::blocked_range<size_t>(begin, end, 4096),
            [&](const tbb::blocked_range<size_t>& r) { checkRange(r.begin(), r.end()); });
    }
}

}  // namespace

namespace face_check_detail {

// One repair of one kind: how many faces, and the first one's description.
struct RepairCount {
    size_t faces = 0, triangles = 0;
    std::string first;
};

// checkLoadedFaces' work on one scene whose faces' statuses are known: the refusal of the first
// face it may not repair, the repairs, and their warnings.
class FaceRepairs {
  public:
    FaceRepairs(Scene& scene, const FaceNamer& name, const std::vector<uint8_t>& status)
        : scene_(scene), name_(name), status_(status) {}

    // Refused: an invalid face always, a degenerate or splittable one in strict mode (repair
    // false); in face order, the first one.
    void refuseFirst(bool repair) const {
        for (size_t f = 0; f < status_.size(); ++f) {
            if (status_[f] == kOk) continue;
            const Kind kind = static_cast<Kind>(status_[f] - 1);
            if (kind == Kind::Invalid || !repair) {
                const FaceDefect d = defectOf(static_cast<uint32_t>(f));
                std::string message = faceName(static_cast<uint32_t>(f)) + ": " + d.message;
                if (kind != Kind::Invalid)
                    message += d.degenerate()
                                   ? " (repair mode drops such faces; strict mode refuses them)"
                                   : " (repair mode splits such faces into triangles; "
                                     "strict mode refuses them)";
                throw makeSceneError(scene_.sourcePath, lineOf(f), message);
            }
        }
    }

    // Repairs: degenerate faces dropped, non-planar and non-convex ones split into triangles of
    // their own vertices (polygon_triangulation.h), each triangle keeping the face's material
    // and source line. A triangle of a split whose area rounds to zero is dropped too.
    void repair() {
        const size_t nf = status_.size();
        faces_.reserve(nf);
        for (size_t f = 0; f < nf; ++f) {
            if (status_[f] == kOk) {
                keep(f, std::move(scene_.mesh.faces[f]));
                continue;
            }
            // The kind is known from the check above; the message (a second checkFace) only for
            // the first face of each kind, and for an error.
            const Kind kind = static_cast<Kind>(status_[f] - 1);
            if (kind == Kind::Degenerate) {
                if (dropped_.faces++ == 0)
                    dropped_.first = describe(static_cast<uint32_t>(f),
                                              defectOf(static_cast<uint32_t>(f)).message);
                continue;
            }
            split(f, kind);
        }
        scene_.mesh.faces = std::move(faces_);
        if (!scene_.faceMaterial.empty()) scene_.faceMaterial = std::move(material_);
        if (!scene_.faceSourceLine.empty()) scene_.faceSourceLine = std::move(line_);
        if (!scene_.faceUv.empty()) scene_.faceUv = std::move(uv_);
    }

    // One warning per kind of repair made, of the nf faces checked.
    void warn(size_t nf) const {
        const std::string& file = scene_.sourcePath;
        if (dropped_.faces > 0)
            scene_.warnings.push_back(file + ": dropped " + std::to_string(dropped_.faces) +
                                      " degenerate (zero-area) faces of " + std::to_string(nf) +
                                      " (first: " + dropped_.first + ")");
        if (splitNonPlanar_.faces > 0)
            scene_.warnings.push_back(file + ": split " + std::to_string(splitNonPlanar_.faces) +
                                      " non-planar faces into " +
                                      std::to_string(splitNonPlanar_.triangles) +
                                      " triangles (first: " + splitNonPlanar_.first + ")");
        if (splitNonConvex_.faces > 0)
            scene_.warnings.push_back(file + ": split " + std::to_string(splitNonConvex_.faces) +
                                      " non-convex faces into " +
                                      std::to_string(splitNonConvex_.triangles) +
                                      " triangles (first: " + splitNonConvex_.first + ")");
    }

  private:
    std::string faceName(uint32_t f) const {
        return name_ ? name_(f) : "face " + std::to_string(f);
    }
    int64_t lineOf(size_t f) const {
        return f < scene_.faceSourceLine.size() ? scene_.faceSourceLine[f] : 0;
    }
    // "<name>, line L: <message>" (the line where the loader knows it).
    std::string describe(uint32_t f, const std::string& message) const {
        std::string s = faceName(f);
        if (lineOf(f) > 0) s += ", line " + std::to_string(lineOf(f));
        return s + ": " + message;
    }
    FaceDefect defectOf(uint32_t f) const {
        FaceCheckScratch scratch;
        return *checkFace(scene_.mesh, f, scratch);
    }
    // Face f kept whole (its texture coordinates with it), or a triangle of it (`uvs`: the
    // coordinates of its corners, empty when f has none).
    void keep(size_t f, std::vector<uint32_t> face) {
        if (f < scene_.faceUv.size()) uv_.push_back(std::move(scene_.faceUv[f]));
        keepAttributes(f, std::move(face));
    }
    void keep(size_t f, std::vector<uint32_t> face, std::vector<Uv> uvs) {
        if (f < scene_.faceUv.size()) uv_.push_back(std::move(uvs));
        keepAttributes(f, std::move(face));
    }
    void keepAttributes(size_t f, std::vector<uint32_t> face) {
        faces_.push_back(std::move(face));
        if (f < scene_.faceMaterial.size()) material_.push_back(scene_.faceMaterial[f]);
        if (f < scene_.faceSourceLine.size()) line_.push_back(scene_.faceSourceLine[f]);
    }

    // A non-planar or non-convex face split into triangles, those whose area rounds to zero
    // dropped; an error when it cannot be split.
    void split(size_t f, Kind kind) {
        const auto message = [&] { return defectOf(static_cast<uint32_t>(f)).message; };
        const std::vector<uint32_t>& ids = scene_.mesh.faces[f];
        points_.clear();
        for (uint32_t v : ids) points_.push_back(scene_.mesh.vertices[v]);
        if (const auto problem = triangulation_.run(points_))
            throw makeSceneError(scene_.sourcePath, lineOf(f),
                                 faceName(static_cast<uint32_t>(f)) + ": " + message() +
                                     ", and it cannot be split into triangles: " + *problem);
        RepairCount& count = kind == Kind::NonPlanar ? splitNonPlanar_ : splitNonConvex_;
        if (count.faces++ == 0) count.first = describe(static_cast<uint32_t>(f), message());
        count.triangles += triangulation_.triangles().size();
        for (const auto& t : triangulation_.triangles()) {
            // A triangle of the split turns strictly in its projection, so its vertices are
            // distinct and not collinear: of checkFace's tests only the last can fail, an
            // area that rounds to zero (the same formula as PolygonMesh::faceArea). Such a
            // triangle is dropped as degenerate.
            const std::array<vis::Vec3, 3> corners = {points_[t[0]], points_[t[1]], points_[t[2]]};
            if (!(vis::polygonArea(corners) > 0)) {
                if (dropped_.faces++ == 0)
                    dropped_.first = "a triangle of a split face" +
                                     (lineOf(f) > 0 ? ", line " + std::to_string(lineOf(f)) : "") +
                                     ": degenerate: its area rounds to zero (a sliver below double "
                                     "precision)";
                continue;
            }
            std::vector<Uv> uvs;
            if (f < scene_.faceUv.size() && scene_.faceUv[f].size() == ids.size())
                uvs = {scene_.faceUv[f][t[0]], scene_.faceUv[f][t[1]], scene_.faceUv[f][t[2]]};
            keep(f, {ids[t[0]], ids[t[1]], ids[t[2]]}, std::move(uvs));
        }
    }

    Scene& scene_;
    const FaceNamer& name_;
    const std::vector<uint8_t>& status_;
    // The repaired faces, with their materials and lines where the scene has them.
    std::vector<std::vector<uint32_t>> faces_;
    std::vector<int32_t> material_, line_;
    std::vector<std::vector<Uv>> uv_;
    PolygonTriangulation triangulation_;
    std::vector<vis::Vec3> points_;
    RepairCount dropped_, splitNonPlanar_, splitNonConvex_;
};

}  // namespace face_check_detail

void checkLoadedFaces(Scene& scene, DegenerateFaces policy, const FaceNamer& name) {
    validateSceneStructure(scene);
    const size_t nf = scene.mesh.faces.size();
    std::vector<uint8_t> status(nf, kOk);
    checkFaces(scene.mesh, 0, nf, status);
    face_check_detail::FaceRepairs repairs(scene, name, status);
    repairs.refuseFirst(policy == DegenerateFaces::kDrop);
    bool anyRepair = false;
    for (uint8_t s : status) anyRepair = anyRepair || s != kOk;
    if (anyRepair) repairs.repair();
    repairs.warn(nf);
    if (scene.mesh.faces.empty()) throw makeSceneError(scene.sourcePath, 0, "no faces");
    scene.collectLights();
}

}  // namespace penumbra
