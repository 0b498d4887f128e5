// Two-way fluid-solid coupling (physics/coupling, docs/coupling.md), validation cases of issue 11:
//  1. an isolated droplet hitting a free elastic block (no gravity, no walls): total linear
//     momentum conserved to round-off (pair forces applied to both sides), total energy
//     (kinetic + fluid compression + elastic) to 1 %;
//  3. a pressurised pore: a circular cavity in an elastic ring filled with water whose pressure
//     is its EOS' background pressure; the ring's radial displacement and hoop stress at the
//     bore against Lame (plane strain) at the fluid pressure reached, body-fitted rings and the
//     voxel lattice (staircase bore).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <sstream>
#include <vector>

#include "libcore/fluid_pair_terms.hpp"
#include "libcore/integrator.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/solid/solid_scenes.hpp"
#include "physics/solid/wall_stress.hpp"
#include "tests/support/pair_class_powers.hpp"
#include "tests/support/validation_record.hpp"
#include "tests/validation/coupling_pore_case.hpp"

using namespace poresph;
using poresph::pore::PoreResult;
using poresph::pore::runPressurisedPore;

namespace {

double column(const Simulation& sim, const std::string& name) {
  for (const auto& [k, v] : sim.diagnostics())
    if (k == name) return v;
  ADD_FAILURE() << "no column " << name;
  return 0.0;
}

Vec<2> momentum(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  Vec<2> p = Vec<2>::Zero();
  const std::int32_t* mo = st.data(sim.motion);
  for (Index i = 0; i < st.realCount(); ++i) {
    if (mo[i] == kMotionFixed) continue;
    p += st.data(st.mass())[i] * st.vec<2>(st.velocity(), i);
  }
  return p;
}

double totalEnergy(const Simulation& sim) {
  return column(sim, "kinetic_energy") + column(sim, "fluid_internal_energy") +
         column(sim, "solid_elastic_energy");
}

const char* kDroplet = R"(dimension: 2
domain: {lo: [-0.02, -0.02], hi: [0.04, 0.02]}
spacing: 0.001
kernel: wendland_c2
end_time: 1.0
time_step: {adaptive: true, cfl: 0.2}
output: {every_steps: 1000}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 0}
  - {name: block, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, formulation: total_lagrangian}
geometry:
  - {shape: box, lo: [0.0, -0.01], hi: [0.01, 0.01], material: block}
  - {shape: sphere, centre: [-0.006, 0], radius: 0.004, material: water, velocity: [1.0, 0]}
fluid: {continuity_form: mass, pressure_gradient: symmetric}
)";

// The droplet scene with the fluid section `fluidSection` ("" = none), the block as in kDroplet
// or (twoDrops) a second droplet coming the other way instead of the block (fluid only), at cfl.
std::string dropletText(const std::string& fluidSection, bool twoDrops, double cfl) {
  std::string t = kDroplet;
  t.replace(t.find("cfl: 0.2"), 8, "cfl: " + std::to_string(cfl));
  if (twoDrops) {
    t.replace(t.find("  - {name: block"), t.find("geometry:") - t.find("  - {name: block"), "");
    const auto b = t.find("  - {shape: box");
    t.replace(b, t.find('\n', b) + 1 - b,
              "  - {shape: sphere, centre: [0.006, 0], radius: 0.004, material: water, velocity: "
              "[-1.0, 0]}\n");
  }
  const auto f = t.find("fluid: {");
  t.replace(f, t.find('\n', f) + 1 - f, fluidSection.empty() ? "" : "fluid: " + fluidSection + "\n");
  return t;
}

struct EnergyRun {
  double worst = 0.0, last = 0.0, time = 0.0;
  double momentum = 0.0;  ///< worst |P - P0| / sum m |v| at the start, sampled every 100 steps
  int steps = 0;
};

// Steps the scene `text` with leapfrog; worst and last |E - E0| / E0 of kinetic + compression +
// elastic energy, sampled every step.
EnergyRun energyDrift(const std::string& text, int steps) {
  Scene s = loadSceneText(text, "droplet.yaml");
  Simulation& sim = *s.sim;
  auto integrator = makeIntegrator("leapfrog");
  auto total = [&] {
    double e = 0.0;
    for (const auto& [k, v] : sim.diagnostics())
      if (k == "kinetic_energy" || k == "fluid_internal_energy" || k == "solid_elastic_energy")
        e += v;
    return e;
  };
  const double e0 = total();
  const Vec<2> p0 = momentum(sim);
  double pScale = 0.0;
  {
    const ParticleStore& st = sim.store;
    for (Index i = 0; i < st.realCount(); ++i)
      pScale += st.data(st.mass())[i] * st.vec<2>(st.velocity(), i).norm();
  }
  EnergyRun r;
  for (int k = 1; k <= steps; ++k) {
    integrator->step(sim, s.nextTimeStep());
    r.last = (total() - e0) / e0;
    r.worst = std::max(r.worst, std::abs(r.last));
    if (k % 100 == 0) r.momentum = std::max(r.momentum, (momentum(sim) - p0).norm() / pScale);
  }
  r.time = sim.time;
  r.steps = steps;
  return r;
}

}  // namespace

// The drift of the droplet tests against the fluid's continuity form and the step (docs/fluid.md
// "Energy-consistent continuity"): block and two droplets, volume (Eq. 5.1a) and mass form with
// Eq. 5.2b, and Eq. 5.2a with 5.1a (pressure_gradient: volume), cfl 0.2 / 0.1 / 0.05 over the
// same simulated time. PORESPH_ENERGY_STUDY=1.
TEST(CouplingMomentum, ExploreContinuityForm) {
  if (!std::getenv("PORESPH_ENERGY_STUDY")) GTEST_SKIP() << "set PORESPH_ENERGY_STUDY=1";
  const int steps0 = std::getenv("PORESPH_STEPS") ? std::atoi(std::getenv("PORESPH_STEPS")) : 10000;
  for (bool two : {false, true})
    for (const char* form : {"{continuity_form: volume, pressure_gradient: symmetric}",
                             "{continuity_form: mass, pressure_gradient: symmetric}",
                             "{pressure_gradient: volume}"})
      for (double cfl : {0.2, 0.1, 0.05}) {
        test::Stopwatch clock;
        const int steps = static_cast<int>(steps0 * 0.2 / cfl);
        const EnergyRun r = energyDrift(dropletText(form, two, cfl), steps);
        std::printf("%s %-55s cfl %.2f: %6d steps to t %.5f: worst drift %.3e, last %+.3e, "
                    "momentum %.2e (%.1f s)\n",
                    two ? "two drops" : "block    ", form, cfl, r.steps, r.time, r.worst, r.last,
                    r.momentum, clock.seconds());
        std::fflush(stdout);
      }
}

// The power balance of the droplet on the free block per pair class (issue 11 item 1): after
// every step the rates are re-evaluated on the synchronised state, module by module (the store's
// rates put back afterwards), and the power that each class's pair forces put into the kinetic
// energy is added to the rate of the compression energy sum m e(rho) (de/drho = p / rho^2) that
// its continuity terms give, then integrated (trapezoid) and printed as a fraction of E0:
//   fluid-fluid  sum_fluid m (v . a + p/rho^2 drho/dt) of the fluid module's stage,
//   fluid-solid  the coupling's stage: the power on the fluid side, on the solid side, and the
//                compression rate of its continuity terms (a conservative pair sums to zero).
// PORESPH_PAIR_POWER=1; PORESPH_FLUID_SECTION sets the fluid section (default: none = the fluid's
// defaults, Eq. 5.1a with Eq. 5.2a; '{pressure_gradient: symmetric}' for Eq. 5.2b).
TEST(CouplingMomentum, ExplorePowerByPairClass) {
  if (!std::getenv("PORESPH_PAIR_POWER")) GTEST_SKIP() << "set PORESPH_PAIR_POWER=1";
  const char* section = std::getenv("PORESPH_FLUID_SECTION");
  const double cfl = std::getenv("PORESPH_CFL") ? std::atof(std::getenv("PORESPH_CFL")) : 0.2;
  const int steps = std::getenv("PORESPH_STEPS") ? std::atoi(std::getenv("PORESPH_STEPS")) : 10000;
  Scene s = loadSceneText(dropletText(section ? section : "", false, cfl), "droplet_block.yaml");
  Simulation& sim = *s.sim;
  auto integrator = makeIntegrator("leapfrog");
  Module* fluid = sim.module("fluid");
  Module* coupling = sim.module("coupling");
  ASSERT_NE(fluid, nullptr);
  ASSERT_NE(coupling, nullptr);
  // Powers of one evaluation: {ff kinetic, ff compression, fs on fluid, fs on solid, fs compression}
  auto powers = [&] { return test::pairClassPowers2D(sim, fluid, coupling); };
  const double e0 = totalEnergy(sim);
  std::array<double, 5> P0 = powers(), W{0, 0, 0, 0, 0};
  for (int k = 1; k <= steps; ++k) {
    const double dt = s.nextTimeStep();
    integrator->step(sim, dt);
    const std::array<double, 5> P1 = powers();
    for (int c = 0; c < 5; ++c) W[c] += 0.5 * dt * (P0[c] + P1[c]);
    P0 = P1;
    if (k % (steps / 20) != 0) continue;
    std::printf("t %.5f drift %+.3e | fluid-fluid: kinetic %+.3e compression %+.3e sum %+.3e | "
                "fluid-solid: on fluid %+.3e on solid %+.3e compression %+.3e sum %+.3e\n",
                sim.time, (totalEnergy(sim) - e0) / e0, W[0] / e0, W[1] / e0, (W[0] + W[1]) / e0,
                W[2] / e0, W[3] / e0, W[4] / e0, (W[2] + W[3] + W[4]) / e0);
    std::fflush(stdout);
  }
}

// Fluid only: two droplets of kDroplet's water colliding head-on (no solid, no walls), 1e4 steps
// at cfl 0.2. With continuity_form: mass the kinetic + compression energy drifts 4.1e-3 (3.2e-4 /
// 6.4e-5 at cfl 0.1 / 0.05); with Eq. 5.1a 3.3 % (2.3 / 2.7 %, not a time-step error).
TEST(CouplingMomentum, TwoDropletsConserveEnergyWithTheMassContinuity) {
  test::Stopwatch clock;
  const EnergyRun mass = energyDrift(dropletText("{continuity_form: mass, pressure_gradient: symmetric}", true, 0.2), 10000);
  const EnergyRun volume = energyDrift(dropletText("{continuity_form: volume, pressure_gradient: symmetric}", true, 0.2), 10000);
  std::printf("  two droplets, 1e4 steps to t = %.4f s: worst energy drift %.3e (mass), %.3e "
              "(Eq. 5.1a)\n", mass.time, mass.worst, volume.worst);
  EXPECT_LT(mass.worst, 0.01);
  EXPECT_GT(volume.worst, 0.01);  // the option is what closes the balance
  test::recordValidation({"fluid_two_droplets_energy", "relative drift of total energy",
                          mass.worst, 0.0, mass.worst,
                          "2D, dx 1 mm, 2 x 50 particles, 10^4 steps, cfl 0.2", clock.seconds(),
                          "< 1 % (continuity_form: mass; Eq. 5.1a: " +
                              std::to_string(volume.worst * 100.0).substr(0, 4) + " %)",
                          "conservation (kinetic + compression)"});
}

TEST(CouplingMomentum, DropletOnAFreeBlockConservesMomentumAndEnergy) {
  test::Stopwatch clock;
  Scene s = loadSceneText(kDroplet, "droplet_block.yaml");
  Simulation& sim = *s.sim;
  ASSERT_NE(sim.module("coupling"), nullptr) << "fluid + solid scenes get the coupling module";
  auto integrator = makeIntegrator("leapfrog");
  const Vec<2> p0 = momentum(sim);
  const double e0 = totalEnergy(sim);
  double worstP = 0.0, worstE = 0.0, solidMomentum = 0.0;
  // The solid's own balance: its kinetic + elastic energy change against the work of the
  // fluid-solid pair forces on it (their power at the synchronised velocities, trapezoid over the
  // steps; the pair forces are re-evaluated by the coupling's stage on the state after the step,
  // with the store's rates put back).
  Module* coupling = sim.module("coupling");
  auto solidEnergy = [&] {
    return column(sim, "solid_kinetic_energy") + column(sim, "solid_elastic_energy");
  };
  std::vector<double> accSaved, rateSaved;
  auto pairPowerOnSolid = [&] {
    ParticleStore& st = sim.store;
    const Index n = st.realCount();
    double* acc = st.data(sim.acceleration);
    double* rate = st.data(st.real("density_rate"));
    accSaved.assign(acc, acc + 2 * n);
    rateSaved.assign(rate, rate + n);
    std::fill(acc, acc + 2 * n, 0.0);
    coupling->interfaces(sim);
    double P = 0.0;
    const double* v = st.data(st.velocity());
    const double* m = st.data(st.mass());
    for (Index i = 0; i < n; ++i)
      if (st.data(st.phase())[i] == kPhaseSolid)
        P += m[i] * (acc[2 * i] * v[2 * i] + acc[2 * i + 1] * v[2 * i + 1]);
    std::copy(accSaved.begin(), accSaved.end(), acc);
    std::copy(rateSaved.begin(), rateSaved.end(), rate);
    return P;
  };
  const double es0 = solidEnergy();
  double pairWork = 0.0, power = pairPowerOnSolid(), worstSolid = 0.0;
  const int steps = 10000;
  for (int k = 1; k <= steps; ++k) {
    const double dt = s.nextTimeStep();
    integrator->step(sim, dt);
    const double p1 = pairPowerOnSolid();
    pairWork += 0.5 * dt * (power + p1);
    power = p1;
    if (k % 100 != 0) continue;
    worstP = std::max(worstP, (momentum(sim) - p0).norm() / p0.norm());
    worstE = std::max(worstE, std::abs(totalEnergy(sim) - e0) / e0);
    worstSolid = std::max(worstSolid, std::abs(solidEnergy() - es0 - pairWork) / e0);
  }
  // The block was pushed: the momentum it took came from the droplet through the pair forces.
  const ParticleStore& st = sim.store;
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseSolid)
      solidMomentum += st.data(st.mass())[i] * st.data(st.velocity())[2 * i];
  std::printf("  %d steps to t = %.4f s: momentum drift %.3e, energy drift %.3e, block took "
              "%.1f %% of the momentum; solid: pair work %.3e J, energy change %.3e J, worst "
              "|change - work| %.2e of E0\n",
              steps, sim.time, worstP, worstE, 100.0 * solidMomentum / p0.norm(), pairWork,
              solidEnergy() - es0, worstSolid);
  EXPECT_GT(solidMomentum, 0.2 * p0.norm());
  EXPECT_LT(worstP, 1e-12);
  // Total, with the fluid's energy-consistent continuity (continuity_form: mass, the partner of
  // the momentum form 5.2b): measured 1.43e-3 at cfl 0.2 (1.77e-4 / 2.84e-5 at cfl 0.1 / 0.05:
  // second order in dt, ExploreContinuityForm). With Eq. 5.1a (rho_a sum V_b v_ab . grad W) the
  // same scene drifts 3.8 % (2.3 / 2.8 % at cfl 0.1 / 0.05: not a time-step error), which fails
  // this bound: 5.1a with 5.2b leaves the power 1/2 sum m_a m_b (v_ab . grad W)(1/rho_b - 1/rho_a)
  // (p_a/rho_a - p_b/rho_b) (tests/validation/test_solid_energy.cpp ExploreDroplet). The solid
  // closes its own balance (5.6e-4 of E0: its force is the exact gradient of its stored energy,
  // unit test SolidVariational) and the mirror pairs conserve energy by construction. The
  // extrapolated (Adami) pairs gain 20-80 % here (docs/coupling.md).
  EXPECT_LT(worstE, 0.01);
  EXPECT_LT(worstSolid, 0.002);
  test::recordValidation({"coupling_droplet_block_momentum", "relative drift of total momentum",
                          worstP, 0.0, worstP, "2D, dx 1 mm, 50 fluid + 200 solid particles",
                          clock.seconds(), "< 1e-12",
                          "conservation (action = reaction in every pair)"});
  test::recordValidation({"coupling_droplet_block_energy", "relative drift of total energy",
                          worstE, 0.0, worstE, "2D, dx 1 mm, 10^4 steps", clock.seconds(),
                          "< 1 % (continuity_form: mass)", "conservation (kinetic + compression + elastic)"});
  test::recordValidation({"coupling_droplet_block_solid_balance",
                          "max |solid energy change - work of the pair forces| / E0", worstSolid, 0.0,
                          worstSolid, "2D, dx 1 mm, 10^4 steps", clock.seconds(), "< 0.2 %",
                          "the solid's energy balance (kinetic + elastic against the pair work)"});
}

// The fluid's default settings (issue 11: energy within 1 % "with the default settings"): the
// thesis' Eq. 5.2a as the pressure gradient (`pressure_gradient: volume`, the default since
// 2026-11-27; physics/fluid/fluid_pair.hpp) with the default continuity Eq. 5.1a; the scenes
// have no `fluid:` section at all, so the test fails if either default changes. The pair's power is
// exactly minus the compression rate of its continuity terms (docs/coupling.md "Energy per pair
// class"), and the mirror fluid-solid pairs are unchanged (p_b = p_a, rho_b = rho_a: 5.2a and
// 5.2b coincide). The droplet on the free block and the two droplets, 1e4 steps at cfl 0.2:
// total energy within the issue's 1 % (Eq. 5.2b with 5.1a drifts 3.8 % / 3.3 %, the tests
// above), momentum to round-off.
TEST(CouplingMomentum, DropletOnAFreeBlockConservesEnergyWithTheDefaultEq52a) {
  test::Stopwatch clock;
  const EnergyRun block = energyDrift(dropletText("", false, 0.2), 10000);
  const double blockSeconds = clock.seconds();
  const EnergyRun two = energyDrift(dropletText("", true, 0.2), 10000);
  std::printf("  Eq. 5.2a + 5.1a, 1e4 steps: block to t = %.4f s: worst energy drift %.3e (last "
              "%+.3e), momentum %.3e; two droplets to t = %.4f s: energy %.3e (last %+.3e), "
              "momentum %.3e\n",
              block.time, block.worst, block.last, block.momentum, two.time, two.worst, two.last,
              two.momentum);
  EXPECT_LT(block.worst, 0.01);
  EXPECT_LT(two.worst, 0.01);
  EXPECT_LT(block.momentum, 1e-12);
  EXPECT_LT(two.momentum, 1e-12);
  test::recordValidation({"coupling_droplet_block_energy_eq52a", "relative drift of total energy",
                          block.worst, 0.0, block.worst, "2D, dx 1 mm, 10^4 steps, cfl 0.2",
                          blockSeconds, "< 1 % (the fluid's defaults: Eq. 5.2a with Eq. 5.1a)",
                          "conservation (kinetic + compression + elastic)"});
  test::recordValidation({"fluid_two_droplets_energy_eq52a", "relative drift of total energy",
                          two.worst, 0.0, two.worst, "2D, dx 1 mm, 2 x 50 particles, 10^4 steps, cfl 0.2",
                          clock.seconds() - blockSeconds, "< 1 % (the fluid's defaults: Eq. 5.2a with Eq. 5.1a)",
                          "conservation (kinetic + compression)"});
}

// 3. Pressurised pore (2D): the case is in coupling_pore_case.hpp.
TEST(CouplingPore, ExploreLatticeResolution) {
  if (!std::getenv("PORE_LATTICE_STUDY")) GTEST_SKIP() << "set PORE_LATTICE_STUDY=1";
  // PORE_N: one resolution (particles across the wall), lattice only.
  std::vector<int> ns = {16, 24, 32};
  if (std::getenv("PORE_N")) ns = {std::atoi(std::getenv("PORE_N"))};
  for (int n : ns) runPressurisedPore(false, n, 0.01);
  if (!std::getenv("PORE_N")) runPressurisedPore(true, 16, 0.01);
}

TEST(CouplingPore, PressurisedRingAgainstLame) {
  if (std::getenv("PORE_STUDY")) {
    for (int n : {12, 16, 24})
      for (double t : {0.01, 0.02}) runPressurisedPore(true, n, t);
  }
  // Measured (time averages over the last third of 0.01 s / 0.02 s): 12 rings 6.9 / 8.2 %
  // displacement, 3.1 / 4.0 % hoop; 16 rings 4.0 / 4.9 %, 2.0 / 1.1 %; 24 rings 4.1 / 4.4 %,
  // 3.0 / 2.7 %: the displacement stays ~4 % short of Lame from 16 rings on (docs/coupling.md).
  const PoreResult r = runPressurisedPore(true, 16, 0.01);
  EXPECT_LT(r.displacementError, 0.05);
  EXPECT_LT(r.hoopError, 0.05);
  EXPECT_EQ(r.crossings, 0);
  const std::string res = "2D plane strain, 16 rings across the wall, " +
                          std::to_string(r.particles) + " particles";
  test::recordValidation({"coupling_pressurised_pore_rings", "radial displacement at the bore",
                          r.uMeasured, r.uExact, r.displacementError, res, r.wall, "< 5 %",
                          "Lame, thick cylinder at the water's pressure"});
  test::recordValidation({"coupling_pressurised_pore_rings", "hoop stress at the bore",
                          r.hoopMeasured, r.hoopExact, r.hoopError, res, r.wall, "< 5 %",
                          "Lame, thick cylinder at the water's pressure"});
}

TEST(CouplingPore, PressurisedVoxelPoreAgainstLame) {
  // The bore is a voxel staircase (what an image gives). Measured (docs/coupling.md "Staircase
  // bore"): the load is right (the fluid's total radial force 1.002 / 0.992 / 0.992 of 2 pi a p at
  // 16 / 24 / 32 across) and from the second layer on the hoop stress follows Lame (within 3-6 %
  // at 16, 0-2 % at 24-32), but the first layer's mean is 17 / 20 / 25 % low and does not
  // converge: it mixes teeth (two wet faces, stress towards -p 1) and omits the notches. The
  // wall value of solid::estimateWallStress (linear MLS from 1.5-5 dx behind each wet particle,
  // extrapolated to the colour-gradient wall point) is asserted at two resolutions: measured
  // 6.2 % (16 across) and 5.5 % (24 across), against the first layer's 17 / 20 %.
  for (int across : {16, 24}) {
    const PoreResult r = runPressurisedPore(false, across, 0.01);
    EXPECT_EQ(r.crossings, 0);
    EXPECT_LT(r.displacementError, 0.05);
    EXPECT_LT(r.hoopError, 0.22);  // first-layer mean: the staircase (regression guard)
    EXPECT_LT(r.wallHoopError, 0.08) << across << " across";
    EXPECT_LT(r.wallHoopError, 0.5 * r.hoopError) << across << " across";
    EXPECT_NEAR(r.wallRadius, 0.01, 0.05 * 0.01);  // the wall points lie on r = a
    const std::string res = "2D plane strain, lattice, " + std::to_string(across) +
                            " dx across the wall, " + std::to_string(r.particles) + " particles";
    const std::string id = across == 16 ? "coupling_pressurised_pore_lattice"
                                        : "coupling_pressurised_pore_lattice_24";
    test::recordValidation({id, "radial displacement at the bore", r.uMeasured, r.uExact,
                            r.displacementError, res, r.wall, "< 5 %",
                            "Lame, thick cylinder at the water's pressure"});
    test::recordValidation({id, "hoop stress at the bore (first-layer mean)", r.hoopMeasured,
                            r.hoopExact, r.hoopError, res, r.wall, "< 22 % (staircase)",
                            "Lame, thick cylinder at the water's pressure"});
    test::recordValidation({id, "hoop stress at the wall r = a (solid::estimateWallStress)",
                            r.wallHoop, r.wallHoopExact, r.wallHoopError, res, r.wall,
                            "< 8 % and < half the first layer's",
                            "Lame, thick cylinder at the water's pressure"});
  }
}

// The spherical pore (3D) on the voxel lattice, from a scene file (the shipped sample's 3D
// twin): u(r) = p a^3 / (E (b^3 - a^3)) [(1 - 2 nu) r + (1 + nu) b^3 / (2 r^2)].
TEST(CouplingPore, PressurisedSphericalVoxelPoreAgainstLame) {
  test::Stopwatch clock;
  const double a = 0.01, b = 0.02, E = 1.0e6, nu = 0.25;
  const double dx = std::getenv("PORE_DX") ? std::atof(std::getenv("PORE_DX")) : 0.002;
  const double endTime = std::getenv("PORE_T") ? std::atof(std::getenv("PORE_T")) : 0.01;
  std::string text = R"(dimension: 3
domain: {lo: [-0.025, -0.025, -0.025], hi: [0.025, 0.025, 0.025]}
spacing: 0.002
kernel: wendland_c2
end_time: 0.01
time_step: {adaptive: true, cfl: 0.5}
output: {every_time: 0.001}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 3, viscosity: 0.05, background_pressure: 1000}
  - {name: clay, model: elastic, density: 1000, young_modulus: 1.0e6, poisson_ratio: 0.25, formulation: total_lagrangian, damping: 3000}
geometry:
  - {shape: sphere, centre: [0, 0, 0], radius: 0.02, material: clay}
  - {shape: sphere, centre: [0, 0, 0], radius: 0.01, material: water}
)";
  text.replace(text.find("spacing: 0.002"), 14, "spacing: " + std::to_string(dx));
  text.replace(text.find("end_time: 0.01"), 14, "end_time: " + std::to_string(endTime));
  Scene s = loadSceneText(text, "pore_3d.yaml");
  Simulation& sim = *s.sim;
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  const RealField X = st.real("reference_position"), pressure = st.real("pressure");
  double pSum = 0.0, uSum = 0.0, rSum = 0.0, wHoop = 0.0, pHoop = 0.0, wR = 0.0;
  Index nf = 0, ns = 0, crossings = 0, nw = 0;
  long k = 0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.time < 2.0 / 3.0 * s.endTime || ++k % 10 != 0) continue;
    if (std::getenv("PORE_WALL_3D"))  // study: the wall hoop stress read by the estimator
      for (const auto& e : solid::estimateWallStress<3>(sim, dx)) {
        const Vec<3> er = e.wallPoint.normalized();
        wHoop += 0.5 * (e.stress.trace() - er.dot(e.stress * er));
        pHoop += 0.5 * (e.particleStress.trace() - er.dot(e.particleStress * er));
        wR += e.wallPoint.norm();
        ++nw;
      }
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] == kPhaseFluid) {
        pSum += st.data(pressure)[i];
        ++nf;
        continue;
      }
      const Vec<3> Xi = st.vec<3>(X, i);
      const double r0 = Xi.norm();
      if (r0 > a + dx) continue;
      uSum += (st.vec<3>(st.position(), i) - Xi).dot(Xi / r0);
      rSum += r0;
      ++ns;
    }
  }
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseFluid && st.vec<3>(st.position(), i).norm() > a + 0.5 * dx)
      ++crossings;
  const double p = pSum / nf, r = rSum / ns, u = uSum / ns;
  const double exact = p * a * a * a / (E * (b * b * b - a * a * a)) *
                       ((1.0 - 2.0 * nu) * r + (1.0 + nu) * b * b * b / (2.0 * r * r));
  const double err = std::abs(u - exact) / exact;
  if (nw > 0) {
    const double rw = wR / nw, hw = p * a * a * a / (b * b * b - a * a * a) *
                                     (1.0 + b * b * b / (2.0 * rw * rw * rw));
    std::printf("  3D wall estimate: hoop %.1f Pa at r = %.5f (Lame %.1f, %.2f %%); wet particles' "
                "own hoop %.1f (%.2f %%)\n", wHoop / nw, rw, hw, 100 * (wHoop / nw / hw - 1),
                pHoop / nw, 100 * (pHoop / nw / hw - 1));
  }
  std::printf("  3D lattice, dx %g: water p = %.1f Pa, u(%.5f) = %.4e m (Lame %.4e, "
              "%.2f %%), %lld particles, %.1f s\n",
              dx, p, r, u, exact, 100.0 * err, static_cast<long long>(st.realCount()), clock.seconds());
  // Measured: 18.1 % at 5 dx across the wall (dx 2 mm), 13.8 % at 6.7 (dx 1.5 mm, 12.7 s), the
  // same at twice the relaxation time: the staircase sphere converges slowly (docs/coupling.md;
  // the body-fitted shells of test_pore_shells_3d.cpp meet 5 % on the displacement). The bound
  // guards the measured value against regression.
  EXPECT_EQ(crossings, 0);
  EXPECT_LT(err, 0.20);
  test::recordValidation({"coupling_pressurised_pore_3d_lattice", "radial displacement at the bore",
                          u, exact, err,
                          "3D, lattice, 5 dx across the wall, " + std::to_string(st.realCount()) +
                              " particles",
                          clock.seconds(), "< 20 % (staircase)", "Lame, thick sphere at the water's pressure"});
}

// ---------------------------------------------------------------------------------------------
// 5 (the slit's opening, without the gas). samples/coupling_elastic_slit.yaml: water between two
// elastic layers, periodic along x, each layer clamped at its back. A uniform pressure p on the
// wet face of a periodic layer gives uniaxial strain, exactly: sigma_yy = -p, eps_yy = -p / M,
// M = E (1 - nu) / ((1 + nu)(1 - 2 nu)); the wet face moves back by p t / M (t: free thickness,
// from the clamp's boundary to the wet face) and the slit widens by 2 p t / M. Time averages over
// the last third of the run (the layers are damped; the water rings slowly), p the water's mean
// pressure then.
TEST(CouplingSlit, PeriodicElasticSlitWidensByPtOverM) {
  test::Stopwatch clock;
  Scene s = loadScene(std::string(PORESPH_SOURCE_DIR) + "/samples/coupling_elastic_slit.yaml");
  Simulation& sim = *s.sim;
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  const double E = 1.0e6, nu = 0.25, t = 0.005, gap = 0.005, dx = sim.spacing;
  const double M = E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const RealField X = st.real("reference_position"), sigma = st.real("stress");
  const RealField pressure = st.real("pressure");
  double pSum = 0.0, wSum = 0.0, sSum = 0.0;
  long nP = 0, nW = 0, nS = 0, k = 0;
  Index crossings = 0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.time < 2.0 / 3.0 * s.endTime || ++k % 10 != 0) continue;
    double low = 0.0, high = 0.0, sl = 0.0;
    long nl = 0, nh = 0, ns = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] == kPhaseFluid) {
        pSum += st.data(pressure)[i];
        ++nP;
        continue;
      }
      const double Y = st.vec<2>(X, i)[1];
      const double uy = st.vec<2>(st.position(), i)[1] - Y;
      if (Y < 0.0 && Y > -dx) low += uy, ++nl;           // the lower layer's wet row
      if (Y > gap && Y < gap + dx) high += uy, ++nh;     // the upper layer's wet row
      if (Y < -0.2 * t && Y > -0.8 * t) sl += st.mat<2>(sigma, i)(1, 1), ++ns;  // interior
    }
    wSum += high / nh - low / nl;
    ++nW;
    sSum += sl / ns;
    ++nS;
  }
  for (Index i = 0; i < st.realCount(); ++i) {
    if (st.data(st.phase())[i] != kPhaseFluid) continue;
    const double y = st.vec<2>(st.position(), i)[1];
    if (y < 0.0 || y > gap) ++crossings;  // water in a layer
  }
  const double p = pSum / nP, widening = wSum / nW, syy = sSum / nS;
  const double exact = 2.0 * p * t / M;
  const double wErr = std::abs(widening - exact) / exact, sErr = std::abs(-syy - p) / p;
  std::printf("  elastic slit, dx %g: water p = %.2f Pa, widening %.4e m (2 p t / M = %.4e, "
              "%.2f %%), interior sigma_yy %.2f Pa (-p: %.2f %%), %lld crossings, %lld "
              "particles, %.1f s\n",
              dx, p, widening, exact, 100.0 * wErr, syy, 100.0 * sErr,
              static_cast<long long>(crossings), static_cast<long long>(st.realCount()),
              clock.seconds());
  // Measured: widening 1.1 % below 2 p t / M, sigma_yy 2.6 % below p in magnitude (the solid's
  // strain follows its stress exactly: the 2.6 % is the traction the mirror pairs put on a flat
  // lattice wall; the ring pore is ~4 % short, docs/coupling.md "Elastic slit").
  EXPECT_EQ(crossings, 0);
  EXPECT_LT(wErr, 0.05);
  EXPECT_LT(sErr, 0.05);
  const std::string res = "2D, dx 0.25 mm, layers 20 dx free, water 20 dx, 20 columns periodic, " +
                          std::to_string(st.realCount()) + " particles";
  test::recordValidation({"coupling_elastic_slit", "slit widening under the water's pressure",
                          widening, exact, wErr, res, clock.seconds(), "< 5 %",
                          "uniaxial strain of a periodic clamped layer: 2 p t / M"});
  test::recordValidation({"coupling_elastic_slit", "interior sigma_yy of a layer / -p", -syy, p,
                          sErr, res, clock.seconds(), "< 5 %",
                          "uniaxial strain: sigma_yy = -p"});
}
