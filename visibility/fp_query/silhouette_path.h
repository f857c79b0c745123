// The silhouette path of a partial tree (deferred_silhouettes.h), taken when its silhouettes pay
// and x lies in their region: only the deferred faces that cross B's or L's plane are activated,
// the boundary chain is built from the pair's kept edges in the cone, and a cell's line is tested
// against the other deferred faces (the Surface slots) through the tree's hierarchy, from their
// input edges.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "visibility/deferred_silhouettes.h"
#include "visibility/fp_query/line_tests.h"
#include "visibility/history_tree.h"

namespace penumbra::vis {

struct QueryParts;

class SilhouettePath {
  public:
    explicit SilhouettePath(QueryParts& q) : q_(q) {}

    void reset() {
        surface_ = nullptr;
        clipped_ = 0;
        recentHits_.fill(UINT32_MAX);
        recentNext_ = 0;
    }
    // Takes the path for this run where the tree's silhouettes pay and x lies in their region:
    // activates the deferred faces that cross B's or L's plane and finds the kept edge groups in
    // the cone. False: not taken.
    bool prepare(const HistoryTree& tree);
    // Taken this run.
    bool active() const { return surface_ != nullptr; }
    const DeferredSilhouettes& silhouettes() const { return *surface_; }
    // The kept edge groups in the cone, in increasing order.
    const std::vector<uint32_t>& groups() const { return groups_; }
    // A cell that needs Algorithm 1: the Surface faces in the pyramid activated too, once per run.
    void activateRest();
    // The side Surface slot `slot`'s face faces x: +1 (x in front of its plane), -1, 0 (x on
    // it); decided for the silhouettes' region, else the exact sign, taken once per run.
    int sideAt(uint32_t slot);
    // The line tests of this path (LineTests' for the silhouette path): the activated faces that
    // cross B's or L's plane, then the Surface faces from their input edges.
    bool lineBlocked(const Vec3& y);
    std::optional<int> countLine(const Vec3& y);

  private:
    // The line from x through y against Surface slot `slot`'s face (closed; exact signs at y),
    // as LineTests::hitKind for an activated face.
    LineHit hitKind(uint32_t slot, const Vec3& y);
    bool hits(uint32_t slot, const Vec3& y) { return hitKind(slot, y) != LineHit::Miss; }
    bool isSurface(uint32_t slot) const {
        return surface_->slots[slot] == DeferredSilhouettes::Slot::Surface;
    }

    QueryParts& q_;
    const DeferredSilhouettes* surface_ = nullptr;
    // The activated faces that cross B's or L's plane (the first of the active occluders), and
    // whether the Surface faces were activated too.
    size_t clipped_ = 0;
    bool restActivated_ = false;
    std::vector<uint32_t> groups_, lineSlots_;
    std::vector<uint32_t> slotStamp_;  // per slot: the run whose sign slotSide_ holds
    std::vector<int8_t> slotSide_;
    uint32_t runStamp_ = 0;
    // The last Surface slots that hid a cell (a hidden cell's neighbour is mostly hidden by the
    // same few faces): tried before the hierarchy.
    static constexpr uint32_t kRecentHits = 8;
    std::array<uint32_t, kRecentHits> recentHits_{};
    uint32_t recentNext_ = 0;
};

}  // namespace penumbra::vis
