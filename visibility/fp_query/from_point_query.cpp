#include "visibility/fp_query/from_point_query.h"

#include <stdexcept>

#include "visibility/fp_query/query_parts.h"

namespace penumbra::vis {

// ---- The choice between the strategies (QueryParts) ----------------------------------------

void QueryParts::startRun() {
    run.reset();
    contactAnswer = false;
    walk.reset();
    active.clear(true);
    chain.reset();
    clip.reset();
    cells.reset();
    lines.reset();
    silhouettes.reset();
    clusters.reset();
    solids.reset();
    edges.reset();
}

bool QueryParts::startPair(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                           const Vec3& x) {
    run.pair.prepare(mesh, receiver, light);
    // The light emits only to its front: x must be strictly in front of L's plane.
    if (run.pair.lightPlane().sign(x) != Sign::Positive) return false;
    return run.pair.lightClipped().size() >= 3;
}

void QueryParts::reachVisible(std::span<const Vec3> poly, size_t depth) {
    if (!deferredPrepared) {  // on the first visible leaf: a point in full shadow pays nothing
        deferredPrepared = true;
        prepareDeferred(*run.tree);
    }
    if (chain.use()) {
        if (run.budget.reached()) return;  // (the chain may be half built)
        cells.cut(poly, depth, 0);
        return;
    }
    clip.clipOrdered(poly, depth);
}

void QueryParts::prepareDeferred(const HistoryTree& tree) {
    active.clear(false);
    if (!tree.partial()) return;
    run.preparePyramid();
    if (silhouettes.prepare(tree)) return;
    // The occluders whose box may meet the pyramid, in the order the hierarchy finds them.
    if (!tree.deferredIndex.empty()) {
        if (!findCandidates(tree.deferredIndex)) return;
    } else {
        run.candidates.clear();
        for (uint32_t k = 0; k < tree.deferred.size(); ++k) run.candidates.push_back(k);
    }
    run.budget.enter(WorkStage::ActivateOccluders);
    for (uint32_t k : run.candidates) {
        if (!run.budget.spend()) return;
        active.activate(tree.deferred[k].face);
    }
}

bool QueryParts::findCandidates(const BoxTree& index) {
    run.budget.enter(WorkStage::FindOccluders);
    run.candidates.clear();
    return run.budget.spend(index.notOutside(run.pyramid, run.candidates, run.budget.left()));
}

void QueryParts::clipCandidates() {
    run.tree = nullptr;
    run.budget.enter(WorkStage::ActivateOccluders);
    if (clusters.walked() && solids.worth()) {
        if (solids.prepare()) solids.leaveOutBacks();
        if (run.budget.reached() || solids.hidden()) return;  // (hidden: no fragment)
    }
    for (uint32_t f : run.candidates) {
        if (f == run.pair.receiver() || f == run.pair.light()) continue;
        if (!run.budget.spend()) return;
        active.activate(f);
    }
    if (clusters.active()) {
        // Fewer faces in all than the chain is for (ChainOptions::minOccluders): the groups'
        // faces are activated and the usual rule chooses between the chain and Algorithm 1.
        size_t grouped = 0;
        for (const ClusterPath::Used& c : clusters.used())
            grouped += clusters.faces().nodeItems(c.node).size();
        if (grouped + active.size() < run.chainOptions.minOccluders) clusters.dissolve();
        if (run.budget.reached()) return;
    }
    deferredPrepared = true;
    reachVisible(run.pair.lightClipped(), 0);
}

bool QueryParts::takeLightEdges(const BoxTree& faces, const LightEdgeIndex& index) {
    if (run.chainOptions.minOccluders == 0 || !edges.prepare(faces, index)) return false;
    if (run.budget.reached()) return true;
    deferredPrepared = true;
    reachVisible(run.pair.lightClipped(), 0);
    return true;
}

// ---- FromPointQuery ------------------------------------------------------------------------

FromPointQuery::FromPointQuery(PredicateMode mode) : q_(std::make_unique<QueryParts>(mode)) {}
FromPointQuery::~FromPointQuery() = default;
FromPointQuery::FromPointQuery(FromPointQuery&&) noexcept = default;
FromPointQuery& FromPointQuery::operator=(FromPointQuery&&) noexcept = default;

const FragmentList& FromPointQuery::runDirect(const PolygonMesh& mesh, uint32_t receiver,
                                              uint32_t light, const AnsweredPoint& point,
                                              const BoxTree& faces, const FaceClusters* clusters,
                                              const LightEdgeIndex* lightEdges) {
    QueryParts& q = *q_;
    QueryRun& r = q.run;
    q.startRun();
    if (receiver == light) return r.fragments;
    r.input = point.input;
    r.moved = point.moved();
    if (!q.startPair(mesh, receiver, light, point.at)) return r.fragments;
    r.x = point.at;
    r.preparePyramid();
    // The light-edge path where it is given and taken (edge_path.h): the chain from S_L's edges
    // near the cone, no face activated.
    if (lightEdges != nullptr && q.takeLightEdges(faces, *lightEdges)) return r.fragments;
    // The candidates in the order the hierarchy's walk finds them (a function of the mesh alone:
    // the answer is deterministic). Insertion order as the builder's (pair_occluders.h) would be
    // costlier to find than it saves; sorting them into face order cost the bunny's penumbra
    // points 4.6% of their time.
    if (clusters != nullptr && clusters->size() > 0 && r.chainOptions.minOccluders != 0) {
        if (!q.clusters.find(faces, *clusters)) return r.fragments;
    } else if (!q.findCandidates(faces)) {
        return r.fragments;
    }
    q.clipCandidates();
    return r.fragments;
}

const FragmentList* FromPointQuery::runLightEdges(const PolygonMesh& mesh, uint32_t receiver,
                                                  uint32_t light, const AnsweredPoint& point,
                                                  const BoxTree& faces,
                                                  const LightEdgeIndex& lightEdges) {
    QueryParts& q = *q_;
    QueryRun& r = q.run;
    q.startRun();
    if (receiver == light) return &r.fragments;
    r.input = point.input;
    r.moved = point.moved();
    if (!q.startPair(mesh, receiver, light, point.at)) return &r.fragments;
    r.x = point.at;
    r.preparePyramid();
    if (r.chainOptions.minOccluders == 0) {
        q.edges.declined(EdgeDecline::ChainOff);
        return nullptr;
    }
    if (!q.edges.prepare(faces, lightEdges)) return nullptr;
    if (r.budget.reached()) return &r.fragments;
    // Where the edges found near the cone mostly remain (separate faces, leaves: few cancel),
    // the chain cut by them costs more than the face-by-face paths, which drop a hidden part at
    // once (ChainOptions::gain, as ChainBuild decides for those paths): not taken.
    const uint32_t gain = r.chainOptions.gain;
    if (gain != 0 && q.edges.remaining().size() * gain > q.edges.nearCone()) {
        q.edges.reset();
        q.edges.declined(EdgeDecline::FewCancel);
        return nullptr;
    }
    q.deferredPrepared = true;
    q.reachVisible(r.pair.lightClipped(), 0);
    return &r.fragments;
}

const FragmentList& FromPointQuery::run(const PolygonMesh& mesh, const HistoryTree& tree,
                                        const AnsweredPoint& point, std::vector<TraceStep>* trace,
                                        RegionDecisions* region) {
    if (region != nullptr && region->tree() != &tree)
        throw std::invalid_argument("FromPointQuery::run: region decisions of another tree");
    QueryParts& q = *q_;
    QueryRun& r = q.run;
    q.startRun();
    if (tree.kind == PairKind::BackFacing) return r.fragments;
    const Vec3& x = point.at;
    r.input = point.input;
    r.moved = point.moved();
    // (A fully hidden pair is answered without touching the pair's setup unless x is on contact.)
    // A moved point is on contact where its input is (answered_point.h).
    const bool contact = q.contact.onContact(tree, x) ||
                         (r.moved && q.contact.onContact(tree, r.input)) ||
                         q.contact.nearContact(mesh, tree, x);
    if (tree.kind == PairKind::FullyHidden && !contact) return r.fragments;
    if (!q.startPair(mesh, tree.receiver, tree.light, x)) return r.fragments;
    if (tree.kind == PairKind::FullyVisible) {
        r.fragments.add(r.pair.lightClipped());
        return r.fragments;
    }
    r.x = x;
    if (contact) {
        // x lies in the plane of an occluder that reaches B's plane: it may stand on that
        // occluder's contact with B, where the tree's cells (closed sets of lines) give the limit
        // of the neighbouring points and the contract asks for more (a segment touching an
        // occluder only at x is not blocked). Answered from the pair's occluders directly, which
        // applies the contract exactly (ActiveOccluders::activate). Measure zero: a rendered
        // point is almost never exactly there.
        q.contactAnswer = true;
        q.contact.gatherCandidates(tree);
        r.preparePyramid();
        q.clipCandidates();
        return r.fragments;
    }
    if (tree.kind == PairKind::FullyHidden) return r.fragments;
    r.tree = &tree;
    q.deferredPrepared = !tree.partial();
    q.walk.walk(trace, region);
    return r.fragments;
}

uint32_t FromPointQuery::nodesVisited() const { return q_->walk.nodesVisited(); }
bool FromPointQuery::answeredOnContact() const { return q_->contactAnswer; }
void FromPointQuery::setWorkLimit(uint64_t planeTests) { q_->run.budget.setLimit(planeTests); }
uint64_t FromPointQuery::workLimit() const { return q_->run.budget.limit(); }
uint64_t FromPointQuery::work() const { return q_->run.budget.work(); }
bool FromPointQuery::limitReached() const { return q_->run.budget.reached(); }
WorkStage FromPointQuery::limitStage() const { return q_->run.budget.limitStage(); }
const std::array<uint64_t, kWorkStages>& FromPointQuery::stageWork() const {
    return q_->run.budget.stageWork();
}
uint32_t FromPointQuery::deferredActive() const { return static_cast<uint32_t>(q_->active.size()); }
uint32_t FromPointQuery::deferredClips() const { return q_->clip.clips(); }
void FromPointQuery::setChainOptions(const ChainOptions& o) { q_->run.chainOptions = o; }
const ChainCounts& FromPointQuery::chainCounts() const { return q_->chain.counts(); }
bool FromPointQuery::usedSilhouettes() const { return q_->silhouettes.active(); }
bool FromPointQuery::usedLightEdges() const { return q_->edges.active(); }
EdgeDecline FromPointQuery::lightEdgeDecline() const { return q_->edges.decline(); }
uint32_t FromPointQuery::clustersUsed() const {
    return static_cast<uint32_t>(q_->clusters.used().size());
}
uint32_t FromPointQuery::clustersUsedByExactSides() const {
    return q_->clusters.usedByExactSides();
}
uint32_t FromPointQuery::solidGroupsLeftOut() const { return q_->solids.groupsLeftOut(); }
uint32_t FromPointQuery::solidFacesLeftOut() const { return q_->solids.facesLeftOut(); }
bool FromPointQuery::hiddenBySolid() const { return q_->solids.hidden(); }

FromPointResult fromPointQuery(const PolygonMesh& mesh, const HistoryTree& tree,
                               const AnsweredPoint& x) {
    FromPointQuery query;
    FromPointResult out;
    const FragmentList& fragments = query.run(mesh, tree, x, &out.trace);
    out.answeredOnContact = query.answeredOnContact();
    out.fragments = fragments.polygons();
    out.nodesVisited = query.nodesVisited();
    out.deferredActive = query.deferredActive();
    out.deferredClips = query.deferredClips();
    return out;
}

}  // namespace penumbra::vis
