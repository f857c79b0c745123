// Which history trees of a scene stay true when some of its lights move (the viewer's Move light
// window, `view`/`screenshot --move-light`): a tree of the scene before is handed to the store of
// the moved scene when nothing it depends on moved.
//
// A tree of the pair (receiver patch R, light L) depends on R's region, L's polygon and the faces
// that cut the shaft between them (the segments from R to L). A moved light M is a face like any
// other: it is an occluder of every pair whose shaft it crosses, before or after the move. So a
// tree is kept only when
//  - R's face and L are not moved faces (the moved light's own pairs, as light and as receiver,
//    are rebuilt),
//  - M's box is certainly outside the hull of R and L both before and after the move
//    (EmbreeScene::mayCutShaft, the test the shaft query makes of every face): M then meets none
//    of the pair's segments in either scene, so the occluders that decide it are the same and the
//    tree answers every point exactly as one built in the moved scene would,
//  - both stores build trees with the same options (the build budget), the receivers' patches
//    are the same in both scenes (PatchLayout's patch size follows the
//    mesh's bounds, which a light moved outside them changes: then no tree is kept), and every
//    face but the moved ones has the same vertex numbers and coordinates (the tree's nodes name
//    occluder edges by vertex number).
// Only the receiver patches' own trees are kept: the refined sub-patch trees are a cache of the
// render (patch_layout.h), rebuilt where the render asks again.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>

namespace penumbra {

class EmbreeScene;
class VisibilityStore;

struct KeptTrees {
    size_t kept = 0;
    // Why none could be kept at all ("" when each tree was decided on its own).
    std::string noneBecause;
};

// Inserts into `after` (the moved scene's store, built over `bvhAfter`) a copy of every tree of
// `before` (the scene before the move, over `bvhBefore`) that the move of the faces `movedFaces`
// leaves true (above). The scenes must have the same faces; `before` may be building trees
// meanwhile (a snapshot of its published trees is taken).
KeptTrees keepTreesPastLightMove(const VisibilityStore& before, const EmbreeScene& bvhBefore,
                                 VisibilityStore& after, const EmbreeScene& bvhAfter,
                                 std::span<const uint32_t> movedFaces);

}  // namespace penumbra
