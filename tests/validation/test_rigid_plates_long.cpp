// Rigid bodies (physics/rigid, docs/rigid.md), validation case 4 of issue 15: resolution study of
// the block confined by four force-controlled plates (set-up in test_rigid_plates_case.hpp),
// with the plates bonded to the block's face along their normal (`bonded: slip`: the face slides
// freely along the plate; TL clay with hourglass control 1). 20 / 40 / 60 particles across.
// Asserted: the interior strain error, the interior stress error and the plate displacement error
// fall with resolution, the displacement error at least at order 0.7 from 20 to 60, and the
// finest interior stress within 2 %. (The A.18 contact plates do not converge: their face
// particles slide off the plate particles' lattice and sink into the valleys between them;
// docs/rigid.md.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/validation/test_rigid_plates_case.hpp"

using namespace poresph;
using namespace poresph::test;

TEST(RigidPlatesLong, SlipBondedPlatesConvergeToTheUniformStateAtFirstOrder) {
  const int ns[3] = {20, 40, 60};
  PlatesResult r[3];
  double strainErr[3], uErr[3];
  for (int k = 0; k < 3; ++k) {
    r[k] = runPlates(ns[k], "total_lagrangian", 1.0, "slip");
    const double exact = -r[k].uExact * 2.0 / 0.02;
    strainErr[k] = std::abs(r[k].interiorStrain / exact - 1.0);
    uErr[k] = std::abs(r[k].meanU / r[k].uExact - 1.0);
    EXPECT_LT(r[k].worstForce, 1e-3) << ns[k] << " across: a plate does not carry its load";
  }
  const double order = std::log(uErr[0] / uErr[2]) / std::log(3.0);
  std::printf("  plate displacement error %.2f / %.2f / %.2f %% (order %.2f), interior strain "
              "%.2f / %.2f / %.2f %%, interior stress %.2f / %.2f / %.2f %%\n",
              100 * uErr[0], 100 * uErr[1], 100 * uErr[2], order, 100 * strainErr[0],
              100 * strainErr[1], 100 * strainErr[2], 100 * r[0].worst, 100 * r[1].worst,
              100 * r[2].worst);
  EXPECT_LT(uErr[1], uErr[0]);
  EXPECT_LT(uErr[2], uErr[1]);
  EXPECT_LT(strainErr[2], strainErr[0]);
  EXPECT_LT(r[2].worst, r[0].worst);
  EXPECT_GT(order, 0.7);
  EXPECT_LT(r[2].worst, 0.02) << "interior stress at 60 across";
  test::recordValidation({"rigid_plates_slip_displacement", "mean plate displacement (m), bonded: slip",
                          r[2].meanU, r[2].uExact, uErr[2],
                          "2D, 60 x 60 particles (20 / 40 / 60 studied), TL hourglass 1",
                          r[0].seconds + r[1].seconds + r[2].seconds, "falls, order > 0.7",
                          "closed form s L / (4 (lambda + mu)), plane strain"});
  test::recordValidation({"rigid_plates_slip_stress", "worst interior |sigma + s| / s, bonded: slip",
                          r[2].worst, 0.0, r[2].worst, "2D, 60 x 60 particles, TL hourglass 1",
                          r[2].seconds, "< 2 % at 60 across", "uniform stress (equilibrium)"});
}
