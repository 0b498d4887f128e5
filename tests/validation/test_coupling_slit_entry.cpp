// Issue 11 item 5, the reference of the slit's opening: the two clay blocks of
// samples/coupling_elastic_slit_entry.yaml alone (no fluid), on their rollers and pins, under a
// uniform pressure p on every wet face (solid boundary `pressure`). The exact state is uniform,
// sigma_xx = sigma_yy = -p, and each wet face moves back by p t (1 + nu)(1 - 2 nu) / E
// (coupling_slit_entry_case.hpp). This separates the geometry of the set-up (roller, pin, block)
// from the fluid-solid pairs, which test_coupling_slit_entry_long.cpp checks against the same
// estimate at the pressures the water puts on the faces.
#include <gtest/gtest.h>

#include "tests/support/validation_record.hpp"
#include "tests/validation/coupling_slit_entry_case.hpp"

using namespace poresph;
namespace se = poresph::slitentry;

TEST(CouplingSlitEntry, BlocksOnRollersOpenByTheUniformStateUnderUniformPressure) {
  test::Stopwatch clock;
  const double p = 75.0;  // ~ the slit's water pressure in the entry runs
  Scene s = loadSceneText(se::blocksAloneScene(p, 0.02), "coupling_elastic_slit_entry_blocks.yaml");
  Simulation& sim = *s.sim;
  auto integrator = makeIntegrator("leapfrog");
  double opening = 0.0, exact = 0.0;
  long k = 0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.time < 0.75 * s.endTime) continue;  // damped (3000 1/s): settled after ~5 ms
    const se::SlitState st = se::readSlit(sim);
    opening += st.opening();
    exact += se::faceDisplacement(p, p, st.yLow) + se::faceDisplacement(p, p, st.yHigh);
    ++k;
  }
  opening /= static_cast<double>(k);
  exact /= static_cast<double>(k);  // at the wet rows, t - dx/2 from the rollers
  const double err = std::abs(opening - exact) / exact;
  // the state is uniform: sigma_xx of an interior particle is -p as well
  const RealField sigma = sim.store.real("stress"), X = sim.store.real("reference_position");
  double sxx = 0.0, syy = 0.0;
  long n = 0;
  for (Index i = 0; i < sim.store.realCount(); ++i) {
    const Vec<2> Xi = sim.store.vec<2>(X, i);
    if (Xi[0] < 4.5e-3 || Xi[0] > 6.5e-3 || Xi[1] < 0.2e-3 || Xi[1] > 0.7e-3) continue;
    sxx += sim.store.mat<2>(sigma, i)(0, 0), syy += sim.store.mat<2>(sigma, i)(1, 1), ++n;
  }
  sxx /= n, syy /= n;
  std::printf("  blocks alone, p = %.1f Pa: opening %.4e m (2 p (t - dx/2)(1+nu)(1-2nu)/E = %.4e, %.2f %%), "
              "interior sigma_xx %.2f, sigma_yy %.2f Pa, %lld steps, %.1f s\n",
              p, opening, exact, 100.0 * err, sxx, syy, static_cast<long long>(sim.step), clock.seconds());
  EXPECT_LT(err, 0.02);
  EXPECT_NEAR(sxx, -p, 0.02 * p);
  EXPECT_NEAR(syy, -p, 0.02 * p);
  test::recordValidation({"coupling_slit_entry_blocks", "opening of the slit, clay blocks alone under p",
                          opening, exact, err,
                          "2D, dx 0.1 mm, blocks 30 x 10 dx on symmetry rollers, quintic h = dx",
                          clock.seconds(), "< 2 %", "uniform state: 2 p y (1 + nu)(1 - 2 nu) / E at the wet rows (y = t - dx/2)"});
}
