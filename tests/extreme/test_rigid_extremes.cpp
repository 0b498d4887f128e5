// Rigid bodies (physics/rigid, docs/rigid.md), extremes of issue 15:
//  - two bodies in sustained contact: a heavy box dropped on another on a wall floor under
//    gravity (rigid-rigid and rigid-wall repulsion, A.18) comes to rest stacked, without
//    interpenetration, the floor carrying both weights. (The contacts store the impact energy
//    elastically and ring at their own frequency, ~2.5e4 rad/s; with a body damping of 30 /s the
//    boxes still bounce and rock at ~1e-2 m/s after 0.3 s; 300 /s brings them to rest.)
//  - a grain 10 times denser than the clay with a contact modulus 1e3 times the clay's bulk
//    modulus resting on an elastic block: stable, no penetration;
//  - a body crossing a periodic face keeps its shape and momentum;
//  (1000 bodies in one scene: test_rigid_many_grains.cpp, in a fluid, and test_rigid_many_bodies_long.cpp.)
#include <gtest/gtest.h>

#include <omp.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"

using namespace poresph;

namespace {

/// Smallest distance between particles of different bodies (or a body and another phase).
double minGap(const Simulation& sim, bool withOtherPhases) {
  const ParticleStore& st = sim.store;
  const std::int32_t* body = st.data(st.integer("body"));
  const std::int32_t* ph = st.data(st.phase());
  const double* x = st.data(st.position());
  const int d = sim.dimension();
  double gap = 1e300;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (body[i] < 0) continue;
    for (Index j = 0; j < st.realCount(); ++j) {
      if (body[j] == body[i]) continue;
      if (body[j] < 0 && (!withOtherPhases || ph[j] == kPhaseFluid)) continue;
      double r2 = 0.0;
      for (int a = 0; a < d; ++a) r2 += (x[i * d + a] - x[j * d + a]) * (x[i * d + a] - x[j * d + a]);
      gap = std::min(gap, std::sqrt(r2));
    }
  }
  return gap;
}

}  // namespace

TEST(RigidExtremes, TwoBodiesInSustainedContactComeToRestStacked) {
  const char* scene = R"(dimension: 2
domain: {lo: [-0.004, -0.004], hi: [0.024, 0.04]}
spacing: 0.001
end_time: 0.3
time_step: {adaptive: true, cfl: 0.5}
output: {every_steps: 1000000}
materials:
  - {name: floor, model: wall, density: 2000}
  - {name: lower, model: rigid, density: 2650, contact_modulus: 1.0e7, damping: 300}
  - {name: upper, model: rigid, density: 8000, contact_modulus: 1.0e7, damping: 300}
geometry:
  - {shape: box, lo: [-0.004, -0.004], hi: [0.024, 0.0], material: floor}
  - {shape: box, lo: [0.005, 0.001], hi: [0.015, 0.007], material: lower}
  - {shape: box, lo: [0.007, 0.009], hi: [0.013, 0.015], material: upper}
rigid: {gravity: [0, -9.81]}
health: {domain_margin: 1.0}
)";
  Scene s = loadSceneText(scene, "stack.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_EQ(rigid->bodies().size(), 2u);
  auto integrator = makeIntegrator(std::getenv("RIGID_INT") ? std::getenv("RIGID_INT") : "leapfrog");
  double gapMin = 1e300;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.step % 200 == 0) gapMin = std::min(gapMin, minGap(sim, true));
    if (std::getenv("RIGID_TRACE") && sim.step % 2000 == 0)
      std::printf("    t %.3f V0 (%.2e %.2e) V1 (%.2e %.2e) w %.2e %.2e F %.3f %.3f\n", sim.time,
                  rigid->bodies()[0].state.V[0], rigid->bodies()[0].state.V[1],
                  rigid->bodies()[1].state.V[0], rigid->bodies()[1].state.V[1],
                  rigid->bodies()[0].state.omega()[2], rigid->bodies()[1].state.omega()[2],
                  rigid->bodies()[0].force[1], rigid->bodies()[1].force[1]);
  }
  const auto& b = rigid->bodies();
  const double weight = (b[0].state.mass + b[1].state.mass) * 9.81;
  std::printf("  after %.2f s (%lld steps): speeds %.2e, %.2e m/s; closest approach %.3f dx; "
              "lower box y %.5f, upper %.5f\n",
              sim.time, static_cast<long long>(sim.step), b[0].state.V.norm(),
              b[1].state.V.norm(), gapMin / sim.spacing, b[0].state.X[1], b[1].state.X[1]);
  std::printf("  weight of the stack %.3f N/m\n", weight);
  EXPECT_LT(b[0].state.V.norm(), 1e-6);
  EXPECT_LT(b[1].state.V.norm(), 1e-6);
  // At rest the floor carries both weights: the net force on each box (gravity included) is 0.
  EXPECT_NEAR(b[0].force[1], 0.0, 1e-4 * weight);
  EXPECT_NEAR(b[1].force[1], 0.0, 1e-4 * weight);
  EXPECT_GT(gapMin, 0.5 * sim.spacing) << "bodies interpenetrate";
  EXPECT_GT(b[1].state.X[1], b[0].state.X[1] + 0.005) << "the upper box fell through";
  EXPECT_GT(b[0].state.X[1], 0.002) << "the lower box went through the floor";
}

TEST(RigidExtremes, DenseStiffGrainOnAnElasticBlockIsStable) {
  const char* scene = R"(dimension: 2
domain: {lo: [-0.01, -0.01], hi: [0.03, 0.03]}
spacing: 0.001
kernel: wendland_c2
end_time: 0.004
time_step: {adaptive: true, cfl: 0.5}
output: {every_steps: 1000000}
materials:
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, formulation: total_lagrangian, damping: 2000}
  - {name: grain, model: rigid, density: 20000, contact_modulus: 1.2e9, damping: 200}
geometry:
  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.01], material: clay, motion: fixed}
  - {shape: box, lo: [0.0, 0.003], hi: [0.02, 0.01], material: clay}
  - {shape: box, lo: [0.007, 0.010], hi: [0.013, 0.016], material: grain}
rigid: {gravity: [0, -98.1]}
health: {domain_margin: 1.0}
)";
  Scene s = loadSceneText(scene, "dense_grain.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_EQ(rigid->bodies().size(), 1u);
  auto integrator = makeIntegrator("leapfrog");
  double gapMin = 1e300;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.step % 100 == 0) gapMin = std::min(gapMin, minGap(sim, true));
  }
  const RigidBody& b = rigid->bodies()[0];
  std::printf("  after %.4f s (%lld steps, dt %.2e s): grain speed %.2e m/s, y %.5f m, closest "
              "approach %.3f dx, force %.3f N/m vs weight %.3f N/m\n",
              sim.time, static_cast<long long>(sim.step), sim.dt, b.state.V.norm(), b.state.X[1],
              gapMin / sim.spacing, b.force[1], b.state.mass * 98.1);
  EXPECT_TRUE(std::isfinite(b.state.X[1]));
  EXPECT_GT(gapMin, 0.5 * sim.spacing) << "the grain penetrates the clay";
  EXPECT_GT(b.state.X[1], 0.0125) << "the grain sank into the clay";
  EXPECT_LT(b.state.V.norm(), 0.1);
}

TEST(RigidExtremes, BodyCrossesAPeriodicFaceKeepingItsShape) {
  const char* scene = R"(dimension: 2
domain: {lo: [0, 0], hi: [0.02, 0.02], periodic: [true, true]}
spacing: 0.001
end_time: 0.02
time_step: {dt: 1.0e-4}
output: {every_steps: 1000000}
materials:
  - {name: grain, model: rigid, density: 2650, angular_velocity: [30]}
geometry:
  - {shape: box, lo: [0.014, 0.007], hi: [0.02, 0.012], material: grain, velocity: [1.0, 0.3]}
)";
  Scene s = loadSceneText(scene, "periodic.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_EQ(rigid->bodies().size(), 1u);
  auto integrator = makeIntegrator("verlet");
  const ParticleStore& st = sim.store;
  // Pairwise distances by particle id before and after (the shape of a rigid body).
  auto distances = [&] {
    std::vector<std::pair<std::int32_t, Vec<2>>> p;
    for (Index i = 0; i < st.realCount(); ++i)
      p.emplace_back(st.data(st.id())[i], st.vec<2>(st.position(), i));
    std::sort(p.begin(), p.end(), [](auto& a, auto& b) { return a.first < b.first; });
    std::vector<double> d;
    for (size_t a = 0; a < p.size(); ++a)
      for (size_t b = a + 1; b < p.size(); ++b) {
        Vec<2> r = p[a].second - p[b].second;
        for (int c = 0; c < 2; ++c) r[c] -= 0.02 * std::round(r[c] / 0.02);  // minimal image
        d.push_back(r.norm());
      }
    return d;
  };
  const std::vector<double> d0 = distances();
  const double E0 = sim.kineticEnergy();
  while (!s.finished()) integrator->step(sim, s.nextTimeStep());
  const std::vector<double> d1 = distances();
  double worst = 0.0;
  for (size_t k = 0; k < d0.size(); ++k) worst = std::max(worst, std::abs(d1[k] - d0[k]));
  const RigidBody& b = rigid->bodies()[0];
  std::printf("  crossed to x = %.4f (unwrapped), shape change %.2e m, energy drift %.2e\n",
              b.state.X[0], worst, std::abs(sim.kineticEnergy() - E0) / E0);
  EXPECT_GT(b.state.X[0], 0.03) << "the body did not cross the periodic face";
  EXPECT_LT(worst, 1e-12);
  EXPECT_NEAR(sim.kineticEnergy(), E0, 1e-10 * E0);
  for (Index i = 0; i < st.realCount(); ++i)
    for (int c = 0; c < 2; ++c) {
      EXPECT_GE(st.vec<2>(st.position(), i)[c], 0.0);
      EXPECT_LT(st.vec<2>(st.position(), i)[c], 0.02);
    }
}

// A body that starts across a periodic face (two boxes of one material meeting through the face
// x = 0 / 0.02) is one body with the inertia of the same box in one piece (clusters linked and
// centre of mass found by the minimal image), and moves and spins keeping its shape.
TEST(RigidExtremes, BodyStartingAcrossAPeriodicFaceIsOneBody) {
  auto scene = [](const char* boxes) {
    return std::string(R"(dimension: 2
domain: {lo: [0, 0], hi: [0.02, 0.02], periodic: [true, true]}
spacing: 0.001
end_time: 0.01
time_step: {dt: 1.0e-4}
output: {every_steps: 1000000}
materials:
  - {name: grain, model: rigid, density: 2650, angular_velocity: [30]}
geometry:
)") + boxes;
  };
  Scene split = loadSceneText(
      scene("  - {shape: box, lo: [0.016, 0.007], hi: [0.02, 0.012], material: grain, velocity: [1.0, 0.3]}\n"
            "  - {shape: box, lo: [0.0, 0.007], hi: [0.004, 0.012], material: grain, velocity: [1.0, 0.3]}\n"),
      "split.yaml");
  Scene whole = loadSceneText(
      scene("  - {shape: box, lo: [0.006, 0.007], hi: [0.014, 0.012], material: grain, velocity: [1.0, 0.3]}\n"),
      "whole.yaml");
  auto* rs = dynamic_cast<RigidModule*>(split.sim->module("rigid"));
  auto* rw = dynamic_cast<RigidModule*>(whole.sim->module("rigid"));
  ASSERT_EQ(rs->bodies().size(), 1u) << "the body across the face was split";
  ASSERT_EQ(rw->bodies().size(), 1u);
  const RigidBody& a = rs->bodies()[0];
  const RigidBody& b = rw->bodies()[0];
  EXPECT_EQ(a.count, 40);
  EXPECT_NEAR(a.state.Ib[2], b.state.Ib[2], 1e-12 * b.state.Ib[2]);
  // centre on the face (minimal image): x = 0 or 0.02 up to round-off
  EXPECT_NEAR(std::abs(a.state.X[0] - 0.01), 0.01, 1e-12);
  EXPECT_NEAR(a.state.L[2], b.state.L[2], 1e-12 * std::abs(b.state.L[2]));
  auto is = makeIntegrator("verlet"), iw = makeIntegrator("verlet");
  while (!split.finished()) is->step(*split.sim, split.nextTimeStep());
  while (!whole.finished()) iw->step(*whole.sim, whole.nextTimeStep());
  // the same motion: velocities, spin and the displacement of the centre agree
  EXPECT_NEAR((a.state.X - a.X0 - (b.state.X - b.X0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(a.state.omega()[2], b.state.omega()[2], 1e-9);
  std::printf("  split body: %lld particles, I %.6e vs %.6e, centre moved %.6f / %.6f m\n",
              static_cast<long long>(a.count), a.state.Ib[2], b.state.Ib[2],
              (a.state.X - a.X0).norm(), (b.state.X - b.X0).norm());
}
