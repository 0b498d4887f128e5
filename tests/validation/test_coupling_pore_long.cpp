// Issue 11 item 3 on the voxel lattice (label validation_long, tests/long-tests.txt): the hoop
// stress at the wall of the staircase bore within the 5 % of Lame. The default test
// (test_coupling.cpp, CouplingPore.PressurisedVoxelPoreAgainstLame) asserts the wall estimator
// (solid::estimateWallStress) below 8 % at 16 and 24 dx across the wall (measured 6.2 / 5.5 %:
// the linear fit under-reads the steep Lame profile by ~2.4 (3 dx / a)^2, docs/coupling.md
// "Staircase bore"); at 32 dx across that bias is ~2 % and the estimator meets 5 %. The
// first-layer mean of the particle stresses stays 20-25 % low (the staircase; regression guard).
#include <gtest/gtest.h>

#include <string>

#include "tests/support/validation_record.hpp"
#include "tests/validation/coupling_pore_case.hpp"

using namespace poresph;

TEST(CouplingPoreLong, VoxelPoreWallHoopStressWithinFivePercentAt32Across) {
  const pore::PoreResult r = pore::runPressurisedPore(false, 32, 0.01);
  EXPECT_EQ(r.crossings, 0);
  EXPECT_LT(r.displacementError, 0.05);
  EXPECT_LT(r.hoopError, 0.30);  // first-layer mean: the staircase (regression guard)
  EXPECT_LT(r.wallHoopError, 0.05);  // the 5 %
  EXPECT_NEAR(r.wallRadius, 0.01, 0.05 * 0.01);
  const std::string res = "2D plane strain, lattice, 32 dx across the wall, " +
                          std::to_string(r.particles) + " particles";
  test::recordValidation({"coupling_pressurised_pore_lattice_32", "radial displacement at the bore",
                          r.uMeasured, r.uExact, r.displacementError, res, r.wall, "< 5 %",
                          "Lame, thick cylinder at the water's pressure"});
  test::recordValidation({"coupling_pressurised_pore_lattice_32",
                          "hoop stress at the bore (first-layer mean)", r.hoopMeasured, r.hoopExact,
                          r.hoopError, res, r.wall, "< 30 % (staircase)",
                          "Lame, thick cylinder at the water's pressure"});
  test::recordValidation({"coupling_pressurised_pore_lattice_32",
                          "hoop stress at the wall r = a (solid::estimateWallStress)", r.wallHoop,
                          r.wallHoopExact, r.wallHoopError, res, r.wall, "< 5 % (issue 11)",
                          "Lame, thick cylinder at the water's pressure"});
}
