// Rigid bodies (physics/rigid, docs/rigid.md), validation case 6 of issue 15: an isolated scene
// (no gravity, no walls) of water, an elastic block and a free rigid body. A droplet hits the
// body off-centre; the body turns and pushes the block. Every pair class (fluid-rigid through
// the shared fluid pair terms, rigid-solid through A.18, fluid-solid through the coupling) applies
// its pair force to both sides and the body update sums what its particles received, so the total
// linear momentum is conserved to round-off; the inviscid fluid's pair forces, A.18 and the mirror
// pressure pairs are central, so the angular momentum of fluid + body is as well.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

const char* kScene = R"(dimension: 2
domain: {lo: [-0.03, -0.03], hi: [0.04, 0.03]}
spacing: 0.001
kernel: wendland_c2
end_time: 1.0
time_step: {adaptive: true, cfl: 0.2}
output: {every_steps: 100000}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 40, viscosity: 0}
  - {name: block, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, formulation: total_lagrangian}
  - {name: grain, model: rigid, density: 2650}
geometry:
  - {shape: box, lo: [0.0, -0.01], hi: [0.01, 0.01], material: block}
  - {shape: box, lo: [-0.005, -0.004], hi: [0.0, 0.004], material: grain}
  - {shape: sphere, centre: [-0.011, 0.003], radius: 0.004, material: water, velocity: [1.0, 0]}
health: {domain_margin: 1.0}
)";

struct Momenta {
  Vec<2> p = Vec<2>::Zero();
  double L = 0.0;  // about the origin, all phases
};

Momenta momenta(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  Momenta out;
  for (Index i = 0; i < st.realCount(); ++i) {
    const double m = st.data(st.mass())[i];
    const Vec<2> x = st.vec<2>(st.position(), i), v = st.vec<2>(st.velocity(), i);
    out.p += m * v;
    const double l = m * (x[0] * v[1] - x[1] * v[0]);
    out.L += l;
  }
  return out;
}

}  // namespace

TEST(RigidMomentum, FluidElasticBlockAndFreeBodyConserveMomentum) {
  test::Stopwatch clock;
  Scene s = loadSceneText(kScene, "rigid_momentum.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_NE(rigid, nullptr);
  ASSERT_NE(sim.module("coupling"), nullptr);
  ASSERT_EQ(rigid->bodies().size(), 1u);
  auto integrator = makeIntegrator("leapfrog");
  const Momenta m0 = momenta(sim);
  double worstP = 0.0, worstL = 0.0;
  const int steps = 6000;
  for (int k = 1; k <= steps; ++k) {
    integrator->step(sim, s.nextTimeStep());
    if (k % 20 != 0) continue;
    const Momenta m = momenta(sim);
    worstP = std::max(worstP, (m.p - m0.p).norm() / m0.p.norm());
    worstL = std::max(worstL, std::abs(m.L - m0.L) / std::abs(m0.L));
  }
  const RigidBody& b = rigid->bodies()[0];
  const Vec<2> pBody(b.state.mass * b.state.V[0], b.state.mass * b.state.V[1]);
  std::printf("  %d steps to t = %.4f s: momentum drift %.2e, angular momentum drift %.2e; "
              "body took %.1f %% of the momentum, "
              "omega %.3f rad/s\n",
              steps, sim.time, worstP, worstL, 100.0 * pBody[0] / m0.p.norm(),
              b.state.omega().z());
  EXPECT_GT(pBody[0], 0.05 * m0.p.norm()) << "the droplet did not push the body";
  EXPECT_GT(std::abs(b.state.omega().z()), 0.05) << "the off-centre impact did not turn the body";
  EXPECT_LT(worstP, 1e-10);
  // The elastic block's Total-Lagrangian forces are not exactly central either; measured 2e-15
  // here (the test would show a module whose pairs break it).
  EXPECT_LT(worstL, 1e-10);
  test::recordValidation({"rigid_fluid_solid_momentum",
                          "relative drift of total linear momentum (water + elastic block + free body)",
                          worstP, 0.0, worstP, "2D, dx 1 mm, 50 fluid + 200 solid + 40 rigid particles, 6000 steps",
                          clock.seconds(), "< 1e-10", "conservation (action = reaction in every pair class)"});
  test::recordValidation({"rigid_fluid_solid_angular_momentum",
                          "relative drift of total angular momentum (water + elastic block + free body)",
                          worstL, 0.0, worstL, "2D, dx 1 mm, 50 fluid + 200 solid + 40 rigid particles, 6000 steps",
                          clock.seconds(), "< 1e-10", "conservation (central pair forces, exact body torque)"});
}
