// Validation: sessile drop in 3D on a flat lattice-aligned wall (issue 14 "Sessile droplet ... in
// 3D"), the 2D flat-wall test's wetting settings (test::kWettingGhostSettings). Scene and
// measurement: fluid_wetting_3d_case.hpp; docs/fluid.md "Sessile drops in 3D".
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/validation/fluid_wetting_3d_case.hpp"
#include "tests/validation/fluid_wetting_case.hpp"

using namespace poresph;

namespace {
double envd(const char* n, double d) { return std::getenv(n) ? std::atof(std::getenv(n)) : d; }
}  // namespace

// Manual study: SESSILE3D_THETA, SESSILE3D_RDX, SESSILE3D_T0, SESSILE3D_TEND, SESSILE3D_MU,
// SESSILE3D_EXTRA (fluid keys replacing the validated setting), SESSILE3D_BOX (half side in R0),
// SESSILE3D_HEIGHT (fluid layer in R0), SESSILE3D_TAG; SESSILE3D_VERBOSE prints the angle every 5 ms.
TEST(FluidWetting3D, DISABLED_Probe) {
  const std::string extra = std::getenv("SESSILE3D_EXTRA") ? std::getenv("SESSILE3D_EXTRA") : test::kWettingGhostSettings;
  test::runSessile3D(envd("SESSILE3D_THETA", 90), static_cast<int>(envd("SESSILE3D_RDX", 8)),
                     envd("SESSILE3D_T0", 0.03), envd("SESSILE3D_TEND", 0.06), envd("SESSILE3D_MU", 0.01), extra,
                     envd("SESSILE3D_EVERY", 0.005), envd("SESSILE3D_BOX", 2.0), envd("SESSILE3D_HEIGHT", 2.0),
                     std::getenv("SESSILE3D_TAG") ? std::getenv("SESSILE3D_TAG") : "");
}

namespace {
// The default case: 120 degrees at R0/dx 6 (4536 particles, cell 18 x 18 x 14 dx), from the cube,
// mu 0.01 (Oh 0.036), the sphere-fit angle averaged over 20-30 ms (every 2.5 ms).
test::Wetting3DResult coarse120(const std::string& extra, const std::string& tag) {
  return test::runSessile3D(120.0, 6, 0.02, 0.03, 0.01, extra, 0.0025, 1.5, 1.75, tag);
}
}  // namespace

// Coarse 3D sessile drop at 120 degrees, the 2D setting unchanged (test::kWettingGhostSettings,
// wetting_curvature with kappa / (D - 1), Eq. 1.6's kappa being the sum of the two principal
// curvatures). Measured (docs/fluid.md "Sessile drops in 3D"): 120.43 (119.6-122.2), cap 119.35;
// without wetting_curvature the same drop reads 122.89 (121.8-124.5), cap 121.63: the meniscus-
// foot bias of 2D (+2.9 here). Asserted within 2 degrees, so that the bias fails the test.
// ~35 s CPU measured on a machine at load 15-18 (4536 particles, 993 steps).
TEST(FluidWetting3D, OneHundredTwentyCoarseFromACube) {
  const auto r = coarse120(test::kWettingGhostSettings, "");
  char res[300];
  std::snprintf(res, sizeof res,
                "3D flat lattice-aligned wall, R0/dx = 6, cube start, periodic cell 18 x 18 x 14 dx, quintic h = dx, "
                "Oh = 0.036, equal densities, p_b = 100 Pa, mean over 20-30 ms (%.1f to %.1f), %lld steps, "
                "max speed %.2g m/s at 30 ms",
                r.lo, r.hi, r.steps, r.speed);
  test::recordValidation({"fluid_wetting_3d_flat_theta120_R6",
                          "contact angle (degrees), sphere fit above 2 dx, time mean", r.mean, 120.0,
                          std::abs(r.mean - 120.0) / 120.0, res, r.wall, "|error| < 2 degrees",
                          "prescribed wall angle (Eq. 1.10), wetting: normal with ghost colour, wetting_scale 0.05, "
                          "wall_normal: wide, wetting_curvature (kappa / 2 in 3D)"});
  EXPECT_NEAR(r.mean, 120.0, 2.0);
  // the end state is a cap (not a film, not lifted off): the cap reading from volume and height agrees
  EXPECT_NEAR(r.cap, 120.0, 5.0);
}
