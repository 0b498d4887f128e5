// Validation (issue 11, item 3, 3D body-fitted), finer resolution (label validation_long): the
// pressurised spherical cavity of pore_shells_3d_case.hpp on 10 shells across the wall
// (a = 10 dx, 33,492 particles); the default suite runs 6 and 8 (test_pore_shells_3d.cpp).
#include <gtest/gtest.h>

#include "tests/validation/pore_shells_3d_case.hpp"

using namespace poresph;

TEST(CouplingPore3DLong, PressurisedSphericalShellsAgainstLameTenAcross) {
  test::SphereOptions o;
  o.shells = 10;
  const test::SphereResult r = test::runPressurisedSphere(o);
  // Measured (0.012 s, averages over the last 6 ms): bore displacement 0.60 % (the 5 %);
  // the pairs' radial force 1.0297 of p 4 pi a^2 (1.047 / 1.036 at 6 / 8 shells); the displacement
  // against Lame at that force -2.30 %; hoop stress, second shell +4.52 % (the 5 %), first
  // (surface) shell +11.1 % (not met; 7.8 / 9.3 % at 6 / 8 shells: it does not converge).
  EXPECT_EQ(r.crossings, 0);
  EXPECT_LT(r.uError, 0.05);
  EXPECT_LT(std::abs(r.uAtLoadError), 0.03);
  EXPECT_GT(r.loadRatio, 1.0);
  EXPECT_LT(r.loadRatio, 1.035);
  EXPECT_LT(r.hoop2Error, 0.05);
  EXPECT_LT(r.hoopError, 0.12) << "regression bound, not the issue's 5 %";
  const std::string res = "3D, body-fitted shells (clay and water), 10 across the wall, " +
                          std::to_string(r.particles) + " particles";
  const char* ref = "Lame, thick sphere at the water's pressure";
  const std::string name = "coupling_pressurised_pore_3d_shells_10";
  test::recordValidation({name, "radial displacement at the bore", r.u, r.uExact, r.uError, res,
                          r.wall, "< 5 %", ref});
  test::recordValidation({name, "hoop stress, second shell", r.hoop2, r.hoop2Exact, r.hoop2Error,
                          res, r.wall, "< 5 %", ref});
  test::recordValidation({name, "hoop stress, first (surface) shell", r.hoop, r.hoopExact,
                          r.hoopError, res, r.wall, "< 12 % (regression bound; issue: 5 %, not met)", ref});
}
