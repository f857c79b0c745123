#include <gtest/gtest.h>
#include "visibility/predicates.h"
TEST(Predicates, Placeholder) { EXPECT_EQ(penumbra::vis::orientSign({0,0,0},{1,0,0},{0,1,0},{0,0,1}), penumbra::vis::Sign::Positive); }
