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
