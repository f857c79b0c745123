// Random points for the tests: a random convex combination of given points (strictly inside their
// hull when every weight is positive) and of a face's vertices, from the one sampler of the tree
// (engine/scene/surface_samples.h; points on a scene's surfaces: penumbra::surfaceSamples).
#pragma once

#include "engine/scene/surface_samples.h"

namespace penumbra::test {

using penumbra::randomCombination;
using penumbra::randomPointOn;

}  // namespace penumbra::test
