// Validation (label `long`): the 3D static droplet of test_fluid_droplet_3d.cpp at R/dx = 15,
// the resolution (91 125 particles). Scene and protocol: fluid_droplet_3d_case.hpp.
#include <gtest/gtest.h>

#include "tests/validation/fluid_droplet_3d_case.hpp"

TEST(FluidDroplet3D, StaticLaplaceJumpR15) { poresph::test::runStaticDroplet3D(15); }
