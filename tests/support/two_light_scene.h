// A small scene with two area lights far apart, for the tests of moving one light (which trees of
// the other light stay true: engine/precompute/moved_light_trees.h, the viewer's --move-light):
//   face 0  the floor, y = 0, x in [-1, 4], z in [-1, 1], facing up;
//   face 1  an occluder under light 0, y = 0.5, x and z in [-0.125, 0.125];
//   face 2  an occluder under light 1, y = 0.5, x in [2.875, 3.125], z in [-0.125, 0.125];
//   face 3  light 0, y = 1, x and z in [-0.25, 0.25], facing down;
//   face 4  light 1, y = 1, x in [2.75, 3.25], z in [-0.25, 0.25], facing down, plus `offset`.
// Every coordinate is a dyadic fraction, so an offset of dyadic fractions moves light 1 exactly.
// Light 1 lies outside every shaft between a face and light 0 as long as it stays at x >= 2.75
// and y >= 0.75: a shaft from a receiver at y >= 0 to light 0 (|x| <= 0.25 at y = 1) reaches at
// height y no further than x = 4 - 3.75 y (the floor's far edge to the light's), 1.19 at y = 0.75.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "visibility/vec3.h"

namespace penumbra::test {

// Writes dir/two_lights.obj and dir/two_lights.mtl; returns the OBJ's path.
inline std::filesystem::path writeTwoLightScene(const std::filesystem::path& dir,
                                                const vis::Vec3& offset = {0, 0, 0}) {
    std::ofstream(dir / "two_lights.mtl") << "newmtl floor\nKd 0.8 0.8 0.8\n"
                                             "newmtl block\nKd 0.5 0.5 0.5\n"
                                             "newmtl lamp\nKd 0 0 0\nKe 10 10 10\n";
    std::ostringstream obj;
    obj.precision(17);
    obj << "mtllib two_lights.mtl\n"
           "v -1 0 -1\nv -1 0 1\nv 4 0 1\nv 4 0 -1\n"
           "v -0.125 0.5 -0.125\nv -0.125 0.5 0.125\nv 0.125 0.5 0.125\nv 0.125 0.5 -0.125\n"
           "v 2.875 0.5 -0.125\nv 2.875 0.5 0.125\nv 3.125 0.5 0.125\nv 3.125 0.5 -0.125\n"
           "v -0.25 1 -0.25\nv 0.25 1 -0.25\nv 0.25 1 0.25\nv -0.25 1 0.25\n";
    for (const vis::Vec3& v : {vis::Vec3{2.75, 1, -0.25}, vis::Vec3{3.25, 1, -0.25},
                               vis::Vec3{3.25, 1, 0.25}, vis::Vec3{2.75, 1, 0.25}})
        obj << "v " << v.x + offset.x << ' ' << v.y + offset.y << ' ' << v.z + offset.z << '\n';
    obj << "usemtl floor\nf 1 2 3 4\n"
           "usemtl block\nf 5 6 7 8\nf 9 10 11 12\n"
           "usemtl lamp\nf 13 14 15 16\nf 17 18 19 20\n";
    const std::filesystem::path path = dir / "two_lights.obj";
    std::ofstream(path) << obj.str();
    return path;
}

}  // namespace penumbra::test
