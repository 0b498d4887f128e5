// Rigid bodies (physics/rigid, docs/rigid.md), extreme of issue 15: 1e3 bodies in one scene.
// 1000 free grains (2 x 2 particles, dx = 1 mm; 40 columns x 25 rows, one particle apart) fall
// under 10 g into a wall box and settle into a pile (body damping 300 1/s, as the two-box stack of
// test_rigid_extremes.cpp; 50 1/s leaves the pile ringing at 0.08 s: kinetic energy 2.8 % of the
// energy released, net force 23 % of the weight): rigid-rigid and rigid-wall contacts (A.18)
// between ~1000 bodies at once. Asserted: every body stays finite and inside the box, no two
// bodies closer than 0.5 dx (no interpenetration), the pile settling at 0.12 s (kinetic energy
// < 1 % of the potential energy released, 0.34 % measured) with the floor carrying its weight
// (sum of the net forces on the bodies < 20 % of the weight, 7.8 % measured; not yet at rest). Reported (not asserted, timings of a loaded machine): CPU per step and body
// of the whole step and of the rigid module's body stages (reduction + Newton-Euler update +
// placement) against the rest of the step (neighbour search and the pair loops).
// Label extreme_long (tests/long-tests.txt): ~45,000 steps of 5,192 particles (RIGID_MANY_END: a
// shorter run, s).
#include <gtest/gtest.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <sstream>
#include <limits>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/extreme/rigid_many_bodies_case.hpp"

using namespace poresph;

TEST(RigidManyBodies, ThousandGrainsSettleIntoAPileInAWallBox) {
  const double g = 98.1, dx = 1e-3;
  std::ostringstream y;
  y << "dimension: 2\ndomain: {lo: [-0.005, -0.005], hi: [0.125, 0.09]}\n"
       "spacing: 0.001\nend_time: " << (std::getenv("RIGID_MANY_END") ? std::getenv("RIGID_MANY_END") : "0.12")
    << "\ntime_step: {adaptive: true, cfl: 0.5}\n"
       "output: {every_steps: 100000000}\n"
       "materials:\n  - {name: wall, model: wall, density: 2650}\n"
       "  - {name: grain, model: rigid, density: 2650, contact_modulus: 1.0e7, damping: 300}\n"
       "geometry:\n"
       "  - {shape: box, lo: [-0.004, -0.004], hi: [0.124, 0.0], material: wall}\n"
       "  - {shape: box, lo: [-0.004, 0.0], hi: [0.0, 0.085], material: wall}\n"
       "  - {shape: box, lo: [0.12, 0.0], hi: [0.124, 0.085], material: wall}\n";
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 25; ++j)  // pitch 3 mm (2 particles + a one-particle gap: separate bodies);
                                  // rows shifted by 1 mm every other row
      y << "  - {shape: box, lo: [" << 0.003 * i + 0.001 * (j % 2) << ", " << 0.001 + 0.003 * j
        << "], hi: [" << 0.003 * i + 0.002 + 0.001 * (j % 2) << ", " << 0.003 + 0.003 * j
        << "], material: grain}\n";
  y << "rigid: {gravity: [0, " << -g << "]}\n";
  Scene s = loadSceneText(y.str(), "many_bodies.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_NE(rigid, nullptr);
  ASSERT_EQ(rigid->bodies().size(), 1000u);
  const auto& bodies = rigid->bodies();
  double mass = 0.0, y0 = 0.0;
  for (const RigidBody& b : bodies) {
    mass += b.state.mass;
    y0 += b.state.mass * b.state.X[1];
  }
  auto integrator = makeIntegrator("leapfrog");
  double gapMin = 1e300, tBody = 0.0;
  const double c0 = static_cast<double>(std::clock());
  long steps = 0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    ++steps;
    if (steps % 500 == 0) gapMin = std::min(gapMin, test::minBodyGap2D(sim));
  }
  const double cpu = (static_cast<double>(std::clock()) - c0) / CLOCKS_PER_SEC;
  gapMin = std::min(gapMin, test::minBodyGap2D(sim));
  double ke = 0.0, y1 = 0.0, fy = 0.0, xmin = 1e300, xmax = -1e300, ymin = 1e300;
  bool finite = true;
  for (const RigidBody& b : bodies) {
    ke += 0.5 * b.state.mass * b.state.V.squaredNorm() + b.state.rotationalEnergy();
    y1 += b.state.mass * b.state.X[1];
    fy += b.force[1];
    xmin = std::min(xmin, b.state.X[0]);
    xmax = std::max(xmax, b.state.X[0]);
    ymin = std::min(ymin, b.state.X[1]);
    finite = finite && std::isfinite(b.state.X[0]) && std::isfinite(b.state.X[1]);
  }
  const double released = g * (y0 - y1), weight = mass * g;
  const double perBodyStep = 1e6 * cpu / static_cast<double>(steps) / 1000.0;
  // The body stages on their own, timed on the settled pile after the state above was taken:
  // constraints() (the reduction of the last evaluation's accelerations, which already hold the
  // rigid ones and gravity: it would count gravity twice, so the run's physics stops here) and
  // the Newton-Euler update and placement with dt = 0 (no motion).
  const int timed = 300;
  for (int k = 0; k < timed; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    rigid->constraints(sim);
    rigid->endOfStep(sim, 0.0);
    tBody += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const double bodyStages = 1e6 * tBody / timed / 1000.0;
  std::printf("  1000 grains (%lld particles), %ld steps to t = %.3f s: centre of mass fell %.2f mm, kinetic "
              "energy %.2e of the %.3e J/m released, net force on the bodies %.2e of the weight; closest "
              "approach of two bodies %.3f dx; bodies x in [%.4f, %.4f], lowest y %.4f m\n",
              static_cast<long long>(sim.store.realCount()), steps, sim.time, 1e3 * (y0 - y1) / mass,
              ke / released, released, std::abs(fy) / weight, gapMin / dx, xmin, xmax, ymin);
  std::printf("  cost: %.2f us CPU per step and body for the whole step; body stages (reduction, "
              "Newton-Euler update, placement) %.3f us per step and body (wall, %d thread%s; loaded "
              "machine)\n",
              perBodyStep, bodyStages, omp_get_max_threads(), omp_get_max_threads() == 1 ? "" : "s");
  EXPECT_TRUE(finite);
  EXPECT_GT(released, 0.0) << "the grains did not fall";
  // settling, not rest: measured at 0.12 s 3.4e-3 and 7.8 % (the A.18 contacts ring, with no
  // dissipation of their own; at 0.08 s with damping 50 1/s 2.8e-2 and 23 %); while falling the
  // ratios are ~1
  EXPECT_LT(ke, 1e-2 * released) << "the pile is not settling";
  EXPECT_LT(std::abs(fy), 0.2 * weight) << "the floor does not carry the pile's weight";
  EXPECT_GT(gapMin, 0.5 * dx) << "bodies interpenetrate";
  EXPECT_GT(xmin, 0.0);
  EXPECT_LT(xmax, 0.12);
  EXPECT_GT(ymin, 0.0) << "a grain went through the floor";
}
