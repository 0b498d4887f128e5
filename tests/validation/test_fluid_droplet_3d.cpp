// Validation: CSF surface tension in 3D (Eqs. 5.6-5.8, 1.9; curvature of Eq. 5.8 with the
// moment-matrix correction). Static spherical droplet in a periodic box: Laplace jump 2 gamma / R
// (Young-Laplace, Eq. 1.5) within 5 %, the drop stays intact, spurious currents reported as a
// capillary number. Default suite: R/dx = 10 (27 000 particles); R/dx = 15 (91 125 particles) is
// the `long` test test_fluid_droplet_3d_long.cpp. Scene and protocol: fluid_droplet_3d_case.hpp.
#include <gtest/gtest.h>

#include "tests/validation/fluid_droplet_3d_case.hpp"

TEST(FluidDroplet3D, StaticLaplaceJumpR10) { poresph::test::runStaticDroplet3D(10); }
