// Issue 15, validation case 2 (settling), the issue's own case (label validation_long): a heavy
// sphere settling in a viscous fluid in a closed container reaches the Stokes terminal velocity
// with the container's wall correction. The sphere of test_rigid_stokes_3d.cpp (same fluid, same
// drive) at the centre of a closed spherical cavity of radius 4 a walled by no-slip `wall`
// particles; reference: the exact Stokes drag of a sphere at the centre of a spherical container,
// F = 6 pi mu a K U, K = (1 - l^5) / (1 - 9/4 l + 5/2 l^3 - 9/4 l^5 + l^6), l = a / R
// (Happel & Brenner 1965, Sec. 4-22). Case and reference in rigid_stokes_3d_case.hpp; numbers in
// docs/rigid.md ("Settling sphere in a closed container").
#include <gtest/gtest.h>

#include <cmath>

#include "tests/validation/rigid_stokes_3d_case.hpp"

using namespace poresph;

namespace {

void checkAndRecord(const test::Stokes3dResult& r, const char* name, const char* resolution) {
  EXPECT_LT(std::abs(r.err), 0.10) << "terminal velocity against Stokes with the container's wall correction";
  EXPECT_LT(std::abs(r.Ulate / r.U - 1.0), 0.01) << "no plateau: not steady";
  EXPECT_LT(r.transverse, 1e-6) << "the sphere left the axis of its weight";
  EXPECT_LT(r.offset, 0.1) << "the sphere left the container's centre (the reference is concentric)";
  EXPECT_LT(r.Re, 0.01) << "not Stokes flow";
  test::recordValidation({name, "terminal velocity of a sphere at the centre of a closed spherical container (m/s)",
                          r.U, r.Uexact, std::abs(r.err), resolution, r.seconds, "< 10 %",
                          "Stokes drag with the spherical container's wall correction (Happel & Brenner 1965, "
                          "Sec. 4-22), Stokes flow"});
}

}  // namespace

TEST(RigidStokes3dContainerLong, ThreeSpacingsPerRadius) {
  const test::Stokes3dResult r = test::runStokes3d(3, 4.0, 0.024, true);
  checkAndRecord(r, "rigid_stokes_sphere_container_a3",
                 "3D, a = 3 dx (136 particles), cavity radius 4 a, 7,072 fluid + 7,624 wall particles");
}

TEST(RigidStokes3dContainerLong, FourSpacingsPerRadius) {
  const test::Stokes3dResult r = test::runStokes3d(4, 4.0, 0.024, true);
  checkAndRecord(r, "rigid_stokes_sphere_container_a4",
                 "3D, a = 4 dx (280 particles), cavity radius 4 a, 16,976 fluid + 12,208 wall particles");
}
