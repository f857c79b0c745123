#include "visibility/closed_surfaces.h"

#include <algorithm>
#include <numeric>

namespace penumbra::vis {

namespace {

// Union-find over the faces (path halving, union by index: enough for a one-time build).
class FaceSets {
  public:
    explicit FaceSets(uint32_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
    uint32_t find(uint32_t f) {
        while (parent_[f] != f) {
            parent_[f] = parent_[parent_[f]];
            f = parent_[f];
        }
        return f;
    }
    void join(uint32_t a, uint32_t b) {
        a = find(a);
        b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }

  private:
    std::vector<uint32_t> parent_;
};

// One directed use of an edge, filed under its lower vertex id: the higher one, the face, and
// +1 when the face runs from the lower to the higher id, else -1.
struct EdgeUse {
    uint32_t hi = 0, face = 0;
    int dir = 0;
};

}  // namespace

ClosedSurfaces::ClosedSurfaces(const PolygonMesh& mesh) {
    const auto faceCount = static_cast<uint32_t>(mesh.faces.size());
    const size_t vertexCount = mesh.vertices.size();
    // The uses grouped by lower vertex id (a counting sort: O(uses)). An edge from a vertex to
    // itself (a repeated vertex) is a point: it bounds nothing and joins nothing.
    std::vector<uint32_t> start(vertexCount + 1, 0);
    for (uint32_t f = 0; f < faceCount; ++f) {
        const auto& ids = mesh.faces[f];
        for (size_t i = 0; i < ids.size(); ++i) {
            const uint32_t a = ids[i], b = ids[(i + 1) % ids.size()];
            if (a != b) ++start[std::min(a, b) + 1];
        }
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<EdgeUse> uses(start.back());
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    for (uint32_t f = 0; f < faceCount; ++f) {
        const auto& ids = mesh.faces[f];
        for (size_t i = 0; i < ids.size(); ++i) {
            const uint32_t a = ids[i], b = ids[(i + 1) % ids.size()];
            if (a == b) continue;
            uses[next[std::min(a, b)]++] = {std::max(a, b), f, a < b ? 1 : -1};
        }
    }
    // Faces sharing an edge join; an edge whose uses do not sum to zero is open.
    FaceSets sets(faceCount);
    struct Open {
        uint32_t lo, hi, face;
    };
    std::vector<Open> open;
    for (uint32_t lo = 0; lo < vertexCount; ++lo) {
        const auto first = uses.begin() + start[lo], last = uses.begin() + start[lo + 1];
        std::sort(first, last, [](const EdgeUse& p, const EdgeUse& q) { return p.hi < q.hi; });
        for (auto run = first; run != last;) {
            auto end = run;
            int sum = 0;
            for (; end != last && end->hi == run->hi; ++end) {
                sum += end->dir;
                sets.join(run->face, end->face);
            }
            if (sum != 0) open.push_back({lo, run->hi, run->face});
            run = end;
        }
    }
    // Components numbered in the order of their lowest face.
    faceComponent_.assign(faceCount, 0);
    std::vector<uint32_t> idOfRoot(faceCount, UINT32_MAX);
    for (uint32_t f = 0; f < faceCount; ++f) {
        const uint32_t root = sets.find(f);
        if (idOfRoot[root] == UINT32_MAX) idOfRoot[root] = componentCount_++;
        faceComponent_[f] = idOfRoot[root];
    }
    std::vector<uint8_t> hasOpen(componentCount_, 0);
    std::vector<Bounds3> boxes;
    for (const Open& o : open) {
        const uint32_t component = faceComponent_[o.face];
        openEdges_.push_back({o.lo, o.hi, component});
        hasOpen[component] = 1;
        Bounds3 box;
        box.add(mesh.vertices[o.lo]);
        box.add(mesh.vertices[o.hi]);
        boxes.push_back(box);
    }
    closedCount_ =
        componentCount_ - static_cast<uint32_t>(std::count(hasOpen.begin(), hasOpen.end(), 1));
    for (uint32_t f = 0; f < faceCount; ++f) closedFaces_ += hasOpen[faceComponent_[f]] == 0;
    openEdgeTree_ = BoxTree(boxes);
}

}  // namespace penumbra::vis
