// Balanced-force CSF (physics/fluid/surface_tension.hpp, option `surface_tension_form:
// balanced`): spurious currents and Laplace jump of the 2D static droplet of
// fluid_spurious_case.hpp against the default CSF (issue 14).
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/validation/fluid_spurious_case.hpp"

using poresph::test::runSpurious2D;
using poresph::test::SpuriousRow;

// Probe: PORESPH_PROBE_EXTRA holds extra fluid keys (", key: value"), PORESPH_PROBE_RDX R/dx.
TEST(FluidSurfaceBalanced, DISABLED_Probe) {
  const char* e = std::getenv("PORESPH_PROBE_EXTRA");
  const char* r = std::getenv("PORESPH_PROBE_RDX");
  const char* hh = std::getenv("PORESPH_PROBE_H");
  const char* t0 = std::getenv("PORESPH_PROBE_TRELAX");
  const char* t1 = std::getenv("PORESPH_PROBE_TEND");
  runSpurious2D(r ? std::atoi(r) : 10, hh ? std::atof(hh) : 1.0, e ? e : "", "_probe",
                t0 ? std::atof(t0) : 0.003, t1 ? std::atof(t1) : 0.012,
                std::getenv("PORESPH_PROBE_PB") ? std::atof(std::getenv("PORESPH_PROBE_PB")) : 0.0);
}

// R/dx = 10, equal densities: the balanced form against the default CSF at 12 and 24 ms. The
// spurious currents measured at 12 ms are mostly the relaxation of the lattice-cut disc (they
// halve from 12 to 24 ms with either form: Stokes creep of the interface particles, not a
// steady current); the balanced form lowers them by ~10 % at 12 ms and ~25 % at 24 ms.
TEST(FluidSurfaceBalanced, Droplet2DAgainstCsf) {
  const std::string bal = ", surface_tension_form: balanced";
  const SpuriousRow b12 = runSpurious2D(10, 1.0, bal, "_balanced_12ms", 0.003, 0.012);
  const SpuriousRow b24 = runSpurious2D(10, 1.0, bal, "_balanced_24ms", 0.003, 0.024);
  const SpuriousRow c24 = runSpurious2D(10, 1.0, "", "_csf_24ms", 0.003, 0.024);
  std::printf("Ca 12 ms balanced %.3e; 24 ms balanced %.3e, csf %.3e (ratio %.2f)\n", b12.caMean,
              b24.caMean, c24.caMean, b24.caMean / c24.caMean);
  EXPECT_LT(b12.err, 0.03);
  EXPECT_LT(b24.err, 0.08);
  EXPECT_LT(b12.caMean, 1.2e-2);
  EXPECT_LT(b24.caMean, 0.6 * b12.caMean);  // the relaxation decays
  EXPECT_LT(b24.caMean, 0.9 * c24.caMean);  // the balanced form wins at 24 ms
}

// The best spurious-current setting measured in issue 14's second stop: the default CSF with a
// background pressure p_b = 100 Pa (3 gamma / R) at R/dx 20, 12 ms: Ca 3.64e-3, jump +0.01 %
// (p_b = 0: 4.38e-3, 1.03 %). Bounds ~20 % above the measured Ca and at 1 % on the jump.
TEST(FluidSurfaceBalanced, CsfWithBackgroundPressureR20) {
  const SpuriousRow r = runSpurious2D(20, 1.0, "", "_pb100", 0.003, 0.012, 100.0);
  EXPECT_LT(r.caMean, 4.4e-3);
  EXPECT_LT(r.err, 0.01);
}
