// HistoryTree: the exact visibility between one receiver polygon B and one light polygon L,
// recorded as the binary CSG history of the set of lines stabbing B and L (Mora & Aveneau 2005).
//
// Each inner node stores one oriented occluder edge (v0 -> v1). Its hyperplane in Plücker space
// splits line space: a line from y to z is on the node's positive side when
// orient3d(y, z, v0, v1) > 0 (plucker.h), and then follows child[0]; on the negative side it
// follows child[1]. Leaves are encoded in the child slots as kVisibleLeaf / kHiddenLeaf.
// 16 bytes per node, as in the paper.
#pragma once

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::vis {

inline constexpr uint32_t kVisibleLeaf = 0xFFFFFFFFu;
inline constexpr uint32_t kHiddenLeaf = 0xFFFFFFFEu;
constexpr bool isLeaf(uint32_t child) { return child >= kHiddenLeaf; }

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
// Fills DeferredOccluder::box for every deferred occluder of `tree` (a tree of `mesh`) and builds
// HistoryTree::deferredIndex over them.
struct HistoryTree;
void indexDeferred(const PolygonMesh& mesh, HistoryTree& tree);

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
    // cheaply (indexDeferred() fills it; an empty box only means "no quick skip").
    Bounds3 box;
};

struct HistoryTree {
    uint32_t receiver = 0;
    uint32_t light = 0;
    PairKind kind = PairKind::FullyVisible;
    std::string_view why;  // one sentence: why this kind (static string)

    std::vector<HistoryNode> nodes;  // nodes[0] is the root when kind == Penumbra
    // Vertex ids below meshVertexCount refer to the mesh; the others to extraVertices: vertices
    // constructed by clipping occluders to the region between B's and L's planes (rounded
    // constructions, see pair_setup.cpp).
    uint32_t meshVertexCount = 0;
    std::vector<Vec3> extraVertices;
    // Debug information, not part of the 16-byte budget: the occluder face of each node.
    std::vector<uint32_t> nodeOccluder;
    // The occluders left out of a partial tree, in insertion order (largest shadow first). A
    // Penumbra tree may have no node and only these (the budget ran out on the first occluder).
    std::vector<DeferredOccluder> deferred;
    BoxTree deferredIndex;  // over the deferred boxes (indexDeferred), not stored in files

    Vec3 vertex(const PolygonMesh& mesh, uint32_t id) const {
        return id < meshVertexCount ? mesh.vertices[id] : extraVertices[id - meshVertexCount];
    }
    // Storage the tree needs: nodes and constructed vertices (not the debug information).
    size_t bytes() const {
        size_t b = nodes.size() * sizeof(HistoryNode) + extraVertices.size() * sizeof(Vec3);
        b += deferred.size() * sizeof(uint32_t);
        return b;
    }
    bool partial() const { return !deferred.empty(); }
    uint32_t depth() const;
    uint32_t leafCount(bool visible) const;
};

}  // namespace penumbra::vis
