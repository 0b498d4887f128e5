// Rigid bodies (physics/rigid, docs/rigid.md), validation case 2 of issue 15 (settling) in 3D: a
// rigid sphere settling through a periodic simple cubic array of its images against the drag of
// Hasimoto (1959) / Sangani & Acrivos (1982); case and reference in rigid_stokes_3d_case.hpp.
// RIGID_STOKES3D_PROBE="perRadius cellInRadii endTime [container]" runs one more case and prints it
// (container 1: the closed spherical cavity of radius cellInRadii x a; RIGID_STOKES3D_TRACE=1
// prints U along the run).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "tests/validation/rigid_stokes_3d_case.hpp"

using namespace poresph;

TEST(RigidStokes3d, Probe) {
  const char* env = std::getenv("RIGID_STOKES3D_PROBE");
  if (!env) GTEST_SKIP() << "set RIGID_STOKES3D_PROBE=\"perRadius cellInRadii endTime [container]\"";
  std::istringstream in(env);
  int n = 3, container = 0;
  double cell = 6.0, T = 0.05;
  in >> n >> cell >> T >> container;
  test::runStokes3d(n, cell, T, container != 0);
}

// a = 3 dx (136 particles, volume radius 3.19 dx), cell 6 a = 18 dx (5,832 particles), 0.04 s
// (853 steps, 18.7 s CPU on the loaded machine): measured U = V_b - u_cell +8.50 % above the
// cubic-array drag (V_b - V_f +11.1 %; steady to 0.09 % from 3/4 of the run to its end); a = 3 dx
// in a cell of 8 a and a = 4 dx in a cell of 6 a in test_rigid_stokes_3d_long.cpp (docs/rigid.md).
TEST(RigidStokes3d, SphereInAPeriodicCubicArraySettlesAtTheArrayVelocity) {
  const test::Stokes3dResult r = test::runStokes3d(3, 6.0, 0.04);
  EXPECT_LT(std::abs(r.err), 0.10) << "terminal velocity against Hasimoto / Sangani & Acrivos";
  EXPECT_LT(std::abs(r.Ulate / r.U - 1.0), 0.01) << "not steady";
  EXPECT_LT(r.transverse, 1e-6) << "the sphere left the axis of its weight";
  EXPECT_LT(r.Re, 0.01) << "not Stokes flow";
  test::recordValidation({"rigid_stokes_sphere_3d",
                          "terminal velocity of a sphere in a periodic cubic array, V_b - u_cell (m/s)", r.U,
                          r.Uexact, std::abs(r.err),
                          "3D, a = 3 dx (136 particles), cell 6 a = 18 dx, 5,832 particles", r.seconds,
                          "< 10 %",
                          "Hasimoto 1959 / Sangani & Acrivos 1982 simple cubic array, Stokes flow"});
}
