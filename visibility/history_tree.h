// HistoryTree: the exact visibility between one receiver polygon B and one light polygon L,
// recorded as the binary CSG history of the set of lines stabbing B and L (Mora & Aveneau 2005).
//
// Each inner node stores one oriented occluder edge: its supporting line, exactly (edge_line.h).
// Its hyperplane in Plücker space splits line space: a line from y to z is on the node's positive
// side when the side of line(y, z) against the edge's line is > 0 (for an input edge v0 -> v1,
// orient3d(y, z, v0, v1): plucker.h), and then follows child[0]; on the negative side it follows
// child[1]. Leaves are encoded in the child slots as kVisibleLeaf / kHiddenLeaf.
// 16 bytes per node, as in the paper. The edge is (v0, v1): two mesh vertex ids (an input edge of
// the occluder, or the line of one it was shortened from), or, with kClipEdge set in v0, the chord
// where occluder face (v0 & ~kClipEdge) meets the receiver's plane (v1 == kReceiverPlaneEdge) or
// the light's (v1 == kLightPlaneEdge): the new edge of a clipped occluder (clipped_occluder.h).
// No node refers to a constructed point.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/deferred_silhouettes.h"
#include "visibility/edge_line.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

inline constexpr uint32_t kVisibleLeaf = 0xFFFFFFFFu;
inline constexpr uint32_t kHiddenLeaf = 0xFFFFFFFEu;
constexpr bool isLeaf(uint32_t child) { return child >= kHiddenLeaf; }

inline constexpr uint32_t kClipEdge = 0x80000000u;
inline constexpr uint32_t kReceiverPlaneEdge = 0, kLightPlaneEdge = 1;
constexpr bool isClipEdge(uint32_t v0) { return (v0 & kClipEdge) != 0; }

struct HistoryNode {
    uint32_t v0 = 0, v1 = 0;  // oriented edge; vertex ids (see HistoryTree::vertex)
    uint32_t child[2] = {kVisibleLeaf, kVisibleLeaf};  // [0] positive side, [1] negative side
};
static_assert(sizeof(HistoryNode) == 16);

// What a (receiver, light) pair calls for. Only Penumbra pairs get a tree.
enum class PairKind : uint8_t {
    BackFacing,    // L entirely behind B's plane or B entirely behind L's plane: no light
    FullyVisible,  // no occluder can block any line between B and L
    FullyHidden,   // every line between B and L is blocked
    Penumbra,      // partly blocked: the tree decides per line (a partial tree: see deferred)
};
inline constexpr int kPairKindCount = 4;
std::string_view toString(PairKind k);
// Whether B's plane cuts the light: part of L lies behind it, below the horizon of every point of
// B (exact signs). Even with nothing in the shaft such a point sees only the part above.
bool horizonClipsLight(const PolygonMesh& mesh, uint32_t receiver, uint32_t light);
// The kind in words for a reader, which must not call "fully visible" a light the horizon cuts:
// toString(k), but "unoccluded, horizon-clipped" for a FullyVisible pair whose light B's plane
// cuts (horizonClipsLight).
std::string_view describeKind(PairKind k, bool horizonClipped);

// The sentences HistoryTree::why points to: the builder uses these, and a tree read back from a
// file maps its stored text to one of them (knownReasons()).
namespace reasons {
inline constexpr std::string_view kBackFacing =
    "the light is behind the receiver's plane or the receiver behind the light's";
inline constexpr std::string_view kNoOccluder = "no occluder between the receiver and the light";
inline constexpr std::string_view kBlockNothing =
    "occluders lie in the shaft but block no line between receiver and light";
inline constexpr std::string_view kSingleBlocksAll = "a single occluder blocks every line";
inline constexpr std::string_view kTogetherBlockAll = "the occluders together block every line";
inline constexpr std::string_view kPenumbra = "partly blocked: the history tree decides per line";
inline constexpr std::string_view kPartial =
    "partly blocked: the tree holds the occluders its build budget allowed, the others are "
    "clipped from each point";
}  // namespace reasons
// Fills what a tree derives from its mesh for queries (not stored in files): DeferredOccluder::box
// for every deferred occluder and HistoryTree::deferredIndex over them, HistoryTree::silhouettes,
// and contactPlanes. `receiverRegion`: the part of the receiver the tree was built for (its patch,
// receiver_patches.h); empty = the whole face.
struct HistoryTree;
void prepareForQueries(const PolygonMesh& mesh, HistoryTree& tree,
                       std::span<const Vec3> receiverRegion = {});

// The exact line of an edge (v0, v1) in the node encoding above, for the pair (receiver, light).
EdgeLine edgeLine(const PolygonMesh& mesh, uint32_t receiver, uint32_t light, uint32_t v0,
                  uint32_t v1);
// An approximate segment of that edge, in doubles, for display only: the input edge's end
// points, or the chord's part inside the occluder face and in front of the other plane.
std::pair<Vec3, Vec3> edgeSegment(const PolygonMesh& mesh, uint32_t receiver, uint32_t light,
                                  uint32_t v0, uint32_t v1);

// Every reason above, for mapping a stored text back to its static string.
std::span<const std::string_view> knownReasons();

// An occluder the build did not insert (it stopped at BuildOptions::maxLpSolves): a mesh face.
// FPQuery clips it to the region in front of B's and L's planes as the builder clips its
// occluders (pair_occluders.h), then clips every fragment that reaches a visible leaf against it,
// from the query point, with the same exact signs as the walk: a partial tree answers exactly
// like the complete one, only the work moves from the precompute to the query. Stored as the face
// alone (4 bytes): a partial tree of a large mesh defers tens of thousands.
struct DeferredOccluder {
    uint32_t face = 0;
    // Derived, not stored in files: the box of the face's vertices, which lets a query skip it
    // cheaply (prepareForQueries() fills it; an empty box only means "no quick skip").
    Bounds3 box;
};

struct HistoryTree {
    uint32_t receiver = 0;
    uint32_t light = 0;
    PairKind kind = PairKind::FullyVisible;
    std::string_view why;  // one sentence: why this kind (static string)

    std::vector<HistoryNode> nodes;  // nodes[0] is the root when kind == Penumbra
    uint32_t meshVertexCount = 0;    // of the mesh the tree was built for (ids below it)
    // Debug information, not part of the 16-byte budget: the occluder face of each node.
    std::vector<uint32_t> nodeOccluder;
    // The occluders left out of a partial tree, in insertion order (largest shadow first). A
    // Penumbra tree may have no node and only these (the budget ran out on the first occluder).
    std::vector<DeferredOccluder> deferred;
    BoxTree deferredIndex;  // over the deferred boxes (prepareForQueries), not stored in files
    // Derived (prepareForQueries), not stored: which of the deferred occluders' edges can bound a
    // shadow seen from B (deferred_silhouettes.h).
    DeferredSilhouettes silhouettes;
    // The occluder faces the build inserted, in insertion order (with `deferred`: every occluder
    // of the pair). The contact rule needs them: a query point on an occluder that reaches B's
    // plane is answered from these faces directly (fp_query/contact_rule.h).
    std::vector<uint32_t> occluders;
    // Derived (prepareForQueries), not stored: the planes of the inserted occluders that reach
    // B's plane (a vertex on or behind it). A query point exactly on one of these planes is
    // where the tree's limit answer and the contract can differ.
    std::vector<PlaneOrient> contactPlanes;
    // Derived (prepareForQueries), not stored: for a query point x a rounding in front of B's
    // plane. The tree answers for lines between B's plane and L, the contract for segments from
    // x, so they differ where an inserted occluder meets the sliver between B's plane and x that
    // those lines cross (a wall's contact line: FromPointQuery::nearContact). The boxes of the
    // inserted occluders that reach B's plane (contactPlanes' faces, in their order), and a
    // lower bound of B's plane's orient3d value over every vertex of the others (+infinity when
    // none): an x whose value stays below it can meet only the former.
    std::vector<Bounds3> contactBoxes;
    double contactClearance = std::numeric_limits<double>::infinity();

    EdgeLine edgeLine(const PolygonMesh& mesh, const HistoryNode& n) const {
        return vis::edgeLine(mesh, receiver, light, n.v0, n.v1);
    }
    // Storage the tree needs: nodes, occluder faces and deferred faces (not the debug
    // information).
    size_t bytes() const {
        return nodes.size() * sizeof(HistoryNode) + occluders.size() * sizeof(uint32_t) +
               deferred.size() * sizeof(uint32_t);
    }
    bool partial() const { return !deferred.empty(); }
    uint32_t depth() const;
    uint32_t leafCount(bool visible) const;
};

}  // namespace penumbra::vis
