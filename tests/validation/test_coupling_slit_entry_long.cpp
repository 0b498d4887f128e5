// Validation: capillary entry into a slit between elastic walls (issue 11 item 5; label
// validation_long, ~40 s CPU per run on one core). samples/coupling_elastic_slit_entry.yaml, set-up and
// closed forms in coupling_slit_entry_case.hpp and docs/coupling.md "Gas entry between elastic
// walls". A body force f along the periodic loop drives the gas against the Young-Laplace
// threshold f* of the slit (Eq. 1.10 contact angle); the blocks forming the slit are clay on
// rollers, so the water's pressure opens the slit by delta and lowers the threshold to
// f*_el = f* (1/(w + delta) - 1/H) / (1/w - 1/H). Criteria of the fixed-wall test
// (test_fluid_capillary_entry.cpp): gas front past the entrance < 0.5 w and advancing < 0.1 w
// over the second half below the threshold, > 0.6 w and advancing > 0.15 w above it. The opening
// (time mean over the last third, wet rows) against the estimate at the face and end pressures
// the fluids put on the blocks, y (1 + nu)((1 - nu) p_face - nu p_ends) / E per block
// (coupling_slit_entry_case.hpp: exact by Betti's theorem for the mean of the wet face).
#include <gtest/gtest.h>

#include <cstdlib>

#include "tests/support/validation_record.hpp"
#include "tests/validation/coupling_slit_entry_case.hpp"

using namespace poresph;
namespace se = poresph::slitentry;

namespace {

struct EntryRun {
  double frontHalf = 0, frontEnd = 0;  ///< gas front past the entrance / w at T/2 and T
  double opening = 0, estimate = 0;     ///< time means over the last third
  double pFace = 0, pEnds = 0;          ///< mean face / weighted end pressures, last third
  double pLeft = 0, pRight = 0;         ///< the ends' mean pressures, last third
  double cpu = 0;
  long long steps = 0;
};

EntryRun runEntry(double ratio, bool fixedWalls, const std::string& model = "extrapolated") {
  test::Stopwatch clock;
  Scene s = loadSceneText(se::entryScene(ratio, fixedWalls, model), "coupling_elastic_slit_entry.yaml");
  Simulation& sim = *s.sim;
  auto integrator = makeIntegrator("leapfrog");
  const int gas = se::materialId(sim, "gas");
  const double T = s.endTime;
  EntryRun r;
  long n = 0;
  int k = 1;
  double nextSample = 0.0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.time >= 2.0 / 3.0 * T && sim.time >= nextSample) {  // every 0.2 ms
      const se::SlitState st = se::readSlit(sim);
      r.opening += st.opening(), r.estimate += st.estimate();
      r.pFace += 0.5 * (st.pFaceLow + st.pFaceHigh), r.pEnds += 0.5 * (st.pEndsLow + st.pEndsHigh);
      r.pLeft += st.pLeft, r.pRight += st.pRight;
      ++n;
      nextSample = sim.time + 2e-4;
    }
    if (sim.time >= T * k / 8 - 1e-12) {
      const se::SlitState st = se::readSlit(sim);
      const double f = se::gasFront(sim, gas) / se::kW;
      if (k == 4) r.frontHalf = f;
      std::printf("  %s %.2f f*: t = %.3f s, front %.3f w, opening %.3e m (estimate %.3e), p face %.1f / "
                  "%.1f, ends %.1f / %.1f Pa\n",
                  fixedWalls ? "fixed" : model.c_str(), ratio, sim.time, f, st.opening(), st.estimate(),
                  st.pFaceLow, st.pFaceHigh, st.pEndsLow, st.pEndsHigh);
      ++k;
    }
  }
  r.frontEnd = se::gasFront(sim, gas) / se::kW;
  if (n > 0) r.opening /= n, r.estimate /= n, r.pFace /= n, r.pEnds /= n, r.pLeft /= n, r.pRight /= n;
  r.cpu = clock.seconds();
  r.steps = sim.step;
  std::printf("  %s %.2f f*: front %.3f w at T/2, %.3f w at T; opening %.4e m, estimate %.4e m "
              "(%.2f %%), p face %.2f, ends %.2f (left %.2f, right %.2f) Pa; face opening %.4e m; "
              "f*_el / f* = %.4f; %lld steps, %.1f s\n",
              fixedWalls ? "fixed" : model.c_str(), ratio, r.frontHalf, r.frontEnd, r.opening, r.estimate,
              r.estimate != 0.0 ? 100.0 * (r.opening / r.estimate - 1.0) : 0.0, r.pFace, r.pEnds, r.pLeft,
              r.pRight, r.opening * se::kT / (se::kT - 0.5e-4), se::thresholdRatio(r.opening * se::kT / (se::kT - 0.5e-4)),
              r.steps, r.cpu);
  return r;
}

const char* kRes = "2D, dx = 0.1 mm: slit w = 10 dx, 30 dx long, channel H = 30 dx, loop 80 dx, quintic h = dx, "
                   "clay blocks 10 dx thick on rollers (E 12 kPa), extrapolated pairs, t = 80 ms";

}  // namespace

// Below the threshold of the opened slit (0.9 f* = 0.91 f*_el) the gas stays at the entrance, and
// the blocks open the slit as the elastic estimate at the pressures the water puts on them.
TEST(CouplingSlitEntryLong, GasStaysOutBelowThresholdAndTheSlitOpensAsEstimated) {
  const EntryRun r = runEntry(0.9, false);
  EXPECT_LT(r.frontEnd, 0.5);
  EXPECT_LT(r.frontEnd - r.frontHalf, 0.1);
  // Measured (2026-11-27): opening 0.940 of the estimate at face 75.4 Pa, ends 111.5 / 76.9 Pa
  // (gas side / water side); with the slit's pressure on the ends too the estimate would be 14 %
  // higher (docs/coupling.md). The remaining 6 % is the traction the pairs deliver.
  const double err = std::abs(r.opening / r.estimate - 1.0);
  EXPECT_LT(err, 0.10);
  EXPECT_GT(r.opening, 0.0);
  const double fel = se::thresholdRatio(r.opening * se::kT / (se::kT - 0.5e-4));
  test::recordValidation({"coupling_slit_entry", "gas front past the entrance / w at f = 0.90 f* (stays out)",
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.cpu,
                          "< 0.5 w and advance over the second half < 0.1 w",
                          "Young-Laplace entry of the opened slit, f*_el = " + std::to_string(fel) + " f*"});
  test::recordValidation({"coupling_slit_entry", "opening of the slit at 0.90 f* (water pressure on the blocks)",
                          r.opening, r.estimate, err, kRes, r.cpu, "< 10 %",
                          "block on a roller: t (1 + nu)((1 - nu) p_face - nu p_ends) / E (Betti) at the measured pressures"});
}

TEST(CouplingSlitEntryLong, GasEntersAboveThreshold) {
  const EntryRun r = runEntry(1.1, false);
  EXPECT_GT(r.frontEnd, 0.6);
  EXPECT_GT(r.frontEnd - r.frontHalf, 0.15);
  test::recordValidation({"coupling_slit_entry", "gas front past the entrance / w at f = 1.10 f* (enters)",
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.cpu,
                          "> 0.6 w and advance over the second half > 0.15 w",
                          "Young-Laplace entry of the opened slit (f*_el ~ 0.99 f*)"});
}

// Manual bracket (docs/coupling.md): SLIT_ENTRY_RATIO=1.05 [SLIT_ENTRY_FIXED=1]
// [SLIT_ENTRY_MODEL=mirror] ctest -R CouplingSlitEntryLong.Probe -V
TEST(CouplingSlitEntryLong, Probe) {
  const char* ratio = std::getenv("SLIT_ENTRY_RATIO");
  if (!ratio) GTEST_SKIP() << "set SLIT_ENTRY_RATIO";
  const char* model = std::getenv("SLIT_ENTRY_MODEL");
  runEntry(std::atof(ratio), std::getenv("SLIT_ENTRY_FIXED") != nullptr, model ? model : "extrapolated");
}
