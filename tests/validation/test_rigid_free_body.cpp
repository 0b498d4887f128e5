// Rigid bodies (physics/rigid, docs/rigid.md), validation case 1 of issue 15: a free asymmetric
// body (a 4 x 3 x 2 block of particles, three distinct principal moments) with no torque.
//  - angular momentum (sum m x x v over the particles) and kinetic energy (sum 1/2 m v^2) are
//    conserved to 1e-8 relative over 1e5 steps of the scene's integrator + the body update;
//  - started about the intermediate axis with a small perturbation, the body flips (tennis-racket
//    / Dzhanibekov effect) with the half period of Jacobi's closed form (rigid_body.hpp,
//    Landau & Lifshitz Sec. 37) within 5 %.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "libcore/integrator.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using rigid::V3;

namespace {

const char* kBlock = R"(dimension: 3
domain: {lo: [-10, -10, -10], hi: [10, 10, 10]}
spacing: 1.0
end_time: 1000
time_step: {dt: 1.0e-3}
output: {every_steps: 1000000}
materials:
  - {name: grain, model: rigid, density: 2650}
geometry:
  - {shape: box, lo: [-2, -1, -1], hi: [2, 2, 1], material: grain}
)";

V3 particleAngularMomentum(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  V3 L = V3::Zero();
  for (Index i = 0; i < st.realCount(); ++i) {
    V3 x, v;
    for (int a = 0; a < 3; ++a) {
      x[a] = st.data(st.position())[3 * i + a];
      v[a] = st.data(st.velocity())[3 * i + a];
    }
    L += st.data(st.mass())[i] * x.cross(v);
  }
  return L;
}

struct FreeBody {
  Scene scene;
  RigidModule* rigid = nullptr;
  std::unique_ptr<Integrator> integrator;
};

FreeBody makeBody(const V3& omegaBody, const std::string& integrator) {
  FreeBody f{loadSceneText(kBlock, "free_body.yaml"), nullptr, makeIntegrator(integrator)};
  Simulation& sim = *f.scene.sim;
  f.rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  EXPECT_NE(f.rigid, nullptr);
  EXPECT_EQ(f.rigid->bodies().size(), 1u);
  const rigid::BodyState& s = f.rigid->bodies()[0].state;
  f.rigid->setBodyVelocity(sim, 0, V3::Zero(), s.R() * omegaBody);
  return f;
}

}  // namespace

TEST(RigidFreeBody, ConservesAngularMomentumAndEnergy) {
  for (const std::string scheme : {"leapfrog", "verlet"}) {
    test::Stopwatch clock;
    FreeBody f = makeBody(V3(0.3, 1.0, 0.5), scheme);
    Simulation& sim = *f.scene.sim;
    const V3 L0 = particleAngularMomentum(sim);
    const double E0 = sim.kineticEnergy();
    ASSERT_GT(E0, 0.0);
    double worstL = 0.0, worstE = 0.0;
    const int steps = 100000;
    for (int k = 1; k <= steps; ++k) {
      f.integrator->step(sim, 1.0e-3);
      if (k % 500 != 0) continue;
      worstL = std::max(worstL, (particleAngularMomentum(sim) - L0).norm() / L0.norm());
      worstE = std::max(worstE, std::abs(sim.kineticEnergy() - E0) / E0);
    }
    const V3 w = f.rigid->bodies()[0].state.omega();
    std::printf("  %s: %d steps (%.0f rad turned), |L| drift %.2e, energy drift %.2e, %.2f s\n",
                scheme.c_str(), steps, w.norm() * sim.time, worstL, worstE, clock.seconds());
    EXPECT_LT(worstL, 1e-8);
    EXPECT_LT(worstE, 1e-8);
    EXPECT_NEAR(sim.time, 100.0, 1e-6);
    if (scheme == "leapfrog") {
      test::recordValidation({"rigid_free_body_angular_momentum",
                              "relative drift of angular momentum, free asymmetric body",
                              worstL, 0.0, worstL, "24 particles (4 x 3 x 2), omega dt = 1.2e-3, 1e5 steps",
                              clock.seconds(), "< 1e-8", "conservation (Euler's equations)"});
      test::recordValidation({"rigid_free_body_energy",
                              "relative drift of kinetic energy, free asymmetric body", worstE, 0.0,
                              worstE, "24 particles (4 x 3 x 2), omega dt = 1.2e-3, 1e5 steps",
                              clock.seconds(), "< 1e-8", "conservation (Euler's equations)"});
    }
  }
}

TEST(RigidFreeBody, IntermediateAxisFlipsWithTheClosedFormPeriod) {
  test::Stopwatch clock;
  // Spin about the intermediate principal axis (Ib sorted ascending: axis 1), perturbed.
  FreeBody f = makeBody(V3(0.01, 3.0, 0.0), "leapfrog");
  Simulation& sim = *f.scene.sim;
  const rigid::BodyState& s0 = f.rigid->bodies()[0].state;
  const V3 I = s0.Ib;
  ASSERT_LT(I[0], I[1]);
  ASSERT_LT(I[1], I[2]);
  const double L2 = s0.L.squaredNorm(), E2 = 2.0 * s0.rotationalEnergy();
  const double reference = rigid::flipHalfPeriod(I[0], I[1], I[2], L2, E2);
  std::vector<double> flips;
  auto w2 = [&] {
    const rigid::BodyState& s = f.rigid->bodies()[0].state;
    return (s.R().transpose() * s.omega())[1];
  };
  double prev = w2();
  const int steps = 100000;
  for (int k = 1; k <= steps; ++k) {
    const double t0 = sim.time;
    f.integrator->step(sim, 1.0e-3);
    const double now = w2();
    if ((now > 0.0) != (prev > 0.0))  // linear interpolation of the crossing
      flips.push_back(t0 + 1.0e-3 * prev / (prev - now));
    prev = now;
  }
  ASSERT_GE(flips.size(), 3u) << "the body did not flip (reference half period " << reference
                              << " s over " << sim.time << " s)";
  const double measured = (flips.back() - flips.front()) / static_cast<double>(flips.size() - 1);
  const double err = std::abs(measured - reference) / reference;
  std::printf("  %zu flips in %.0f s: half period %.4f s, closed form %.4f s (%.2e)\n",
              flips.size(), sim.time, measured, reference, err);
  EXPECT_LT(err, 0.05);
  test::recordValidation({"rigid_tennis_racket", "half period of the intermediate-axis flip (s)",
                          measured, reference, err,
                          "24 particles (4 x 3 x 2), omega dt = 3e-3, 1e5 steps",
                          clock.seconds(), "< 5 %",
                          "Jacobi elliptic closed form (Landau & Lifshitz, Mechanics Sec. 37)"});
}
