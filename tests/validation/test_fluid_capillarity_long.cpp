// Capillarity studies (issue 14), label `long` (tests/long-tests.txt).
// DISABLED_Probe.* are manual probes driven by environment variables (run with
// --gtest_also_run_disabled_tests --gtest_filter='*Probe*'); they write no validation record.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/support/fluid_drop.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {
double env(const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; }
std::string envs(const char* k, const char* d) { return std::getenv(k) ? std::getenv(k) : d; }
}  // namespace

// Static drop: PROBE_DIM, PROBE_RDX, PROBE_H (h/dx), PROBE_RHOG (gas density, liquid 1000),
// PROBE_MUL, PROBE_MUG, PROBE_CL, PROBE_CG, PROBE_PB, PROBE_GAMMA, PROBE_EXTRA (", key: value"),
// PROBE_TRELAX, PROBE_TEND, PROBE_BOX.
TEST(DISABLED_Probe, StaticDrop) {
  test::Stopwatch clock;
  test::FluidDrop::Params p;
  p.dim = static_cast<int>(env("PROBE_DIM", 2));
  p.rOverDx = env("PROBE_RDX", 10);
  p.hOverDx = env("PROBE_H", 1.0);
  p.boxOverR = env("PROBE_BOX", 3.0);
  p.gamma = env("PROBE_GAMMA", 0.05);
  p.rhoGas = env("PROBE_RHOG", 1000);
  p.muLiquid = env("PROBE_MUL", 0.3);
  p.muGas = env("PROBE_MUG", p.muLiquid);
  p.cLiquid = env("PROBE_CL", 2.0);
  p.cGas = env("PROBE_CG", p.cLiquid);
  p.backgroundPressure = env("PROBE_PB", 0.0);
  p.extra = envs("PROBE_EXTRA", "");
  test::FluidDrop d(p);
  const double tRelax = env("PROBE_TRELAX", 0.003), tEnd = env("PROBE_TEND", 0.012);
  const double window = env("PROBE_WINDOW", d.B / p.cLiquid);
  const test::FluidDrop::Measurement m = d.settleAndMeasure(tRelax, tEnd, window);
  const double ref = (p.dim == 2 ? 1.0 : 2.0) * p.gamma / p.R;
  double rl, rg;
  d.extent(rl, rg);
  std::printf("PROBE dim %d R/dx %g h/dx %g rho_g %g mu %g/%g c %g/%g pb %g extra '%s': %lld particles %ld steps\n"
              "  jump %.4f Pa (ref %.4f) error %+.2f %% swing %.2f %%; Ca max end %.3e mean %.3e rms %.3e; "
              "liquid <= %.3f R gas >= %.3f R; %.1f s\n",
              p.dim, p.rOverDx, p.hOverDx, p.rhoGas, p.muLiquid, p.muGas, p.cLiquid, p.cGas, p.backgroundPressure,
              p.extra.c_str(), static_cast<long long>(d.count()), m.steps, m.dpMean, ref,
              100 * (m.dpMean - ref) / ref, 100 * (m.dpMax - m.dpMin) / ref, p.muLiquid * m.speedEnd / p.gamma,
              p.muLiquid * m.speedMean / p.gamma, p.muLiquid * m.rmsMean / p.gamma, rl / p.R, rg / p.R,
              clock.seconds());
  const std::string dump = envs("PROBE_DUMP", "");
  if (!dump.empty()) d.dumpSlice(dump);
}

// Tilted staircase wall: PROBE_THETA, PROBE_TILT, PROBE_RDX, PROBE_TEND, PROBE_EXTRA.
#include "tests/validation/fluid_wetting_case.hpp"
TEST(DISABLED_Probe, TiltedSessile) {
  const auto r = test::runTiltedSessile(env("PROBE_THETA", 60), env("PROBE_TILT", 30),
                                        static_cast<int>(env("PROBE_RDX", 10)), env("PROBE_TEND", 0.06), false,
                                        envs("PROBE_EXTRA", ""));
  EXPECT_GT(r.theta, 0.0);
}

// Wetting at 30 and 150 degrees on a flat lattice-aligned wall (issue 14 item 4), one setting
// (wetting: normal, wetting_scale 0.15) at two resolutions, rectangle start, 60 ms: the model does
// NOT reach the angle (measured 48.7 / 51.4 deg for 30 at R0/dx 10 / 15, 130.6 / 125.6 for 150;
// the 30-degree drop is still spreading: 44.5 at 90 ms, 37.8 at 180 ms, R0/dx 10). Recorded as a
// failing row against the 5 degrees; asserted only against regression (3 degrees worse
// than measured). This is why the 30-degree capillary entry is 20-30 % low (docs/fluid.md).
TEST(FluidWettingExtremes, Angles30And150FlatWallTwoResolutions) {
  struct Case { double theta; int rdx; double measured; };
  for (const Case c : {Case{30, 10, 48.71}, Case{30, 15, 51.38}, Case{150, 10, 130.57}, Case{150, 15, 125.56}}) {
    const auto r = test::runTiltedSessile(c.theta, 0.0, c.rdx, 0.06, false);
    char cs[96], res[200];
    std::snprintf(cs, sizeof cs, "fluid_wetting_flat_theta%.0f_R%d", c.theta, c.rdx);
    std::snprintf(res, sizeof res,
                  "2D flat lattice-aligned wall, R0/dx = %d, rectangle start, quintic h = dx, Oh = 0.18, equal densities, "
                  "p_b = 100 Pa, t = 60 ms, %lld steps", c.rdx, r.steps);
    test::recordValidation({cs, "contact angle (degrees), circle fit above 2 dx", r.theta, c.theta,
                            std::abs(r.theta - c.theta) / c.theta, res, r.wall,
                            "issue target |error| < 5 deg: NOT met; asserted within 3 deg of the measured level",
                            "prescribed wall angle (Eq. 1.10), wetting: normal"});
    if (c.theta < 90) EXPECT_LT(r.theta, c.measured + 3.0) << "R0/dx " << c.rdx;
    else EXPECT_GT(r.theta, c.measured - 3.0) << "R0/dx " << c.rdx;
  }
}
