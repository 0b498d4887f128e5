// Validation: capillary entry (issue 5, item 6). A periodic 2D channel of height H with a slit of
// width w (walls of contact angle theta, Eq. 1.10 with the prescribed contact-line normal).
// Gas fills the wide channel just before the slit, water the rest. A uniform body force f along x
// (equal densities: a pressure rise rho f Lx around the loop) must beat the difference of the
// Young-Laplace pressures of the slit and the wide channel:
//   rho f* Lx = 2 gamma cos(theta) (1/w - 1/H).
// Below f* the gas stays at the slit entrance, above it the gas enters.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "tests/validation/fluid_capillary_entry_case.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

using test::Entry;
using test::EntryResult;
using test::runEntry;

// Records of FLUID_DX studies go beside the default ones, not over them (kRes names dx = 0.1 mm).
std::string recordDir() {
  return std::getenv("FLUID_DX") ? std::string(PORESPH_BINARY_DIR) + "/validation-records-explore" : std::string();
}

const char* kRes = "dx = 0.1 mm: slit w = 10 dx, channel H = 30 dx, loop Lx = 80 dx, slit length 30 dx, theta = 60 deg, "
                   "quintic h = dx, mu = 0.01 Pa s, equal densities, p_b = 100 Pa, t = 80 ms";

}  // namespace

// Below the Young-Laplace threshold (f = 0.9 f*) the meniscus bulges into the slit entrance and
// stops; above it (f = 1.1 f*) the gas front keeps advancing: the threshold is within 10 %.
TEST(FluidCapillaryEntry, GasStaysOutBelowThreshold) {
  const double ratio = Entry::env("FLUID_RATIO", 0.9);
  const EntryResult r = runEntry(ratio, 0.08);
  char q[120];
  std::snprintf(q, sizeof q, "gas front past the slit entrance / w at f = %.2f f* (stays out)", ratio);
  std::printf("%.2f f*: front %.3f w at T/2, %.3f w at T, %lld steps, %.1f s\n", ratio, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_LT(r.frontEnd, 0.5);                  // the meniscus cap stays near the entrance
  EXPECT_LT(r.frontEnd - r.frontHalf, 0.1);    // and does not advance
  test::recordValidation({"fluid_capillary_entry_2d", q,
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.wall, "< 0.5 w and advance over the second half < 0.1 w",
                          "Young-Laplace entry 2 gamma cos(theta) / w (minus the wide channel's)"},
                         recordDir());
}

TEST(FluidCapillaryEntry, GasEntersAboveThreshold) {
  const double ratio = Entry::env("FLUID_RATIO", 1.1);
  const EntryResult r = runEntry(ratio, 0.08);
  char q[120];
  std::snprintf(q, sizeof q, "gas front past the slit entrance / w at f = %.2f f* (enters)", ratio);
  std::printf("%.2f f*: front %.3f w at T/2, %.3f w at T, %lld steps, %.1f s\n", ratio, r.frontHalf, r.frontEnd, r.steps, r.wall);
  EXPECT_GT(r.frontEnd, 0.6);
  EXPECT_GT(r.frontEnd - r.frontHalf, 0.15);  // still advancing
  test::recordValidation({"fluid_capillary_entry_2d", q,
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.wall, "> 0.6 w and advance over the second half > 0.15 w",
                          "Young-Laplace entry 2 gamma cos(theta) / w (minus the wide channel's)"},
                         recordDir());
}
