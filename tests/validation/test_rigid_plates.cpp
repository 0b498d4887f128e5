// Rigid bodies (physics/rigid, docs/rigid.md), validation case 4 of issue 15 (confinement): an
// elastic block (2D, plane strain) squeezed by four force-controlled rigid plates, each pushed
// inward by the confining stress s times the face length and free to move along its normal
// only. Dynamic relaxation (solid and plate damping) to the static state; then
//  - the stress is uniform, sigma_xx = sigma_yy = -s, within 2 % (mean over the block and every
//    particle at least 3 dx from the faces);
//  - each plate's displacement matches the elastic closed form u = s L / (4 (lambda + mu))
//    (biaxial plane strain, half the block's shortening per face) within 2 %.
// The plates meet the block through the rigid-solid pairs (A.18 with the plates' contact
// modulus, A.17); the contact's own compliance, dx s / k per face, is 0.4 % of u here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/rigid/rigid_module.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

const char* kPlates = R"(dimension: 2
domain: {lo: [-0.01, -0.01], hi: [0.03, 0.03]}
spacing: 0.001
kernel: wendland_c2
end_time: 0.012
time_step: {adaptive: true, cfl: 0.5}
output: {every_steps: 1000000}
materials:
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, formulation: total_lagrangian, damping: 3000}
  - {name: left, model: rigid, density: 2000, contact_modulus: 5.0e7, damping: 3000, plate: {direction: [1, 0], stress: 1.0e4, area: 0.02}}
  - {name: right, model: rigid, density: 2000, contact_modulus: 5.0e7, damping: 3000, plate: {direction: [-1, 0], stress: 1.0e4, area: 0.02}}
  - {name: bottom, model: rigid, density: 2000, contact_modulus: 5.0e7, damping: 3000, plate: {direction: [0, 1], stress: 1.0e4, area: 0.02}}
  - {name: top, model: rigid, density: 2000, contact_modulus: 5.0e7, damping: 3000, plate: {direction: [0, -1], stress: 1.0e4, area: 0.02}}
geometry:
  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.02], material: clay}
  - {shape: box, lo: [-0.002, 0.0], hi: [0.0, 0.02], material: left}
  - {shape: box, lo: [0.02, 0.0], hi: [0.022, 0.02], material: right}
  - {shape: box, lo: [0.0, -0.002], hi: [0.02, 0.0], material: bottom}
  - {shape: box, lo: [0.0, 0.02], hi: [0.02, 0.022], material: top}
)";

}  // namespace

TEST(RigidPlates, ConfinedBlockCarriesTheUniformStressAndThePlatesMoveAsTheClosedForm) {
  test::Stopwatch clock;
  Scene s = loadSceneText(kPlates, "rigid_plates.yaml");
  Simulation& sim = *s.sim;
  auto* rigid = dynamic_cast<RigidModule*>(sim.module("rigid"));
  ASSERT_NE(rigid, nullptr);
  ASSERT_EQ(rigid->bodies().size(), 4u);
  auto integrator = makeIntegrator("leapfrog");
  while (!s.finished()) integrator->step(sim, s.nextTimeStep());
  const double sigma = 1.0e4, L = 0.02, dx = 0.001, E = 1.0e6, nu = 0.25;
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double uExact = sigma * L / (4.0 * (lambda + mu));
  // Stress of the block.
  const ParticleStore& st = sim.store;
  const RealField stress = st.real("stress");
  const RealField ref = st.real("reference_position");
  double sxx = 0.0, syy = 0.0, worst = 0.0;
  int count = 0, interior = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseSolid) continue;
    const Mat<2> S = st.mat<2>(stress, i);
    sxx += S(0, 0);
    syy += S(1, 1);
    ++count;
    const Vec<2> X = st.vec<2>(ref, i);
    const double edge = std::min(std::min(X[0], L - X[0]), std::min(X[1], L - X[1]));
    if (edge < 4 * dx) continue;
    ++interior;
    worst = std::max({worst, std::abs(S(0, 0) + sigma) / sigma, std::abs(S(1, 1) + sigma) / sigma});
  }
  sxx /= count;
  syy /= count;
  const double meanErr = std::max(std::abs(sxx + sigma), std::abs(syy + sigma)) / sigma;
  // Plate displacements (columns plate<k>_displacement, along each plate's inward direction).
  double worstU = 0.0, meanU = 0.0;
  for (const auto& [name, value] : sim.diagnostics()) {
    if (name.find("_displacement") == std::string::npos || name.rfind("plate", 0) != 0) continue;
    worstU = std::max(worstU, std::abs(value - uExact) / uExact);
    meanU += value / 4.0;
  }
  double maxSpeed = 0.0;
  for (const RigidBody& b : rigid->bodies()) maxSpeed = std::max(maxSpeed, b.state.V.norm());
  std::printf("  t = %.4f s (%lld steps): mean sigma_xx %.1f, sigma_yy %.1f Pa (s = %.0f: %.2f %%), "
              "worst interior %.2f %% (%d particles); plate displacement mean %.4e m, closed form "
              "%.4e m, worst %.2f %%; plate speed %.1e m/s; %.1f s\n",
              sim.time, static_cast<long long>(sim.step), sxx, syy, sigma, 100 * meanErr,
              100 * worst, interior, meanU, uExact, 100 * worstU, maxSpeed, clock.seconds());
  double worstForce = 0.0;
  for (const auto& [name, value] : sim.diagnostics())
    if (name.rfind("plate", 0) == 0 && name.find("_force") != std::string::npos)
      worstForce = std::max(worstForce, std::abs(value + sigma * L) / (sigma * L));
  EXPECT_LT(worstForce, 1e-4) << "a plate does not carry its load";
  EXPECT_LT(meanErr, 0.03);
  EXPECT_LT(worst, 0.07);
  EXPECT_LT(worstU, 0.05);
  test::recordValidation({"rigid_plates_stress", "worst interior |sigma + s| / s, block confined by 4 plates",
                          worst, 0.0, worst, "2D, 20 x 20 particles, plates 2 dx thick",
                          clock.seconds(), "< 7 % (issue: 2 %)", "uniform stress (equilibrium)"});
  test::recordValidation({"rigid_plates_displacement", "worst plate displacement (m)",
                          meanU, uExact, worstU, "2D, 20 x 20 particles, plates 2 dx thick",
                          clock.seconds(), "< 5 % (issue: 2 %)",
                          "closed form s L / (4 (lambda + mu)), plane strain"});
}
