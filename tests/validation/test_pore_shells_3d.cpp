// Validation (issue 11, item 3, 3D body-fitted): a pressurised spherical cavity of water in a
// thick elastic sphere on Fibonacci shells, against Lame's thick sphere (the run and the closed
// form: pore_shells_3d_case.hpp; docs/coupling.md "3D body-fitted shells"). Default suite: 6 and
// 8 shells across the wall b - a = a (a = 6 / 8 dx). The finer 10 shells: test_pore_shells_3d_long.cpp.
// Study: PORE_SHELLS_STUDY=<duration s> [PORE_SHELLS_LIST="4 6 8 10"] and the hooks of
// studyOptions() run the listed resolutions and print the per-shell stresses.
#include <gtest/gtest.h>

#include <sstream>

#include "tests/validation/pore_shells_3d_case.hpp"

using namespace poresph;

TEST(CouplingPore3D, PressurisedSphericalShellsAgainstLame) {
  if (std::getenv("PORE_SHELLS_STUDY")) {
    const char* list = std::getenv("PORE_SHELLS_LIST");
    std::istringstream in(list ? list : "4 6 8 10");
    int shells;
    while (in >> shells) test::runPressurisedSphere(test::studyOptions(shells));
    return;
  }
  // Measured (0.012 s of relaxation, averages over the last 6 ms; 6 / 8 / 10 shells, the last in
  // the long test): bore displacement 4.89 / 1.75 / 0.60 %; the pairs' radial force on the clay
  // 1.047 / 1.036 / 1.030 of p 4 pi a^2; the displacement against Lame at that force +0.14 /
  // -1.75 / -2.30 %; hoop stress, second shell +6.5 / +5.1 / +4.5 %, first (surface) shell +7.8 /
  // +9.3 / +11.1 %.
  double previousLoad = 1.0e9;
  for (int shells : {6, 8}) {
    test::SphereOptions o;
    o.shells = shells;
    const test::SphereResult r = test::runPressurisedSphere(o);
    const bool coarse = shells == 6;
    EXPECT_EQ(r.crossings, 0);
    // the 5 % on the bore displacement at 8 across (6 across: a regression bound)
    EXPECT_LT(r.uError, coarse ? 0.055 : 0.05) << shells << " shells";
    // the solid's answer to the load the pairs put on it: Lame at that load
    EXPECT_LT(std::abs(r.uAtLoadError), 0.03) << shells << " shells";
    // the load's excess over p 4 pi a^2 (the pair sum on a concave wall) falls with dx
    EXPECT_GT(r.loadRatio, 1.0) << shells << " shells";
    EXPECT_LT(r.loadRatio, previousLoad) << shells << " shells";
    previousLoad = r.loadRatio;
    // hoop stress: regression bounds, not the 5 % (met only from 10 shells on, second shell)
    EXPECT_LT(r.hoop2Error, coarse ? 0.08 : 0.065) << shells << " shells";
    EXPECT_LT(r.hoopError, 0.11) << shells << " shells";
    const std::string res = "3D, body-fitted shells (clay and water), " + std::to_string(shells) +
                            " across the wall, " + std::to_string(r.particles) + " particles";
    const std::string name = "coupling_pressurised_pore_3d_shells_" + std::to_string(shells);
    const char* ref = "Lame, thick sphere at the water's pressure";
    test::recordValidation({name, "radial displacement at the bore", r.u, r.uExact, r.uError, res,
                            r.wall, coarse ? "< 5.5 % (regression bound)" : "< 5 %", ref});
    test::recordValidation({name, "hoop stress, second shell", r.hoop2, r.hoop2Exact,
                            r.hoop2Error, res, r.wall,
                            coarse ? "< 8 % (regression bound; issue: 5 %, not met)"
                                   : "< 6.5 % (regression bound; issue: 5 %, not met)", ref});
    test::recordValidation({name, "hoop stress, first (surface) shell", r.hoop, r.hoopExact,
                            r.hoopError, res, r.wall, "< 11 % (regression bound; issue: 5 %, not met)", ref});
  }
}
