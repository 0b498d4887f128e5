// Validation: capillary rise scene (fluid_capillary_rise_case.hpp) at 90 degrees: no rise. The
// Jurin heights at 30 / 60 degrees need ~300 ms of simulated time: test_fluid_capillary_rise_long.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <string>

#include "tests/validation/fluid_capillary_rise_case.hpp"

using namespace poresph;
using namespace poresph::capillary_rise;

// 90 degrees: no capillary pressure, the column stays at the reservoir level.
TEST(FluidCapillaryRise90, NoRiseAt90) {
  const RiseResult r = runRise(90.0, kGhost, 0.06, "_ghost");
  const double hdx = r.mean / r.dx;
  test::recordValidation({"fluid_capillary_rise_2d", "mean rise between plates at 90 deg after 60 ms / dx (wetting_ghost)",
                          hdx, 0.0, 0.0, kRes, r.wall, "h within +-0.5 dx (5 % of the 60-degree rise)", "Jurin: h = 0 at 90 degrees"});
  EXPECT_LT(std::abs(hdx), 0.5);
}

