// Issue 15, validation case 2 (settling) in 3D at two more sizes (label validation_long): the
// sphere of test_rigid_stokes_3d.cpp in a bigger cell (a = 3 dx, cell 8 a) and at a finer
// resolution (a = 4 dx, cell 6 a); 13,824 particles each, ~85-90 s CPU each (loaded machine).
// Case and reference (Hasimoto 1959 / Sangani & Acrivos 1982) in rigid_stokes_3d_case.hpp.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/validation/rigid_stokes_3d_case.hpp"

using namespace poresph;

namespace {

void checkAndRecord(const test::Stokes3dResult& r, const char* name, const char* resolution) {
  EXPECT_LT(std::abs(r.err), 0.10) << "terminal velocity against Hasimoto / Sangani & Acrivos";
  EXPECT_LT(std::abs(r.Ulate / r.U - 1.0), 0.01) << "not steady";
  EXPECT_LT(r.transverse, 1e-6) << "the sphere left the axis of its weight";
  EXPECT_LT(r.Re, 0.01) << "not Stokes flow";
  test::recordValidation({name, "terminal velocity of a sphere in a periodic cubic array, V_b - u_cell (m/s)",
                          r.U, r.Uexact, std::abs(r.err), resolution, r.seconds, "< 10 %",
                          "Hasimoto 1959 / Sangani & Acrivos 1982 simple cubic array, Stokes flow"});
}

}  // namespace

// measured +5.62 % (V_b - V_f: +6.67 %), steady to 0.004 % at 0.09 s (1,918 steps)
TEST(RigidStokes3dLong, BiggerCellEightRadii) {
  const test::Stokes3dResult r = test::runStokes3d(3, 8.0, 0.09);
  checkAndRecord(r, "rigid_stokes_sphere_3d_cell8", "3D, a = 3 dx (136 particles), cell 8 a = 24 dx, 13,824 particles");
}

// measured +5.23 % (V_b - V_f: +7.40 %), steady to 0.27 % at 0.05 s (1,894 steps)
TEST(RigidStokes3dLong, FinerSphereFourSpacings) {
  const test::Stokes3dResult r = test::runStokes3d(4, 6.0, 0.05);
  checkAndRecord(r, "rigid_stokes_sphere_3d_a4", "3D, a = 4 dx (280 particles), cell 6 a = 24 dx, 13,824 particles");
}
