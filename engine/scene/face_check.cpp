#include "engine/scene/face_check.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <optional>
#include <vector>

#include "engine/scene/scene_error.h"
#include "engine/scene/scene_validation.h"

namespace penumbra {
namespace {

enum FaceStatus : uint8_t { kOk = 0, kDegenerate = 1, kInvalid = 2 };

// Below this many faces the check runs on the calling thread.
constexpr size_t kParallelThreshold = 20000;

}  // namespace

void checkLoadedFaces(Scene& scene, DegenerateFaces policy, const FaceNamer& name) {
    validateSceneStructure(scene);
    const vis::PolygonMesh& mesh = scene.mesh;
    const size_t nf = mesh.faces.size();
    std::vector<uint8_t> status(nf, kOk);
    const auto checkRange = [&](size_t begin, size_t end) {
        FaceCheckScratch scratch;
        for (size_t f = begin; f < end; ++f) {
            if (const std::optional<FaceDefect> d =
                    checkFace(mesh, static_cast<uint32_t>(f), scratch)) {
                status[f] = d->degenerate ? kDegenerate : kInvalid;
            }
        }
    };
    if (nf < kParallelThreshold) {
        checkRange(0, nf);
    } else {
        tbb::parallel_for(
            tbb::blocked_range<size_t>(0, nf, 4096),
            [&](const tbb::blocked_range<size_t>& r) { checkRange(r.begin(), r.end()); });
    }

    const auto faceName = [&](uint32_t f) { return name ? name(f) : "face " + std::to_string(f); };
    const auto message = [&](uint32_t f) {
        FaceCheckScratch scratch;
        return faceName(f) + ": " + checkFace(mesh, f, scratch)->message;
    };
    const uint8_t fatal = policy == DegenerateFaces::kDrop ? kInvalid : kDegenerate;
    size_t dropped = 0;
    std::optional<uint32_t> firstDropped;
    for (size_t f = 0; f < nf; ++f) {
        if (status[f] >= fatal) {
            const int64_t line = f < scene.faceSourceLine.size() ? scene.faceSourceLine[f] : 0;
            throw makeSceneError(scene.sourcePath, line, message(static_cast<uint32_t>(f)));
        }
        if (status[f] == kDegenerate) {
            ++dropped;
            if (!firstDropped) firstDropped = static_cast<uint32_t>(f);
        }
    }
    if (dropped > 0) {
        std::string warning = scene.sourcePath + ": dropped " + std::to_string(dropped) +
                              " degenerate (zero-area) faces of " + std::to_string(nf) +
                              " (first: " + message(*firstDropped);
        if (*firstDropped < scene.faceSourceLine.size() && scene.faceSourceLine[*firstDropped] > 0)
            warning += ", line " + std::to_string(scene.faceSourceLine[*firstDropped]);
        warning += ")";
        size_t out = 0;
        for (size_t f = 0; f < nf; ++f) {
            if (status[f] != kOk) continue;
            if (out != f) {
                scene.mesh.faces[out] = std::move(scene.mesh.faces[f]);
                if (f < scene.faceMaterial.size()) scene.faceMaterial[out] = scene.faceMaterial[f];
                if (f < scene.faceSourceLine.size())
                    scene.faceSourceLine[out] = scene.faceSourceLine[f];
            }
            ++out;
        }
        scene.mesh.faces.resize(out);
        if (!scene.faceMaterial.empty()) scene.faceMaterial.resize(out);
        if (!scene.faceSourceLine.empty()) scene.faceSourceLine.resize(out);
        scene.warnings.push_back(std::move(warning));
    }
    if (scene.mesh.faces.empty()) throw makeSceneError(scene.sourcePath, 0, "no faces");
    scene.collectLights();
}

}  // namespace penumbra
