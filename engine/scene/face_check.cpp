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

// One repair of one kind: how many faces, and the first one's description.
struct RepairCount {
    size_t faces = 0, triangles = 0;
    std::string first;
};

}  // namespace

void checkLoadedFaces(Scene& scene, DegenerateFaces policy, const FaceNamer& name) {
    validateSceneStructure(scene);
    const size_t nf = scene.mesh.faces.size();
    std::vector<uint8_t> status(nf, kOk);
    checkFaces(scene.mesh, 0, nf, status);

    const auto faceName = [&](uint32_t f) { return name ? name(f) : "face " + std::to_string(f); };
    const auto lineOf = [&](size_t f) -> int64_t {
        return f < scene.faceSourceLine.size() ? scene.faceSourceLine[f] : 0;
    };
    // "<name>, line L: <message>" (the line where the loader knows it).
    const auto describe = [&](uint32_t f, const std::string& message) {
        std::string s = faceName(f);
        if (lineOf(f) > 0) s += ", line " + std::to_string(lineOf(f));
        return s + ": " + message;
    };
    const auto defectOf = [&](uint32_t f) {
        FaceCheckScratch scratch;
        return *checkFace(scene.mesh, f, scratch);
    };
    const bool repair = policy == DegenerateFaces::kDrop;
    // Refused: an invalid face always, a degenerate or splittable one in strict mode; in face
    // order, the first one.
    for (size_t f = 0; f < nf; ++f) {
        if (status[f] == kOk) continue;
        const Kind kind = static_cast<Kind>(status[f] - 1);
        if (kind == Kind::Invalid || !repair) {
            const FaceDefect d = defectOf(static_cast<uint32_t>(f));
            std::string message = faceName(static_cast<uint32_t>(f)) + ": " + d.message;
            if (kind != Kind::Invalid)
                message += d.degenerate()
                               ? " (repair mode drops such faces; strict mode refuses them)"
                               : " (repair mode splits such faces into triangles; "
                                 "strict mode refuses them)";
            throw makeSceneError(scene.sourcePath, lineOf(f), message);
        }
    }
    // Repairs: degenerate faces dropped, non-planar and non-convex ones split into triangles of
    // their own vertices (polygon_triangulation.h), each triangle keeping the face's material
    // and source line. A triangle of a split whose area rounds to zero is dropped too.
    RepairCount dropped, splitNonPlanar, splitNonConvex;
    bool anyRepair = false;
    for (uint8_t s : status) anyRepair = anyRepair || s != kOk;
    if (anyRepair) {
        std::vector<std::vector<uint32_t>> faces;
        std::vector<int32_t> material;
        std::vector<int32_t> line;
        faces.reserve(nf);
        PolygonTriangulation triangulation;
        std::vector<vis::Vec3> points;
        auto keep = [&](size_t f, std::vector<uint32_t> face) {
            faces.push_back(std::move(face));
            if (f < scene.faceMaterial.size()) material.push_back(scene.faceMaterial[f]);
            if (f < scene.faceSourceLine.size()) line.push_back(scene.faceSourceLine[f]);
        };
        for (size_t f = 0; f < nf; ++f) {
            if (status[f] == kOk) {
                keep(f, std::move(scene.mesh.faces[f]));
                continue;
            }
            // The kind is known from the check above; the message (a second checkFace) only for
            // the first face of each kind, and for an error.
            const Kind kind = static_cast<Kind>(status[f] - 1);
            const auto message = [&] { return defectOf(static_cast<uint32_t>(f)).message; };
            if (kind == Kind::Degenerate) {
                if (dropped.faces++ == 0)
                    dropped.first = describe(static_cast<uint32_t>(f), message());
                continue;
            }
            const std::vector<uint32_t>& ids = scene.mesh.faces[f];
            points.clear();
            for (uint32_t v : ids) points.push_back(scene.mesh.vertices[v]);
            if (const auto problem = triangulation.run(points))
                throw makeSceneError(scene.sourcePath, lineOf(f),
                                     faceName(static_cast<uint32_t>(f)) + ": " + message() +
                                         ", and it cannot be split into triangles: " + *problem);
            RepairCount& count = kind == Kind::NonPlanar ? splitNonPlanar : splitNonConvex;
            if (count.faces++ == 0) count.first = describe(static_cast<uint32_t>(f), message());
            count.triangles += triangulation.triangles().size();
            for (const auto& t : triangulation.triangles()) {
                // A triangle of the split turns strictly in its projection, so its vertices are
                // distinct and not collinear: of checkFace's tests only the last can fail, an
                // area that rounds to zero (the same formula as PolygonMesh::faceArea). Such a
                // triangle is dropped as degenerate.
                const std::array<vis::Vec3, 3> corners = {points[t[0]], points[t[1]], points[t[2]]};
                if (!(vis::polygonArea(corners) > 0)) {
                    if (dropped.faces++ == 0)
                        dropped.first =
                            "a triangle of a split face" +
                            (lineOf(f) > 0 ? ", line " + std::to_string(lineOf(f)) : "") +
                            ": degenerate: its area rounds to zero (a sliver below double "
                            "precision)";
                    continue;
                }
                keep(f, {ids[t[0]], ids[t[1]], ids[t[2]]});
            }
        }
        scene.mesh.faces = std::move(faces);
        if (!scene.faceMaterial.empty()) scene.faceMaterial = std::move(material);
        if (!scene.faceSourceLine.empty()) scene.faceSourceLine = std::move(line);
    }
    const std::string& file = scene.sourcePath;
    if (dropped.faces > 0)
        scene.warnings.push_back(file + ": dropped " + std::to_string(dropped.faces) +
                                 " degenerate (zero-area) faces of " + std::to_string(nf) +
                                 " (first: " + dropped.first + ")");
    if (splitNonPlanar.faces > 0)
        scene.warnings.push_back(file + ": split " + std::to_string(splitNonPlanar.faces) +
                                 " non-planar faces into " +
                                 std::to_string(splitNonPlanar.triangles) +
                                 " triangles (first: " + splitNonPlanar.first + ")");
    if (splitNonConvex.faces > 0)
        scene.warnings.push_back(file + ": split " + std::to_string(splitNonConvex.faces) +
                                 " non-convex faces into " +
                                 std::to_string(splitNonConvex.triangles) +
                                 " triangles (first: " + splitNonConvex.first + ")");
    if (scene.mesh.faces.empty()) throw makeSceneError(scene.sourcePath, 0, "no faces");
    scene.collectLights();
}

}  // namespace penumbra
