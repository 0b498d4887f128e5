// Energy conservation of the Total-Lagrangian solid (issues 11 and 13: the balance closes to 1 %),
// docs/solid.md "Energy". Default tests: a free block keeps kinetic + elastic (+ hourglass penalty)
// energy to second order in dt; the driven softening bar (no damage) closes its balance.
// Explore drivers (PORESPH_SOLID_ENERGY=1, the studies quoted in the docs): the free block against
// integrator, step and hourglass control (PORESPH_HG_FORM=pairwise for the old spring, PORESPH_A
// amplitude, PORESPH_T duration); the droplet on a free block against two droplets without any
// solid, with the work of the fluid-solid pairs on the solid; the bar against AV, step and ramp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/phases.hpp"
#include "libcore/scene.hpp"
#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

std::string blockScene(double hourglass, const std::string& extra) {
  const char* form = std::getenv("PORESPH_HG_FORM");
  return std::string(form ? std::string("solid: {hourglass_form: ") + form + "}\n" : "") +
         "dimension: 2\n"
         "domain: {lo: [-0.02, -0.02], hi: [0.04, 0.02]}\n"
         "spacing: 0.001\n"
         "kernel: wendland_c2\n"
         "end_time: 1.0\n"
         "time_step: {adaptive: true, cfl: 0.2}\n"
         "output: {every_steps: 100000}\n"
         "materials:\n"
         "  - {name: block, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: "
         "0.25, formulation: total_lagrangian, hourglass: " +
         std::to_string(hourglass) + extra +
         "}\n"
         "geometry:\n"
         "  - {shape: box, lo: [0.0, -0.01], hi: [0.01, 0.01], material: block}\n";
}

struct Drift {
  double worst = 0.0, e0 = 0.0, last = 0.0;
  int steps = 0;
};

// Free vibration from v = A (sin(2 pi y / Ly), sin(2 pi x / Lx)) (zero mean) for `duration`.
// dtFactor > 0: fixed step dtFactor x Eq. 2.50; < 0: the scene's adaptive step x |dtFactor|/0.2.
Drift vibrate(const std::string& integratorName, double hourglass, double dtFactor,
              double amplitude, double duration, const std::string& extra = "") {
  Scene sc = loadSceneText(blockScene(hourglass, extra), "block.yaml");
  Simulation& sim = *sc.sim;
  auto* solid = dynamic_cast<ElasticSolidModule*>(sim.module("solid"));
  ParticleStore& s = sim.store;
  const double pi = 3.14159265358979323846;
  for (Index i = 0; i < s.realCount(); ++i) {
    const Vec<2> x = s.vec<2>(s.position(), i);
    s.vec<2>(s.velocity(), i) =
        amplitude * Vec<2>(std::sin(2 * pi * x[1] / 0.02), std::sin(2 * pi * x[0] / 0.01));
  }
  auto integrator = makeIntegrator(integratorName);
  sim.evaluateRates();
  Drift d;
  d.e0 = solid->kineticEnergy(sim) + solid->elasticEnergy(sim) + solid->hourglassEnergy(sim);
  const double fixedDt = dtFactor * solid->elasticTimeStepLimit(sim);
  while (sim.time < duration) {
    double dt = fixedDt;
    if (dtFactor < 0.0) dt = sc.nextTimeStep() * (-dtFactor) / 0.2;
    integrator->step(sim, dt);
    ++d.steps;
    const double e = solid->kineticEnergy(sim) + solid->elasticEnergy(sim) +
                     solid->hourglassEnergy(sim) + solid->work(sim)[2];
    d.last = (e - d.e0) / d.e0;
    d.worst = std::max(d.worst, std::abs(d.last));
  }
  return d;
}

}  // namespace

TEST(SolidEnergy, Explore) {
  if (!std::getenv("PORESPH_SOLID_ENERGY")) GTEST_SKIP() << "set PORESPH_SOLID_ENERGY=1";
  const double A = std::getenv("PORESPH_A") ? std::atof(std::getenv("PORESPH_A")) : 0.2;
  const double T = std::getenv("PORESPH_T") ? std::atof(std::getenv("PORESPH_T")) : 0.01;
  for (const char* integ : {"leapfrog", "verlet", "predictor_corrector"})
    for (double hg : {0.0, 1.0})
      for (double f : {-0.2, 0.4, 0.2, 0.1, 0.05}) {
        const Drift d = vibrate(integ, hg, f, A, T);
        std::printf("%-20s hourglass %.0f dt %5.2f: steps %6d E0 %.4e worst %.3e last %+.3e\n",
                    integ, hg, f, d.steps, d.e0, d.worst, d.last);
        std::fflush(stdout);
      }
}

namespace {

double column(const Simulation& sim, const std::string& name) {
  for (const auto& [k, v] : sim.diagnostics())
    if (k == name) return v;
  return 0.0;
}

// The droplet of tests/validation/test_coupling.cpp (CouplingMomentum) with `block` as the
// block's material line ("" = two droplets colliding head-on, fluid only).
std::string dropletScene(double cfl, const std::string& block) {
  std::string s =
      "dimension: 2\n"
      "domain: {lo: [-0.02, -0.02], hi: [0.04, 0.02]}\n"
      "spacing: 0.001\n"
      "kernel: wendland_c2\n"
      "end_time: 1.0\n"
      "time_step: {adaptive: true, cfl: " + std::to_string(cfl) + "}\n"
      "output: {every_steps: 100000}\n"
      "materials:\n"
      "  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 0}\n";
  if (!block.empty()) s += "  - " + block + "\n";
  s += "geometry:\n";
  if (!block.empty())
    s += "  - {shape: box, lo: [0.0, -0.01], hi: [0.01, 0.01], material: block}\n";
  else
    s += "  - {shape: sphere, centre: [0.006, 0], radius: 0.004, material: water, velocity: [-1.0, 0]}\n";
  s += "  - {shape: sphere, centre: [-0.006, 0], radius: 0.004, material: water, velocity: [1.0, 0]}\n";
  return s;
}

}  // namespace

TEST(SolidEnergy, ExploreDroplet) {
  if (!std::getenv("PORESPH_SOLID_ENERGY")) GTEST_SKIP() << "set PORESPH_SOLID_ENERGY=1";
  const std::string blockLine =
      "{name: block, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
      "formulation: total_lagrangian}";
  const int steps0 = std::getenv("PORESPH_STEPS") ? std::atoi(std::getenv("PORESPH_STEPS")) : 10000;
  for (const std::string& block : {blockLine, std::string()})
    for (double cfl : {0.2, 0.1, 0.05}) {
      Scene sc = loadSceneText(dropletScene(cfl, block), "droplet.yaml");
      Simulation& sim = *sc.sim;
      auto integrator = makeIntegrator("leapfrog");
      auto total = [&] {
        return column(sim, "kinetic_energy") + column(sim, "fluid_internal_energy") +
               column(sim, "solid_elastic_energy");
      };
      const double e0 = total();
      double worst = 0.0;
      const int steps = static_cast<int>(steps0 * 0.2 / cfl);
      // The work of the fluid-solid pair forces on the solid (trapezoid over the steps of the
      // power at the synchronised velocities), against the solid's own energy change.
      auto solidEnergy = [&] {
        return column(sim, "solid_kinetic_energy") + column(sim, "solid_elastic_energy");
      };
      auto couplingPower = [&] {
        Module* cm = sim.module("coupling");
        if (!cm) return 0.0;
        ParticleStore& st = sim.store;
        const Index n = st.realCount();
        double* acc = st.data(sim.acceleration);
        double* dr = st.data(st.real("density_rate"));
        std::vector<double> a0(acc, acc + 2 * n), r0(dr, dr + n);
        std::fill(acc, acc + 2 * n, 0.0);
        cm->interfaces(sim);
        double P = 0.0;
        const double* v = st.data(st.velocity());
        const double* m = st.data(st.mass());
        for (Index i = 0; i < n; ++i)
          if (st.data(st.phase())[i] == kPhaseSolid)
            P += m[i] * (acc[2 * i] * v[2 * i] + acc[2 * i + 1] * v[2 * i + 1]);
        std::copy(a0.begin(), a0.end(), acc);
        std::copy(r0.begin(), r0.end(), dr);
        return P;
      };
      // The power that the fluid's continuity (Eq. 5.1a, rho_a sum V_b v_ab . grad W) and momentum
      // (Eq. 5.2b) pair leaves over when the densities differ:
      //   1/2 sum_ab m_a m_b (v_ab . grad W_ab)(1/rho_b - 1/rho_a)(p_a/rho_a - p_b/rho_b)
      // (d/dt of kinetic + compression energy of the fluid-fluid pairs).
      auto fluidResidualPower = [&] {
        const ParticleStore& st = sim.store;
        const double* x = st.data(st.position());
        const double* v = st.data(st.velocity());
        const double* m = st.data(st.mass());
        const double* rho = st.data(st.density());
        const double* p = st.data(st.real("pressure"));
        const std::int32_t* ph = st.data(st.phase());
        const NeighbourList& nl = sim.neighbours;
        double P = 0.0;
        for (Index a = 0; a < st.realCount(); ++a) {
          if (ph[a] != kPhaseFluid) continue;
          for (auto k = nl.offset[static_cast<size_t>(a)]; k < nl.offset[static_cast<size_t>(a) + 1]; ++k) {
            const Index b = nl.index[static_cast<size_t>(k)];
            if (ph[b] != kPhaseFluid) continue;
            const Vec<2> r(x[2 * a] - x[2 * b], x[2 * a + 1] - x[2 * b + 1]);
            const double F = sim.kernel.F(r.norm());
            const double vgw = F * ((v[2 * a] - v[2 * b]) * r[0] + (v[2 * a + 1] - v[2 * b + 1]) * r[1]);
            P += 0.5 * m[a] * m[b] * vgw * (1.0 / rho[b] - 1.0 / rho[a]) * (p[a] / rho[a] - p[b] / rho[b]);
          }
        }
        return P;
      };
      double Wf = 0.0, Pf = fluidResidualPower(), worstRest = 0.0;
      const double es0 = solidEnergy();
      double W = 0.0, Pprev = couplingPower(), worstSolid = 0.0;
      for (int k = 1; k <= steps; ++k) {
        const double dt = sc.nextTimeStep();
        integrator->step(sim, dt);
        const double P = couplingPower();
        W += 0.5 * dt * (P + Pprev);
        Pprev = P;
        const double Pf1 = fluidResidualPower();
        Wf += 0.5 * dt * (Pf + Pf1);
        Pf = Pf1;
        worstRest = std::max(worstRest, std::abs((total() - e0 - Wf) / e0));
        if (!block.empty())
          worstSolid = std::max(worstSolid, std::abs(solidEnergy() - es0 - W) / e0);
        if (k % (steps / 20) != 0) continue;
        const double e = total();
        worst = std::max(worst, std::abs(e - e0) / e0);
        std::printf("  %s cfl %.2f t %.5f fluid KE %.5e int %.5e solid KE %.5e el %.5e total %+.3e\n",
                    block.empty() ? "two drops" : "block", cfl, sim.time,
                    column(sim, "fluid_kinetic_energy"), column(sim, "fluid_internal_energy"),
                    column(sim, "solid_kinetic_energy"), column(sim, "solid_elastic_energy"),
                    (e - e0) / e0);
        std::printf("    integral of the fluid pairs' residual power / E0 %+.3e\n", Wf / e0);
      }
      std::printf("%s cfl %.2f: %d steps to t %.4f, worst drift %.3e; solid: work in %.4e, "
                  "energy change %.4e, worst |change - work| / E0 %.3e; worst |drift - integral of "
                  "the fluid pairs' residual| %.3e (every step)\n",
                  block.empty() ? "two drops" : "block", cfl, steps, sim.time, worst, W,
                  solidEnergy() - es0, worstSolid, worstRest);
      std::fflush(stdout);
    }
}

namespace {

// The softening bar of tests/validation/test_damage_bar.cpp without damage (1D TL, ends driven
// at -+70 m/s over one support from t = 0): |change of kinetic + elastic + dissipated - boundary
// work| / boundary work at t = 1.5 L / c, the balance taken after step `from`.
double barBalance(int n, double dtFactor, double alpha, double beta, int from, double rampTime,
                  double* workOut = nullptr, const std::string& damage = "",
                  const std::string& commit = "") {
  const double E = 70.8e9, rho = 1550.0, L = 0.1, v0 = 70.0, lambda = 5e-3;
  Simulation sim(1);
  char mat[512];
  std::snprintf(mat, sizeof mat,
                "{density: %g, young_modulus: %g, formulation: total_lagrangian, "
                "artificial_viscosity: {alpha: %g, beta: %g}%s}",
                rho, E, alpha, beta, damage.c_str());
  sim.addMaterial("bar", "elastic", mat, "test");
  const double dx = 2.0 * L / (n - 1);
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 1, 0.5 * lambda);
  sim.store.addParticles(n);
  double* x = sim.store.data(sim.store.position());
  for (int i = 0; i < n; ++i) x[i] = -L + i * dx;
  sim.domain.lo = {-L - 10 * dx - 0.1, 0, 0};
  sim.domain.hi = {L + 10 * dx + 0.1, 1, 1};
  char sec[512];
  std::snprintf(sec, sizeof sec,
                "{%sboundaries: [{name: left, type: velocity, velocity: [%g], ramp_time: %g, box: {min: [-1], max: [%.9g]}}, "
                "{name: right, type: velocity, velocity: [%g], ramp_time: %g, box: {min: [%.9g], max: [1]}}]}",
                commit.empty() ? "" : ("damage_commit: " + commit + ", ").c_str(), -v0, rampTime,
                -L + lambda - 0.25 * dx, v0, rampTime, L - lambda + 0.25 * dx);
  std::unique_ptr<Module> mod = ModuleRegistry::create("solid");
  std::vector<const Material*> mats{&sim.materials[0]};
  ParameterSet section(YAML::Load(sec), "test", "solid");
  mod->configure(sim, mats, &section);
  auto* solid = dynamic_cast<ElasticSolidModule*>(mod.get());
  sim.addModule(std::move(mod));
  solid->initialise(sim);
  auto balance = [&] {
    const auto w = solid->work(sim);
    return solid->kineticEnergy(sim) + solid->elasticEnergy(sim) + w[2] - w[0] - w[1] +
           solid->damageDissipation(sim);
  };
  const double c = std::sqrt(E / rho);
  const double tEnd = 1.5 * L / c;
  const double dt = dtFactor * solid->elasticTimeStepLimit(sim);
  auto integrator = makeIntegrator("leapfrog");
  double b0 = from == 0 ? balance() : 0.0;
  long steps = 0;
  while (sim.time < tEnd * (1.0 - 1e-9)) {
    const double h = std::min(dt, tEnd - sim.time);
    integrator->step(sim, h);  // its finishStep commits the damage (Module::endOfStep)
    if (++steps == from) b0 = balance();
  }
  const double w = solid->work(sim)[0];
  if (workOut) *workOut = w;
  return std::abs(balance() - b0) / std::abs(w);
}

}  // namespace

TEST(SolidEnergy, ExploreBar) {
  if (!std::getenv("PORESPH_SOLID_ENERGY")) GTEST_SKIP() << "set PORESPH_SOLID_ENERGY=1";
  for (const char* commit : {"step_end", "evaluation"})
    for (double f : {0.5, 0.25, 0.125}) {  // with PCW damage (DamageBar's law): the commit's share
      double w = 0.0;
      const double b = barBalance(201, f, 10.0, 1.0, 1, 0.0, &w,
                                  ", damage: {law: pcw, strain_onset: 0.022, strain_ultimate: 0.060}", commit);
      std::printf("bar with damage, damage_commit %s, dt %.3f: balance %.3e of work %.4g\n", commit, f, b, w);
    }
  for (double ramp : {0.0, 2e-6})
    for (int from : {0, 1})
      for (double alpha : {10.0, 1.0, 0.0})
        for (double f : {0.5, 0.25, 0.125}) {
          double w = 0.0;
          const double b = barBalance(201, f, alpha, alpha > 0 ? 1.0 : 0.0, from, ramp, &w);
          std::printf("bar ramp %.0e from step %d alpha %4.1f dt %.3f: balance %.3e of work %.4g\n",
                      ramp, from, alpha, f, b, w);
          std::fflush(stdout);
        }
}

// Issue 11/13: the energy of the TL solid closes to 1 %. A free block (10 x 20 particles, E 1 MPa,
// nu 0.25, zero-mean velocity field 0.2 m/s, 10 ms, ~6 periods of the slowest mode, leapfrog)
// conserves kinetic + elastic (+ the hourglass penalty energy) to second order in dt: the TL
// force is the exact gradient of the stored energy (unit test SolidVariational), so what is left
// is the integrator's. Without hourglass control and with the conservative one (default form).
TEST(SolidEnergy, FreeBlockConservesEnergyToSecondOrderInDt) {
  test::Stopwatch clock;
  for (double hg : {0.0, 1.0}) {
    const Drift coarse = vibrate("leapfrog", hg, 0.2, 0.2, 0.01);
    const Drift fine = vibrate("leapfrog", hg, 0.1, 0.2, 0.01);
    const double order = std::log2(coarse.worst / fine.worst);
    std::printf("free block, hourglass %.0f: worst drift %.3e (dt 0.2 x Eq. 2.50), %.3e (0.1), "
                "order %.2f\n", hg, coarse.worst, fine.worst, order);
    // measured 9.0e-4 / 2.3e-4 (order 2.0) with and without hourglass control; the pairwise
    // (Ganzenmueller) spring left 3.1 % at every dt, uncounted
    EXPECT_LT(fine.worst, 1e-3) << "hourglass " << hg;
    EXPECT_GT(order, 1.7) << "hourglass " << hg;
    const std::string res = std::string("2D, 10 x 20 particles, h 1.3 dx, leapfrog, dt 0.1 x Eq. 2.50, ") +
                            (hg > 0 ? "conservative hourglass 1" : "no hourglass control");
    test::recordValidation({hg > 0 ? "solid_free_block_energy_hourglass" : "solid_free_block_energy",
                            "max relative drift of kinetic + elastic + hourglass energy, 6 periods",
                            fine.worst, 0.0, fine.worst, res, clock.seconds(), "< 0.1 %, order > 1.7",
                            "conservation (issue 11: 1 %)"});
  }
}

// The softening bar of issue 13 without damage (test_damage_bar.cpp: 201 points, 2h 5 mm, ends
// driven at -+70 m/s from t = 0, artificial viscosity 10/1): kinetic + elastic + dissipated -
// boundary work after the first step (the driven layers start at v at once) stays constant.
TEST(SolidEnergy, DrivenBarBalanceCloses) {
  test::Stopwatch clock;
  double work = 0.0;
  const double b = barBalance(201, 0.5, 10.0, 1.0, 1, 0.0, &work);
  std::printf("driven bar (201 points, AV 10/1): balance %.3e of the boundary work %.4g J\n", b, work);
  // measured 2.6e-6 (O(dt^2)); 2.2e-2 while the viscous work of the pairs with the driven
  // layers was counted on the free side only
  EXPECT_LT(b, 1e-4);
  test::recordValidation({"solid_driven_bar_balance", "energy balance residual / boundary work", b,
                          0.0, b, "1D, 201 points, 2h 5 mm, AV 10/1, dt 0.5 x Eq. 2.50, leapfrog",
                          clock.seconds(), "< 1e-4 (issue 13: 1 %)",
                          "Eqs. 4.25-4.26 (no damage): kinetic + elastic + dissipated - work"});
}

// The same bar with PCW damage (DamageBar's law; the centre softens from t = L/c): the balance
// closes to second order in dt with `damage_commit: evaluation`: the damage is committed where the
// step's acceleration is evaluated (ElasticSolidModule::constitutive) and released with the step's mean
// degradable energy (trapezoidal, as the leapfrog's work); committed after the step (the
// default `step_end`: the acceleration holds D^n for the next half kick) the residual fell only
// as dt: 3.6e-4 / 1.9e-4 of the work at 0.5 / 0.25 x Eq. 2.50 (order 0.9).
TEST(SolidEnergy, DamagedBarBalanceSecondOrderInDt) {
  test::Stopwatch clock;
  const std::string pcw = ", damage: {law: pcw, strain_onset: 0.022, strain_ultimate: 0.060}";
  const double coarse = barBalance(201, 0.5, 10.0, 1.0, 1, 0.0, nullptr, pcw, "evaluation");
  const double fine = barBalance(201, 0.25, 10.0, 1.0, 1, 0.0, nullptr, pcw, "evaluation");
  const double order = std::log2(coarse / fine);
  std::printf("damaged bar (201 points, PCW, AV 10/1): balance %.3e (dt 0.5 x Eq. 2.50), %.3e (0.25), "
              "order %.2f\n", coarse, fine, order);
  EXPECT_GT(order, 1.6);
  EXPECT_LT(coarse, 1e-4);
  test::recordValidation({"solid_damaged_bar_balance", "energy balance residual / boundary work", coarse,
                          0.0, coarse, "1D, 201 points, 2h 5 mm, PCW, AV 10/1, dt 0.5 x Eq. 2.50, leapfrog, damage_commit: evaluation",
                          clock.seconds(), "< 1e-4, order in dt > 1.6",
                          "Eqs. 4.25-4.26 with the released energy"});
}

// CPU time of the TL force stage (forces(): Eq. 2.76, 2.77, hourglass control) per particle and
// call, 1 thread: no hourglass control, the pairwise spring, the conservative control.
TEST(SolidEnergy, ExploreForceCost) {
  if (!std::getenv("PORESPH_SOLID_ENERGY")) GTEST_SKIP() << "set PORESPH_SOLID_ENERGY=1";
  for (int dim : {2, 3})
    for (const char* form : {"none", "pairwise", "conservative"}) {
      const int n = dim == 2 ? 100 : 20;
      const double dx = 0.01;
      Simulation sim(dim);
      sim.addMaterial("clay", "elastic",
                      std::string("{density: 2000, young_modulus: 1.0e9, poisson_ratio: 0.25, hourglass: ") +
                          (std::string(form) == "none" ? "0" : "1") + "}",
                      "test");
      sim.spacing = dx;
      sim.kernel = Kernel(KernelType::WendlandC2, dim, 1.3 * dx);
      if (dim == 2) buildBlock<2>(sim, Vec<2>::Zero(), {n, n, 1}, dx);
      else buildBlock<3>(sim, Vec<3>::Zero(), {n, n, n}, dx);
      for (int a = 0; a < dim; ++a) {
        sim.domain.lo[static_cast<size_t>(a)] = -dx;
        sim.domain.hi[static_cast<size_t>(a)] = (n + 1) * dx;
      }
      ElasticSolidModule& solid = addSolidModule(
          sim, std::string(form) == "pairwise" ? "{hourglass_form: pairwise}" : "");
      solid.initialise(sim);
      double* x = sim.store.data(sim.store.position());
      for (Index i = 0; i < dim * sim.store.realCount(); ++i) x[i] *= 1.001 + 1e-4 * std::sin(1.0 * i);
      sim.evaluateRates();
      const int calls = dim == 2 ? 200 : 40;
      const std::clock_t c0 = std::clock();
      for (int k = 0; k < calls; ++k) solid.forces(sim);
      const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
      std::printf("%dD %-12s: %ld particles, family ~%lld, forces() %.3f us per particle-call (CPU)\n",
                  dim, form, static_cast<long>(sim.store.realCount()),
                  static_cast<long long>(solid.familyMembers() / sim.store.realCount()),
                  1e6 * cpu / (calls * static_cast<double>(sim.store.realCount())));
      std::fflush(stdout);
    }
}

// The hourglass penalty's fastest mode (omega^2 = 2 sum_b k_ab V_b W0_ab / |X_ab|^2 / rho0) bounds
// the step where it is stiffer than Eq. 2.50: alpha = 1 leaves the limit at Eq. 2.50; alpha = 20
// lowers it, the free block runs at 0.9 x the lowered limit, and inverts at 0.9 x Eq. 2.50.
TEST(SolidEnergy, HourglassPenaltyBoundsTheStep) {
  auto plainLimit = [](const Simulation& sim, const ElasticSolidModule& solid) {
    const ElasticMaterial& e = solid.elasticMaterials()[0];
    return sim.kernel.h() / e.waveSpeed;
  };
  {
    Scene sc = loadSceneText(blockScene(1.0, ""), "block.yaml");
    auto* solid = dynamic_cast<ElasticSolidModule*>(sc.sim->module("solid"));
    const double ratio = 2.0 / std::sqrt(solid->hourglassOmega2()) / plainLimit(*sc.sim, *solid);
    std::printf("hourglass 1: 2/omega = %.2f x Eq. 2.50\n", ratio);
    EXPECT_GT(ratio, 1.0);
    EXPECT_DOUBLE_EQ(solid->elasticTimeStepLimit(*sc.sim), plainLimit(*sc.sim, *solid));
  }
  std::vector<double> factors{0.9, -0.9};
  if (std::getenv("PORESPH_HG_SCAN"))  // where the alpha = 20 block really goes unstable
    factors = {-0.3, -0.35, -0.4, -0.45, -0.5, -0.6};
  for (double factor : factors) {  // > 0: x the limit; < 0: x Eq. 2.50 (limit check lifted)
    Scene sc = loadSceneText(blockScene(20.0, ""), "block.yaml");
    Simulation& sim = *sc.sim;
    auto* solid = dynamic_cast<ElasticSolidModule*>(sim.module("solid"));
    const double plain = plainLimit(sim, *solid), limit = solid->elasticTimeStepLimit(sim);
    if (factor > 0.0) {
      std::printf("hourglass 20: limit %.2f x Eq. 2.50\n", limit / plain);
      EXPECT_LT(limit, 0.8 * plain);
    }
    const double dt = factor > 0.0 ? factor * limit : -factor * plain;
    if (factor < 0.0) solid->courant = plain / limit;  // lets the plain step through the check
    ParticleStore& s = sim.store;
    const double pi = 3.14159265358979323846;
    for (Index i = 0; i < s.realCount(); ++i) {
      const Vec<2> x = s.vec<2>(s.position(), i);
      s.vec<2>(s.velocity(), i) = 0.2 * Vec<2>(std::sin(2 * pi * x[1] / 0.02), std::sin(2 * pi * x[0] / 0.01));
    }
    auto integrator = makeIntegrator("leapfrog");
    bool failed = false;
    double e0 = -1.0, drift = 0.0;
    try {
      for (int k = 0; k < 600; ++k) {
        integrator->step(sim, dt);
        sim.checkFinite();
        const double e = solid->kineticEnergy(sim) + solid->elasticEnergy(sim) + solid->hourglassEnergy(sim);
        if (e0 < 0.0) e0 = e;
        drift = std::max(drift, std::abs(e - e0) / e0);
        if (!(drift < 10.0)) throw NumericalError("energy grew tenfold");
      }
    } catch (const NumericalError&) {
      failed = true;
    }
    std::printf("hourglass 20, dt %.2f x Eq. 2.50: %s, drift %.2e\n", dt / plain,
                failed ? "blew up" : "stable", drift);
    if (factor > 0.0) {
      EXPECT_FALSE(failed);
      EXPECT_LT(drift, 0.01);
    } else if (factor == -0.9) {
      EXPECT_TRUE(failed) << "the bound is not needed at alpha = 20?";
    }
  }
}
