// Validation: capillary entry into a square tube in 3D (issue 14, drainage item 1); scene and
// closed form in fluid_capillary_entry_3d_case.hpp, derivation and measurements in docs/fluid.md
// "Capillary entry into a square tube in 3D". Default suite: 60 degrees, the wetting setting of
// the flat-wall validation (kGhost), w = 6 dx, 20 ms per run; the three angles at 40 ms are the
// long test test_fluid_capillary_entry_3d_long.cpp.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "tests/validation/fluid_capillary_entry_3d_case.hpp"

using namespace poresph;
using namespace poresph::entry3d;

namespace {
const char* kRef = "Mayer-Stowe-Princen entry pressure of a square tube (4 gamma cos(theta) / w for theta >= 45 deg; "
                   "docs/fluid.md), Young-Laplace Eq. 1.5";
}

// Below the threshold (f = 0.9 f*) the meniscus bulges into the tube's entrance and stops.
TEST(FluidCapillaryEntry3D, GasStaysOutBelowThreshold60) {
  const EntryResult r = runEntry3D(60, 0.9, 0.02, kGhost);
  std::printf("0.90 f*: front %.3f w at T/2, %.3f w at T, %lld steps, %.1f s\n", r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_LT(r.frontEnd, 0.5);                // the meniscus stays near the entrance
  EXPECT_LT(r.frontEnd - r.frontHalf, 0.1);  // and does not advance
  test::recordValidation({"fluid_capillary_entry_3d", "gas front past the square tube's entrance / w at f = 0.90 f*, 60 deg (stays out)",
                          r.frontEnd, 0.0, r.frontEnd, r.resolution + ", t = 20 ms", r.wall,
                          "< 0.5 w and advance over the second half < 0.1 w", kRef});
}

// Above it the gas enters and keeps advancing. Measured: at 1.1 f* the front stalls at ~0.7 w
// (40 ms), so the numerical threshold lies between 1.1 and 1.25 f* at w = 6 dx (10-25 % above
// the closed form: the 10 % is not met); this test asserts the 1.25 f* bracket.
TEST(FluidCapillaryEntry3D, GasEntersAboveThreshold60) {
  const EntryResult r = runEntry3D(60, 1.25, 0.02, kGhost);
  std::printf("1.25 f*: front %.3f w at T/2, %.3f w at T, %lld steps, %.1f s\n", r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_GT(r.frontEnd, 0.6);
  EXPECT_GT(r.frontEnd - r.frontHalf, 0.15);  // still advancing
  EXPECT_GT(r.tubeEnd, 0.6);                  // the gas fills the tube's section, not a thin finger
  test::recordValidation({"fluid_capillary_entry_3d", "gas front past the square tube's entrance / w at f = 1.25 f*, 60 deg (enters)",
                          r.frontEnd, 0.0, r.frontEnd, r.resolution + ", t = 20 ms", r.wall,
                          "> 0.6 w, advance over the second half > 0.15 w, gas volume in the tube > 0.6 w^3", kRef});
}

// Manual studies: ENTRY3D_THETA, ENTRY3D_RATIO, ENTRY3D_TEND, ENTRY3D_EXTRA (fluid keys, e.g. the
// value of kGhost), ENTRY3D_NW, ENTRY3D_MU, ENTRY3D_C, ENTRY3D_PB, ENTRY3D_TAG (dump name).
TEST(FluidCapillaryEntry3D, DISABLED_Probe) {
  const double theta = env("ENTRY3D_THETA", 60), ratio = env("ENTRY3D_RATIO", 1.1), T = env("ENTRY3D_TEND", 0.04);
  const std::string extra = std::getenv("ENTRY3D_EXTRA") ? std::getenv("ENTRY3D_EXTRA") : "";
  char path[200];
  std::snprintf(path, sizeof path, "%s/fluid_capillary_entry_3d_t%g_r%.2f%s.txt", PORESPH_BINARY_DIR, theta, ratio,
                std::getenv("ENTRY3D_TAG") ? std::getenv("ENTRY3D_TAG") : "");
  const EntryResult r = runEntry3D(theta, ratio, T, extra, path);
  std::printf("PROBE theta %g ratio %.2f: front %.3f / %.3f w, tube gas %.3f / %.3f w, max var %.3g, %lld steps, %.1f s wall; %s\n",
              theta, ratio, r.frontHalf, r.frontEnd, r.tubeHalf, r.tubeEnd, r.maxVar, r.steps, r.wall,
              r.resolution.c_str());
}
