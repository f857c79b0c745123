#include "visibility/mesh_edges.h"

#include <algorithm>
#include <tuple>

namespace penumbra::vis {

MeshEdges::MeshEdges(const PolygonMesh& mesh) {
    struct Directed {
        uint32_t lo, hi, face;
        bool forward;
    };
    std::vector<Directed> all;
    size_t count = 0;
    for (const auto& f : mesh.faces) count += f.size();
    all.reserve(count);
    for (uint32_t fi = 0; fi < mesh.faces.size(); ++fi) {
        const auto& f = mesh.faces[fi];
        for (size_t i = 0; i < f.size(); ++i) {
            const uint32_t a = f[i], b = f[(i + 1) % f.size()];
            if (a == b) continue;  // (validated meshes have none)
            all.push_back({std::min(a, b), std::max(a, b), fi, a < b});
        }
    }
    std::sort(all.begin(), all.end(), [](const Directed& p, const Directed& q) {
        return std::tie(p.lo, p.hi, p.face, p.forward) < std::tie(q.lo, q.hi, q.face, q.forward);
    });
    uses_.reserve(all.size());
    for (size_t i = 0; i < all.size(); ++i) {
        if (i == 0 || all[i].lo != all[i - 1].lo || all[i].hi != all[i - 1].hi) {
            edges_.push_back({all[i].lo, all[i].hi});
            begin_.push_back(uses_.size());
        }
        uses_.push_back({all[i].face, all[i].forward});
    }
    begin_.push_back(uses_.size());
}

}  // namespace penumbra::vis
