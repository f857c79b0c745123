#include "visibility/light_edge_index.h"

#include <algorithm>
#include <numeric>
#include <utility>

#include "visibility/face_plane.h"
#include "visibility/light_silhouette_edges.h"

namespace penumbra::vis {

LightEdgeIndex::LightEdgeIndex(const PolygonMesh& mesh, const MeshEdges& edges, uint32_t lightFace,
                               const ParallelLoops& loops)
    : light_(lightFace), vertexCount_(mesh.vertices.size()) {
    // Each vertex's side of L's plane (exact), then each face's from its vertices'.
    const PlaneOrient lightPlane = facePlane(mesh, lightFace).orient();
    std::vector<Sign> vertexSide(mesh.vertices.size());
    loops.run(mesh.vertices.size(), 8192, [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v) vertexSide[v] = lightPlane.sign(mesh.vertices[v]);
    });
    sides_.resize(mesh.faces.size(), Side::Behind);
    loops.run(mesh.faces.size(), 8192, [&](size_t begin, size_t end) {
        for (size_t f = begin; f < end; ++f) {
            const auto& ids = mesh.faces[f];
            if (ids.size() < 3) continue;
            bool front = false, behind = false;
            for (uint32_t v : ids) {
                front = front || vertexSide[v] == Sign::Positive;
                behind = behind || vertexSide[v] == Sign::Negative;
            }
            sides_[f] = !front ? Side::Behind : behind ? Side::Across : Side::Front;
        }
    });
    // The Across faces' boxes, those alone (most meshes have few or none).
    for (uint32_t f = 0; f < sides_.size(); ++f)
        if (sides_[f] == Side::Across) acrossIds_.push_back(f);
    acrossCount_ = acrossIds_.size();
    if (acrossCount_ > 0) {
        std::vector<Bounds3> acrossBoxes(acrossCount_);
        loops.run(acrossCount_, 8192, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i)
                for (uint32_t v : mesh.faces[acrossIds_[i]]) acrossBoxes[i].add(mesh.vertices[v]);
        });
        acrossFaces_ = BoxTree(acrossBoxes, {}, loops);
    }

    const LightSilhouetteEdges set(mesh, edges, lightFace, loops);
    share_ = set.share();
    open_ = set.open();
    // S_L's edges in the edge table's order: each chunk of the table counted (edges, uses),
    // the counts summed into offsets, then each chunk copied to its place.
    constexpr size_t kChunk = 16384;
    const size_t chunks = (edges.size() + kChunk - 1) / kChunk;
    std::vector<size_t> edgeAt(chunks + 1, 0), useAt(chunks + 1, 0);
    loops.run(chunks, 1, [&](size_t begin, size_t end) {
        for (size_t c = begin; c < end; ++c)
            for (size_t e = c * kChunk; e < std::min(edges.size(), (c + 1) * kChunk); ++e) {
                if (!set.contains(e)) continue;
                ++edgeAt[c + 1];
                useAt[c + 1] += edges.uses(e).size();
            }
    });
    for (size_t c = 0; c < chunks; ++c) {
        edgeAt[c + 1] += edgeAt[c];
        useAt[c + 1] += useAt[c];
    }
    edges_.resize(edgeAt[chunks]);
    begin_.resize(edges_.size() + 1);
    uses_.resize(useAt[chunks]);
    begin_[edges_.size()] = static_cast<uint32_t>(uses_.size());
    std::vector<Bounds3> boxes(edges_.size());
    loops.run(chunks, 1, [&](size_t begin, size_t end) {
        for (size_t c = begin; c < end; ++c) {
            size_t i = edgeAt[c], u = useAt[c];
            for (size_t e = c * kChunk; e < std::min(edges.size(), (c + 1) * kChunk); ++e) {
                if (!set.contains(e)) continue;
                const MeshEdges::Edge& edge = edges.edge(e);
                edges_[i] = edge;
                begin_[i] = static_cast<uint32_t>(u);
                for (const MeshEdges::Use& use : edges.uses(e)) uses_[u++] = use;
                boxes[i].add(mesh.vertices[edge.lo]);
                boxes[i].add(mesh.vertices[edge.hi]);
                ++i;
            }
        }
    });
    edgeBoxes_ = BoxTree(boxes, {}, loops);
    // S_L's edges renumbered in the hierarchy's leaf order: a query's edges then lie together
    // here, as their boxes do in the hierarchy, and a point's weights read them in order (the
    // same edges in the same order as before: the hierarchy is unchanged).
    const std::vector<uint32_t> old = edgeBoxes_.numberItemsInLeafOrder();
    std::vector<MeshEdges::Edge> leafEdges(edges_.size());
    std::vector<MeshEdges::Use> leafUses(uses_.size());
    std::vector<uint32_t> leafBegin(begin_.size());
    uint32_t u = 0;
    for (size_t i = 0; i < old.size(); ++i) {
        leafEdges[i] = edges_[old[i]];
        leafBegin[i] = u;
        for (uint32_t k = begin_[old[i]]; k < begin_[old[i] + 1]; ++k) leafUses[u++] = uses_[k];
    }
    leafBegin[old.size()] = u;
    edges_ = std::move(leafEdges);
    uses_ = std::move(leafUses);
    begin_ = std::move(leafBegin);

    // The Front faces and their corners, numbered as the uses (in leaf order) meet them.
    std::vector<uint32_t> faceLocal(mesh.faces.size(), kNotFront);
    std::vector<uint32_t> vertexLocal(mesh.vertices.size(), kNotFront);
    useLocal_.resize(uses_.size());
    for (size_t u = 0; u < uses_.size(); ++u) {
        const uint32_t f = uses_[u].face;
        if (sides_[f] != Side::Front) {
            useLocal_[u] = kNotFront;
            continue;
        }
        if (faceLocal[f] == kNotFront) {
            std::array<uint32_t, 3> local{};
            for (size_t k = 0; k < 3; ++k) {
                const uint32_t corner = mesh.faces[f][k];  // its plane's vertices (face_plane.h)
                uint32_t& v = vertexLocal[corner];
                if (v == kNotFront) {
                    v = static_cast<uint32_t>(localVertices_.size());
                    localVertices_.push_back(mesh.vertices[corner]);
                }
                local[k] = v;
            }
            faceLocal[f] = static_cast<uint32_t>(localFaces_.size());
            localFaces_.push_back(f);
            localCorners_.push_back(local);
        }
        useLocal_[u] = faceLocal[f];
    }

    // For the silhouette cull only: a Front triangle that repeats another's three vertices (the
    // motorbike stores 67,326 of its faces twice, each copy turned the other way: two-sided
    // sheets) counts as that one, its uses turned where it is turned. Exact: a copy's plane is
    // the same three points, so x's side of it is the same (a rotation of the other's order) or
    // the opposite (a reversal), and each use's term s_f (+-1) is the same with the use so
    // turned. Seen from one side a two-sided sheet's edges then cancel in the cull as a
    // one-sided surface's do; with both copies a node holding them was never one-sided. The
    // weights themselves are still taken face by face (useLocal_), so B's own copy counts for
    // nothing as before (the caller searches any subtree holding B's edges).
    // (Found in the cull's branch: only it reads them, beside the sorted keys' build.)
    loops.both(
        [&] {
            std::vector<MeshEdges::Use> cullUses;
            std::vector<uint32_t> cullLocal;
            twinUses(mesh, cullUses, cullLocal);
            silhouettes_ = SilhouetteCull(
                edgeBoxes_, {cullUses, begin_, cullLocal, localCorners_, localVertices_}, loops);
        },
        [&] {
            // Edges are in the table's (lo, hi) order before the renumbering: old[i] increases
            // with the key, so sorting by old index sorts by key.
            std::vector<uint32_t> byKey(old.size());
            for (size_t i = 0; i < old.size(); ++i) byKey[old[i]] = static_cast<uint32_t>(i);
            sortedKeys_.resize(old.size());
            sortedIds_ = std::move(byKey);
            for (size_t k = 0; k < sortedIds_.size(); ++k) {
                const MeshEdges::Edge& e = edges_[sortedIds_[k]];
                sortedKeys_[k] = uint64_t{e.lo} << 32 | e.hi;
            }
        });
}

void LightEdgeIndex::twinUses(const PolygonMesh& mesh, std::vector<MeshEdges::Use>& uses,
                              std::vector<uint32_t>& local) const {
    // The local triangles by their sorted vertex ids: each run of equal keys is one triangle
    // stored several times; its first (lowest local number) stands for the others.
    std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> keys;
    keys.reserve(localFaces_.size());
    for (uint32_t l = 0; l < localFaces_.size(); ++l) {
        const auto& f = mesh.faces[localFaces_[l]];
        if (f.size() != 3) continue;
        std::array<uint32_t, 3> key{f[0], f[1], f[2]};
        std::sort(key.begin(), key.end());
        keys.emplace_back(key, l);
    }
    std::sort(keys.begin(), keys.end());
    std::vector<uint32_t> twinOf(localFaces_.size());
    std::iota(twinOf.begin(), twinOf.end(), 0u);
    std::vector<uint8_t> turned(localFaces_.size(), 0);
    for (size_t i = 0; i < keys.size();) {
        size_t j = i + 1;
        while (j < keys.size() && keys[j].first == keys[i].first) ++j;
        const uint32_t first = keys[i].second;
        const auto& a = mesh.faces[localFaces_[first]];
        for (size_t k = i + 1; k < j; ++k) {
            const uint32_t l = keys[k].second;
            const auto& b = mesh.faces[localFaces_[l]];
            // The same order up to rotation: b[1] follows b[0] in a as it does in b.
            size_t at = 0;
            while (a[at] != b[0]) ++at;
            twinOf[l] = first;
            turned[l] = a[(at + 1) % 3] == b[1] ? 0 : 1;
        }
        i = j;
    }
    uses = uses_;
    local = useLocal_;
    for (size_t u = 0; u < uses.size(); ++u) {
        if (local[u] == kNotFront) continue;
        if (turned[local[u]] != 0) uses[u].forward = !uses[u].forward;
        local[u] = twinOf[local[u]];
    }
}

std::optional<uint32_t> LightEdgeIndex::find(uint32_t lo, uint32_t hi) const {
    const uint64_t key = uint64_t{lo} << 32 | hi;
    const auto it = std::lower_bound(sortedKeys_.begin(), sortedKeys_.end(), key);
    if (it == sortedKeys_.end() || *it != key) return std::nullopt;
    return sortedIds_[static_cast<size_t>(it - sortedKeys_.begin())];
}

}  // namespace penumbra::vis
