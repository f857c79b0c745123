// Shared by the precompute and visibility-file tests: a history tree built directly with
// vis::buildHistoryTree (no store, no BVH: every face a candidate) as the independent reference
// for a store's key, and a field-by-field comparison of two trees.
#pragma once

#include <gtest/gtest.h>

#include <span>
#include <string>

#include "engine/precompute/visibility_store.h"
#include "visibility/history_tree_builder.h"

namespace penumbra::test {

inline vis::HistoryTree referenceTree(const VisibilityStore& store, const PairKey& key) {
    const vis::ReceiverPatches& p = store.layout().patches(key.receiver);
    const bool whole = p.patches.size() <= 1;
    return vis::buildHistoryTree(
        store.scene().mesh, key.receiver, key.lightFace, store.options().build, {}, nullptr,
        whole ? std::span<const Vec3>{} : std::span<const Vec3>(p.patches[key.patch]));
}

inline ::testing::AssertionResult sameTree(const vis::HistoryTree& a, const vis::HistoryTree& b) {
    auto fail = [](const std::string& what) { return ::testing::AssertionFailure() << what; };
    if (a.receiver != b.receiver || a.light != b.light) return fail("faces differ");
    if (a.kind != b.kind)
        return fail("kind " + std::string(vis::toString(a.kind)) + " vs " +
                    std::string(vis::toString(b.kind)));
    if (a.why != b.why) return fail("why differs");
    if (a.meshVertexCount != b.meshVertexCount) return fail("meshVertexCount differs");
    if (a.nodes.size() != b.nodes.size())
        return fail("node counts " + std::to_string(a.nodes.size()) + " vs " +
                    std::to_string(b.nodes.size()));
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        const vis::HistoryNode &x = a.nodes[i], &y = b.nodes[i];
        if (x.v0 != y.v0 || x.v1 != y.v1 || x.child[0] != y.child[0] || x.child[1] != y.child[1])
            return fail("node " + std::to_string(i) + " differs");
    }
    if (a.occluders != b.occluders) return fail("occluders differ");
    if (a.nodeOccluder != b.nodeOccluder) return fail("node occluders differ");
    if (a.deferred.size() != b.deferred.size())
        return fail("deferred occluder counts " + std::to_string(a.deferred.size()) + " vs " +
                    std::to_string(b.deferred.size()));
    for (size_t i = 0; i < a.deferred.size(); ++i) {
        const vis::DeferredOccluder &x = a.deferred[i], &y = b.deferred[i];
        if (x.face != y.face) return fail("deferred occluder " + std::to_string(i) + " differs");
        if (x.box.lo != y.box.lo || x.box.hi != y.box.hi)
            return fail("deferred occluder " + std::to_string(i) + ": box differs");
    }
    return ::testing::AssertionSuccess();
}

}  // namespace penumbra::test
