#include "visibility/mesh_edges.h"

#include <algorithm>
#include <tuple>

namespace penumbra::vis {

MeshEdges::MeshEdges(const PolygonMesh& mesh, const ParallelLoops& loops) {
    // The directed uses bucketed by their lower vertex (a counting sort), each bucket sorted by
    // (hi, face, direction): the order of one sort by (lo, hi, face, direction), whoever sorts
    // which bucket.
    struct Directed {
        uint32_t hi, face;
        bool forward;
    };
    const size_t vertices = mesh.vertices.size();
    std::vector<size_t> start(vertices + 1, 0);
    for (const auto& f : mesh.faces)
        for (size_t i = 0; i < f.size(); ++i) {
            const uint32_t a = f[i], b = f[(i + 1) % f.size()];
            if (a != b) ++start[std::min(a, b) + 1];  // (validated meshes have no a == b)
        }
    for (size_t v = 0; v < vertices; ++v) start[v + 1] += start[v];
    std::vector<Directed> all(start[vertices]);
    {
        std::vector<size_t> next(start.begin(), start.end() - 1);
        for (uint32_t fi = 0; fi < mesh.faces.size(); ++fi) {
            const auto& f = mesh.faces[fi];
            for (size_t i = 0; i < f.size(); ++i) {
                const uint32_t a = f[i], b = f[(i + 1) % f.size()];
                if (a != b) all[next[std::min(a, b)]++] = {std::max(a, b), fi, a < b};
            }
        }
    }
    // Each bucket's edges counted, their offsets summed, then written: disjoint ranges.
    std::vector<size_t> edgeStart(vertices + 1, 0);
    loops.run(vertices, 4096, [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v) {
            auto* b = all.data() + start[v];
            auto* e = all.data() + start[v + 1];
            std::sort(b, e, [](const Directed& p, const Directed& q) {
                return std::tie(p.hi, p.face, p.forward) < std::tie(q.hi, q.face, q.forward);
            });
            size_t n = 0;
            for (auto* p = b; p != e; ++p) n += p == b || p->hi != (p - 1)->hi;
            edgeStart[v + 1] = n;
        }
    });
    for (size_t v = 0; v < vertices; ++v) edgeStart[v + 1] += edgeStart[v];
    edges_.resize(edgeStart[vertices]);
    begin_.resize(edges_.size() + 1);
    uses_.resize(all.size());
    begin_[edges_.size()] = all.size();
    loops.run(vertices, 4096, [&](size_t begin, size_t end) {
        for (size_t v = begin; v < end; ++v) {
            size_t e = edgeStart[v];
            for (size_t i = start[v]; i < start[v + 1]; ++i) {
                if (i == start[v] || all[i].hi != all[i - 1].hi) {
                    edges_[e] = {static_cast<uint32_t>(v), all[i].hi};
                    begin_[e++] = i;
                }
                uses_[i] = {all[i].face, all[i].forward};
            }
        }
    });
}

}  // namespace penumbra::vis
