// Validation (long): capillary entry into a square tube in 3D at 30 / 60 / 90 degrees (issue 14,
// drainage item 1); scene and closed form in fluid_capillary_entry_3d_case.hpp, derivation and
// measurements in docs/fluid.md "Capillary entry into a square tube in 3D". Each run: w = 6 dx
// (the last two: 8 dx), the flat-wall wetting setting (kGhost), 40 ms (~3300 steps, ~70 s CPU;
// 8 dx ~120 s).
// Readings (8 over the 40 ms): "stalls" = the gas in the tube (volume / w^2) stays below 1.5 w at
// every reading (three quarters of the 2 w tube) and grows by < 0.1 w over the second half;
// "invades" = it exceeds 1.5 w at some reading (at 30 degrees the column then goes through the
// tube and on round the loop, so the reading at 40 ms alone would not do). Bracketing: stalls at 0.9 f*, invades above (1.1 f* at 30 degrees,
// 1.25 f* at 60 degrees, where 1.1 f* creeps: measured, not asserted). At 90 degrees the entry
// pressure is 0: a pressure drop of 0.2 x 2 gamma / w (a fifth of the 60-degree threshold) invades.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "tests/validation/fluid_capillary_entry_3d_case.hpp"

using namespace poresph;
using namespace poresph::entry3d;

namespace {

const char* kRef = "Mayer-Stowe-Princen entry pressure of a square tube: (2 gamma / w)(cos t + sqrt(pi/4 - t + sin t cos t)) "
                   "below 45 deg, 4 gamma cos(t) / w above (docs/fluid.md), Young-Laplace Eq. 1.5";

void stalls(double theta, double ratio) {
  char path[200];
  std::snprintf(path, sizeof path, "%s/fluid_capillary_entry_3d_t%g_r%.2f.txt", PORESPH_BINARY_DIR, theta, ratio);
  const EntryResult r = runEntry3D(theta, ratio, 0.04, kGhost, path);
  std::printf("theta %g, %.2f f*: tube gas %.3f w at T/2, %.3f w at T; front %.3f / %.3f w; %lld steps, %.1f s\n", theta, ratio,
              r.tubeHalf, r.tubeEnd, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_LT(r.tubeMax, 1.5);
  EXPECT_LT(r.tubeEnd - r.tubeHalf, 0.1);
  char q[160];
  std::snprintf(q, sizeof q, "largest gas volume in the square tube / w^3 at f = %.2f f*, %g deg, 40 ms (stalls)", ratio, theta);
  test::recordValidation({"fluid_capillary_entry_3d", q, r.tubeMax, 0.0, r.tubeMax, r.resolution + ", t = 40 ms", r.wall,
                          "largest reading < 1.5 (tube 2 w long) and growth over the second half < 0.1", kRef});
}

void invades(double theta, double ratio) {
  char path[200];
  std::snprintf(path, sizeof path, "%s/fluid_capillary_entry_3d_t%g_r%.2f.txt", PORESPH_BINARY_DIR, theta, ratio);
  const EntryResult r = runEntry3D(theta, ratio, 0.04, kGhost, path);
  std::printf("theta %g, %.2f: tube gas %.3f w at T/2, %.3f w at T, largest %.3f w; front %.3f / %.3f w; %lld steps, %.1f s\n", theta, ratio,
              r.tubeHalf, r.tubeEnd, r.tubeMax, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_GT(r.tubeMax, 1.5);
  char q[160];
  std::snprintf(q, sizeof q, "largest gas volume in the square tube / w^3 at f = %.2f %s, %g deg, 40 ms (invades)", ratio,
                theta > 89.999 ? "x (2 gamma / w) / (rho Lx)" : "f*", theta);
  test::recordValidation({"fluid_capillary_entry_3d", q, r.tubeMax, 0.0, r.tubeMax, r.resolution + ", t = 40 ms", r.wall,
                          "largest reading > 1.5 (tube 2 w long)", kRef});
}

}  // namespace

TEST(FluidCapillaryEntry3DAngles, Stalls30At090) { stalls(30, 0.9); }
TEST(FluidCapillaryEntry3DAngles, Invades30At110) { invades(30, 1.1); }
TEST(FluidCapillaryEntry3DAngles, Stalls60At090) { stalls(60, 0.9); }
TEST(FluidCapillaryEntry3DAngles, Invades60At125) { invades(60, 1.25); }
TEST(FluidCapillaryEntry3DAngles, Invades90AtFifthOf60) { invades(90, 0.2); }

// Finer tube, w = 8 dx (cell 40 x 12 x 12 dx, ~120 s CPU per run): at 60 degrees 1.1 f*, which
// only crept at 6 dx, enters and keeps advancing; 0.9 f* still stalls: the threshold within 10 %.
TEST(FluidCapillaryEntry3DAngles, Stalls60At090Tube8) {
  const EntryResult r = runEntry3D(60, 0.9, 0.04, kGhost, "", 8);
  std::printf("w 8 dx, 0.90 f*: tube gas %.3f / %.3f w, largest %.3f; front %.3f / %.3f w; %lld steps, %.1f s\n", r.tubeHalf,
              r.tubeEnd, r.tubeMax, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_LT(r.tubeMax, 1.5);
  EXPECT_LT(r.tubeEnd - r.tubeHalf, 0.1);
  test::recordValidation({"fluid_capillary_entry_3d", "largest gas volume in the square tube / w^3 at f = 0.90 f*, 60 deg, w = 8 dx, 40 ms (stalls)",
                          r.tubeMax, 0.0, r.tubeMax, r.resolution + ", t = 40 ms", r.wall,
                          "largest reading < 1.5 (tube 2 w long) and growth over the second half < 0.1", kRef});
}
TEST(FluidCapillaryEntry3DAngles, Enters60At110Tube8) {
  const EntryResult r = runEntry3D(60, 1.1, 0.04, kGhost, "", 8);
  std::printf("w 8 dx, 1.10 f*: tube gas %.3f / %.3f w, largest %.3f; front %.3f / %.3f w; %lld steps, %.1f s\n", r.tubeHalf,
              r.tubeEnd, r.tubeMax, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_GT(r.tubeEnd, 0.6);
  EXPECT_GT(r.tubeEnd - r.tubeHalf, 0.15);  // still advancing (at 6 dx: +0.15 from 0.59, creeping)
  test::recordValidation({"fluid_capillary_entry_3d", "gas volume in the square tube / w^3 at f = 1.10 f*, 60 deg, w = 8 dx, 40 ms (enters)",
                          r.tubeEnd, 0.0, r.tubeEnd, r.resolution + ", t = 40 ms", r.wall,
                          "> 0.6 and growth over the second half > 0.15", kRef});
}
