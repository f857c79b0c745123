#include "visibility/fp_query/chain_build.h"

#include <algorithm>
#include <cmath>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

bool ChainBuild::use() {
    if (q_.silhouettes.active() || q_.clusters.active() || q_.edges.active()) {
        if (!built_) build();
        return true;
    }
    const ChainOptions& options = q_.run.chainOptions;
    if (options.minOccluders == 0 || q_.active.size() < options.minOccluders) return false;
    if (!built_) build();
    return pays_;
}

bool ChainBuild::addUses(uint32_t& surfaceUses) {
    const ActiveOccluders& active = q_.active;
    for (size_t j = 0; j < active.size(); ++j) {
        const ActiveOccluders::Occluder& o = active[j];
        const int weight = o.blocked == Sign::Negative ? 1 : -1;  // x in front of the face: +1
        for (uint32_t e = 0; e < o.planeCount; ++e) {
            const auto [v0, v1] = active.planeEdge(o.firstPlane + e);
            builder_.add(v0, v1, weight, o.firstPlane + e);
        }
        // A chord is the face's own (no other face has it): it never cancels.
        for (uint32_t e = 0; e < o.pencilCount; ++e)
            builder_.add(kClipEdge | (o.firstPencil + e), 0, weight,
                         ActiveOccluders::kPencilRef | (o.firstPencil + e));
    }
    surfaceUses = 0;
    surfaceRemaining_.clear();
    surfaceSums_.clear();
    if (q_.silhouettes.active()) {
        SilhouettePath& path = q_.silhouettes;
        const DeferredSilhouettes& s = path.silhouettes();
        // The kept edges in the cone, each use weighted by the side its face faces x (a face
        // whose plane holds x blocks nothing and adds none). An edge only surface faces use
        // remains where its weighted directions do not sum to zero; one a clipped face uses too
        // goes through the chain builder with that face's uses. A ref marks the use until its
        // edge is known to remain.
        for (uint32_t g : path.groups()) {
            const uint32_t begin = s.groupBegin[g], end = s.groupBegin[g + 1];
            surfaceUses += end - begin;
            if (s.groupWithClipped[g]) {
                for (uint32_t u = begin; u < end; ++u) {
                    const DeferredSilhouettes::Use& use = s.uses[u];
                    const int weight = path.sideAt(use.slot);
                    if (weight != 0) builder_.add(use.v0, use.v1, weight, kSurfaceRef | u);
                }
                continue;
            }
            int sum = 0;
            for (uint32_t u = begin; u < end; ++u) {
                const DeferredSilhouettes::Use& use = s.uses[u];
                sum += path.sideAt(use.slot) * (use.v0 < use.v1 ? 1 : -1);
            }
            if (q_.run.budget.reached()) return false;
            if (sum != 0) {
                surfaceRemaining_.push_back(kSurfaceRef | begin);
                surfaceSums_.push_back(sum);
            }
        }
    }
    // The used face groups' boundaries, each edge weighted by the side x sees its group from (the
    // group's inner edges cancel as its faces' would; its boundary edges are summed with the
    // other uses of the same edges).
    clusterEdges_.clear();
    if (q_.clusters.active()) {
        const FaceClusters& clusters = q_.clusters.clusters();
        for (const ClusterPath::Used& c : q_.clusters.used()) {
            for (const FaceClusters::Use& use : clusters.boundary(c.cluster)) {
                builder_.add(use.lo, use.hi, c.side * use.weight,
                             kClusterRef | static_cast<uint32_t>(clusterEdges_.size()));
                clusterEdges_.emplace_back(use.lo, use.hi);
            }
        }
    }
    return true;
}

void ChainBuild::planesForRemaining() {
    // The remaining group edges get their planes through x now (the others never do).
    for (uint32_t& ref : refs_) {
        if ((ref & ActiveOccluders::kPencilRef) != 0 || (ref & kClusterRef) == 0) continue;
        const auto [lo, hi] = clusterEdges_[ref & ~kClusterRef];
        ref = q_.active.addEdgePlane(lo, hi);
    }
    if (q_.silhouettes.active()) {
        refs_.insert(refs_.end(), surfaceRemaining_.begin(), surfaceRemaining_.end());
        weights_.insert(weights_.end(), surfaceSums_.begin(), surfaceSums_.end());
        // The remaining kept edges get their planes through x now (the others never do).
        const DeferredSilhouettes& s = q_.silhouettes.silhouettes();
        for (uint32_t& ref : refs_) {
            if ((ref & ActiveOccluders::kPencilRef) != 0 || (ref & kSurfaceRef) == 0) continue;
            const DeferredSilhouettes::Use& use = s.uses[ref & ~kSurfaceRef];
            ref = q_.active.addEdgePlane(use.v0, use.v1);
        }
    } else {
        q_.run.prepareCone();
    }
}

void ChainBuild::buildFromLightEdges() {
    // The light-edge path's chain (edge_path.h): its edges of nonzero weight, each with its plane
    // through x, input segments whole; no chord (no face is clipped on this path).
    refs_.clear();
    weights_.clear();
    for (const EdgePath::Remaining& e : q_.edges.remaining()) {
        refs_.push_back(q_.active.addEdgePlane(e.lo, e.hi));
        weights_.push_back(e.weight);
    }
    counts_.lightEdgesExamined = q_.edges.examined();
    counts_.occluderEdges = q_.edges.nearCone();
    counts_.boundaryEdges = static_cast<uint32_t>(refs_.size());
    pays_ = true;
    chain_.clear();
    chords_ = false;
    chordsOnBLeftOut_ = false;
    keepEdgesInCone();
    counts_.chainInCone = static_cast<uint32_t>(chain_.size());
    // c' changes only across these edges, by their weights (no face is cut by L's plane near the
    // cone): cells may be labelled by crossings.
    crossings_ = chain_.size() >= q_.run.chainOptions.crossingsMinEdges;
    q_.cells.prepare(chain_.size(), crossings_);
}

void ChainBuild::build() {
    q_.run.budget.enter(WorkStage::BuildChain);
    built_ = true;
    if (q_.edges.active()) {
        buildFromLightEdges();
        return;
    }
    builder_.clear();
    uint32_t surfaceUses = 0;
    if (!addUses(surfaceUses)) return;
    builder_.remaining(refs_, weights_);
    planesForRemaining();
    counts_.occluderEdges = static_cast<uint32_t>(builder_.uses()) + surfaceUses;
    counts_.boundaryEdges = static_cast<uint32_t>(refs_.size());
    // The cells are decided one line each but are never dropped before the chain has cut them,
    // while Algorithm 1 drops a hidden part at once: the chain pays where most edges cancel
    // (closed and smooth surfaces), not among separate faces (leaves), where it only adds work.
    // (The surface path was chosen for the pair: its silhouettes pay.)
    pays_ = q_.silhouettes.active() || q_.clusters.active() ||
            refs_.size() * q_.run.chainOptions.gain <= builder_.uses();
    chain_.clear();
    chords_ = false;
    chordsOnBLeftOut_ = false;
    if (!pays_) return;
    keepEdgesInCone();
    counts_.chainInCone = static_cast<uint32_t>(chain_.size());
    // Cells may be labelled by crossings when c(y) changes only across the chain's edges: no
    // occluder cut by L's plane (c would also change where y passes through such an occluder,
    // near its chord in L's plane). An occluder cut by B's plane has its chord on B's plane; seen
    // from x on B's plane that chord lies on the line where B's plane meets L's, outside L's
    // part in front of B, but with x off B's plane by a rounding (a rendered point, or one
    // rounded from a wall's contact line) the plane through x and the chord turns through L
    // within some ulps of that line, and c jumps there by an amount the chain does not hold.
    // Such chords are cut first (orderRoot): a path between two points strictly on one side of
    // every chord's plane crosses no chord, and one that may cross a chord's plane is counted on
    // its line instead (countByCrossings; decideWhole decides no cell a chord may still cut).
    // (Before, any such chord in L's cone left every cell of the point to its line test, and
    // none was decided whole: on the motorbike, whose faces' planes often cut the light, its
    // points over the work limit took 7.3 ms each with every point exact, 5.5 ms since.) And
    // only for a long chain: on a short one a cell's line test, which stops at the first face
    // that hides it, costs less than the count that starts the crossings.
    crossings_ = !q_.active.lightChord() && chain_.size() >= q_.run.chainOptions.crossingsMinEdges;
    q_.cells.prepare(chain_.size(), crossings_);
}

void ChainBuild::keepEdgesInCone() {
    const QueryRun& r = q_.run;
    const ActiveOccluders& active = q_.active;
    const PlaneOrient& frontB = r.pair.frontB().orient;
    // x on or in front of B's plane (exact): seen from x, a chord on B's plane lies on or behind
    // that plane (the ray from x through a point of it goes on behind B), so it meets no line
    // from x to a point strictly in front of B, and no triangle of x and two such points: it
    // changes c nowhere in L's part in front of B, the answer's part. Such chords are left out
    // of the chain, and each cell is labelled from a point strictly in front of B's plane
    // (ChainCells::certifiedPoint), which holds its part in front of B. (With x behind B's plane
    // by a rounding they project into L within some ulps of the line where B's plane meets L's,
    // and are cut first.)
    const bool leaveOutChordsOnB = frontB.sign(r.x) != Sign::Negative;
    std::vector<uint32_t>& root = q_.cells.root();
    root.clear();
    const std::vector<PlaneOrient>& cone = r.cone();
    for (size_t k = 0; k < refs_.size(); ++k) {
        const uint32_t ref = refs_[k];
        Edge e;
        e.ref = ref;
        const bool pencil = (ref & ActiveOccluders::kPencilRef) != 0;
        if (pencil && leaveOutChordsOnB && active.pencilOnB(ref & ~ActiveOccluders::kPencilRef)) {
            chordsOnBLeftOut_ = true;
            continue;
        }
        if (!pencil) {
            const auto [v0, v1] = active.planeEdge(ref);
            e.segment = true;
            e.a = r.mesh().vertices[v0];
            e.b = r.mesh().vertices[v1];
            // (On the light-edge path faces are not clipped: an edge bounds its faces whole.)
            e.behindB = !q_.edges.active() &&
                        (frontB.sign(e.a) == Sign::Negative || frontB.sign(e.b) == Sign::Negative);
            // The ref's plane is through x, v0, v1; the weight is the edge's from its lower id.
            e.jump = v0 < v1 ? weights_[k] : -weights_[k];
        }
        // Every vertex of L on one closed side of its plane: its line misses L's open cone.
        bool positive = false, negative = false;
        for (const Vec3& v : r.light()) {
            const Sign s = active.refSign(ref, v);
            positive = positive || s == Sign::Positive;
            negative = negative || s == Sign::Negative;
        }
        if (!positive || !negative) continue;
        // Its segment outside one side plane of the pyramid over L (closed): it misses the cone.
        bool outside = false;
        for (size_t i = 0; e.segment && !outside && i < cone.size(); ++i)
            outside = exactSign(cone[i], e.a) != Sign::Positive &&
                      exactSign(cone[i], e.b) != Sign::Positive;
        if (outside) continue;
        chords_ = chords_ || !e.segment;
        root.push_back(static_cast<uint32_t>(chain_.size()));
        chain_.push_back(e);
    }
    orderRoot(root);
}

void ChainBuild::orderRoot(std::vector<uint32_t>& root) {
    if (root.size() >= kLongestFirstMin) {
        // The cuts in order of the angle each segment spans from x (|a x b| / |a| |b|, rounded:
        // only an order, no decision), chords first (they bound the part of L in front of B):
        // an autopartition that cuts along long edges first makes fewer cells. Measured every
        // point exact at 128x128, 4 spp: dragon plane tests 604M -> 461M, CPU 12.0 -> 10.8 s;
        // motorbike (64x64, 2 spp) 590M -> 429M, 13.4 -> 11.9 s; the same images. Chords last
        // instead: 512M on the dragon.
        const Vec3& x = q_.run.x;
        orderKeys_.clear();
        for (uint32_t i : root) {
            const Edge& e = chain_[i];
            double span = 2;  // (above any segment's: a sine)
            if (e.segment) {
                const Vec3 a = e.a - x, b = e.b - x;
                span = length(cross(a, b)) / (length(a) * length(b));
            }
            orderKeys_.emplace_back(-span, i);
        }
        std::sort(orderKeys_.begin(), orderKeys_.end());
        for (size_t k = 0; k < root.size(); ++k) root[k] = orderKeys_[k].second;
    } else {
        // Chords first here too: the cells below them lie on one side of every chord's plane,
        // where the crossings need no chord (countByCrossings, decideWhole).
        std::stable_partition(root.begin(), root.end(),
                              [&](uint32_t i) { return !chain_[i].segment; });
    }
}

}  // namespace penumbra::vis
