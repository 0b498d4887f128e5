// The -a_w term of a moving boundary's pressure (Adami et al. 2012, Eq. 27; issue 11: "for moving
// walls add the -a_w term"): the fluid extrapolates a boundary particle's pressure with
// (g - a_w) . r, a_w the boundary's acceleration of the previous evaluation
// (Simulation::previousAcceleration). A closed rigid container full of water, released in free
// fall (the same gravity on the water and the body): in the container's frame there is no
// gravity, so the water must stay at rest relative to it at uniform pressure. Without the term
// the walls would be given the hydrostatic pressure of water at rest under g, a pressure
// difference rho g H across the water that pushes it up against the falling container (its
// relative speed would grow like g t).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"

using namespace poresph;

TEST(MovingWallAcceleration, WaterInAFreeFallingContainerStaysAtRestAtUniformPressure) {
  // Container: a rigid square ring 0.05 m wide, walls 3 particles thick (> one support), water
  // 0.04 x 0.04 m inside (16 x 16 particles, dx 2.5 mm), c = 20 m/s; 0.1 s of free fall.
  const std::string text = R"(dimension: 2
domain: {lo: [0.0, -0.1], hi: [0.1, 0.1]}
spacing: 0.0025
kernel: wendland_c2
end_time: 0.1
time_step: {adaptive: true, cfl: 0.5}
output: {every_time: 1.0}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
  - {name: box, model: rigid, density: 2000}
geometry:
  - {shape: box, lo: [0.025, 0.0], hi: [0.0725, 0.0475], material: box}
  - {shape: box, lo: [0.0325, 0.0075], hi: [0.065, 0.04], material: none}
  - {shape: box, lo: [0.0325, 0.0075], hi: [0.065, 0.04], material: water}
fluid:
  gravity: [0, -9.81]
rigid:
  gravity: [0, -9.81]
health: {domain_margin: 1.0}
)";
  Scene s = loadSceneText(text, "free_fall_container.yaml");
  Simulation& sim = *s.sim;
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  const double g = 9.81, rho = 1000.0;
  Index nWater = 0, nBox = 0;
  double yLo = 1e300, yHi = -1e300;
  for (Index i = 0; i < st.realCount(); ++i) {
    const int ph = st.data(st.phase())[i];
    if (ph == kPhaseFluid) {
      ++nWater;
      yLo = std::min(yLo, st.data(st.position())[2 * i + 1]);
      yHi = std::max(yHi, st.data(st.position())[2 * i + 1]);
    }
    if (ph == kPhaseRigid) ++nBox;
  }
  ASSERT_EQ(nWater, 13 * 13);
  ASSERT_GT(nBox, 0);
  const double H = yHi - yLo + sim.spacing;
  double worstRelative = 0.0, worstDp = 0.0;
  int k = 0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    sim.checkFinite();
    if (++k % 100 != 0 && !s.finished()) continue;
    // the container's velocity (mean over its particles: it does not rotate) and the water's
    // largest speed relative to it; the mean pressure of the water's bottom and top rows
    double vb[2] = {0, 0}, y0 = 1e300, y1 = -1e300;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const double* p = st.data(st.real("pressure"));
    for (Index i = 0; i < st.realCount(); ++i)
      if (st.data(st.phase())[i] == kPhaseRigid) vb[0] += v[2 * i] / nBox, vb[1] += v[2 * i + 1] / nBox;
    for (Index i = 0; i < st.realCount(); ++i)
      if (st.data(st.phase())[i] == kPhaseFluid) y0 = std::min(y0, x[2 * i + 1]), y1 = std::max(y1, x[2 * i + 1]);
    double pBottom = 0, pTop = 0;
    int nb = 0, nt = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] != kPhaseFluid) continue;
      worstRelative = std::max(worstRelative, std::hypot(v[2 * i] - vb[0], v[2 * i + 1] - vb[1]));
      if (x[2 * i + 1] < y0 + 2.5 * sim.spacing) pBottom += p[i], ++nb;
      if (x[2 * i + 1] > y1 - 2.5 * sim.spacing) pTop += p[i], ++nt;
    }
    worstDp = std::max(worstDp, std::abs(pBottom / nb - pTop / nt));
    if (s.finished()) {
      std::printf("  free fall: t = %.4f s, %d steps, container v_y %.5f m/s (-g t = %.5f), water "
                  "speed relative to it up to %.2e m/s (g t = %.3f), bottom - top row pressure up "
                  "to %.2f Pa (rho g H = %.1f Pa)\n",
                  sim.time, k, vb[1], -g * sim.time, worstRelative, g * sim.time, worstDp, rho * g * H);
      EXPECT_NEAR(vb[1], -g * sim.time, 0.01 * g * sim.time);  // the container falls freely
    }
  }
  EXPECT_GT(sim.time, 0.1 - 1e-9);
  EXPECT_LT(worstRelative, 0.01 * g * sim.time);  // the water stays with the container
  EXPECT_LT(worstDp, 0.05 * rho * g * H);         // at uniform pressure (no hydrostatic field)
}
