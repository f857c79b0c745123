// The hierarchy of a mesh's face boxes, as the renderer builds it (EmbreeScene::faceBoxes) for the
// direct query and the face groups.
#pragma once

#include <cstdint>
#include <vector>

#include "visibility/box_tree.h"
#include "visibility/polygon_mesh.h"

namespace penumbra::test {

inline vis::BoxTree faceBoxTree(const vis::PolygonMesh& mesh) {
    std::vector<vis::Bounds3> boxes;
    for (uint32_t f = 0; f < mesh.faces.size(); ++f) boxes.push_back(mesh.faceBounds(f));
    return vis::BoxTree(boxes);
}

}  // namespace penumbra::test
