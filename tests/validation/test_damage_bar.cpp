// Validation item 2 of issue 13: the dynamic softening bar of thesis Sec. 4.2 (Tab. 4.1, after
// Bazant & Belytschko and Vignjevic et al.): a bar of half-length L = 100 mm, E = 70.8 GPa,
// rho = 1550 kg/m3, pulled at both ends at v = +-70 m/s (Eq. 4.24), PCW damage (4.21, 4.27:
// a = 1, b = eps_tu / eps_t0 - 1 with eps_t0 = 0.022, eps_tu = 0.060), total-Lagrangian SVK,
// artificial viscosity alpha = 10, beta = 1 (Sec. 4.2), 1D.
//
// Yc0: Tab. 4.1 does not give it; we take the reading under which the PCW law peaks at eps_t0
// (uniaxial stress: Yc0 = (1 + b) E eps_t0^2 / 2, the `strain_onset` formula of docs/damage.md).
// Then the two incoming waves v/c = 0.0104 sum to 2 v / c = 0.0207, just below eps_t0, and the
// centre damages through the SPH overshoot where the waves cross: small, resolution-dependent peak
// values, as the thesis describes for Figs. 4.6-4.7 ("small damage peak values ... decreases with
// the increase of particle density"). (The reading Yc0 = E eps_t0^2 / 2 puts the onset at 0.0133
// and damages a zone 2-4 x 2h wide that keeps growing: not the thesis' picture.)
//
// The ends are driven over a layer one support deep (the driven particles are excluded from the
// damage checks). Damaged width = full width at half the peak damage.
//
// Asserted: no damage before t = L/c; damage only within 2h of the centre; the damaged width at
// t = 3L/(2c) within 30 % of 2h and within 20 % between 101, 151 and 201 points; with 2h = 10 and
// 20 mm the width grows with 2h. The energy balance (kinetic + elastic + dissipated - boundary
// work) is asserted below the 1 %: measured 3.6e-4 of the work (2.6e-6 without damage).
// Until 2026-11-24 it left 2.2 %: the viscous work of the pairs between driven and free particles
// was counted on the free side only (docs/solid.md "Energy bookkeeping").
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

constexpr double E = 70.8e9, rho = 1550.0, L = 0.1, v0 = 70.0;
constexpr double eps0 = 0.022, epsU = 0.060;

struct BarRun {
  double firstDamageTime = -1.0;  ///< first step with some D > 0
  double firstDamageX = 0.0;      ///< |x| of the first damaged particle
  double maxDistance = 0.0;       ///< largest |X| of a damaged particle at the end
  double width = 0.0;             ///< damaged width at t = 3L/(2c)
  double dmax = 0.0;
  double balance = 0.0;           ///< |balance change| / boundary work
  double work = 0.0;
  long steps = 0;
  double wall = 0.0;
  std::vector<double> X, D;
};

// kinetic + elastic + dissipated (viscosity, damage) - work of the boundaries (4.25-4.26)
double balanceOf(const ElasticSolidModule& solid, const Simulation& sim) {
  const auto w = solid.work(sim);
  return solid.kineticEnergy(sim) + solid.elasticEnergy(sim) + w[2] + solid.damageDissipation(sim) -
         w[0] - w[1];
}

// n points over [-L, L] (spacing 2L/(n-1)), support 2h = lambda.
BarRun run(int n, double lambda, bool damage = true) {
  test::Stopwatch clock;
  Simulation sim(1);
  const double rampTime = 0.0;  // Eq. 4.24: u = +-v t
  char mat[512];
  std::snprintf(mat, sizeof mat,
                "{density: %g, young_modulus: %g, formulation: total_lagrangian, "
                "artificial_viscosity: {alpha: 10, beta: 1}%s}",
                rho, E,
                damage ? ", damage: {law: pcw, strain_onset: 0.022, strain_ultimate: 0.060}" : "");
  addMaterial(sim, "bar", "elastic", mat);
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
                "{boundaries: [{name: left, type: velocity, velocity: [%g], ramp_time: %g, box: {min: [-1], max: [%.9g]}}, "
                "{name: right, type: velocity, velocity: [%g], ramp_time: %g, box: {min: [%.9g], max: [1]}}]}",
                -v0, rampTime, -L + lambda - 0.25 * dx, v0, rampTime, L - lambda + 0.25 * dx);
  ElasticSolidModule& solid = addSolidModule(sim, sec);
  solid.initialise(sim);
  const double c = std::sqrt(E / rho);
  const double tEnd = 1.5 * L / c;
  // PORESPH_DAMAGE_BAR_DT: dt / step limit (studies of docs/damage.md; default 0.5)
  const char* dtEnv = std::getenv("PORESPH_DAMAGE_BAR_DT");
  const double dt = (dtEnv ? std::atof(dtEnv) : 0.5) * solid.elasticTimeStepLimit(sim);
  auto integrator = makeIntegrator("leapfrog");
  BarRun r;
  long steps = 0;
  double balance0 = 0.0;
  const double* D = nullptr;
  while (sim.time < tEnd * (1.0 - 1e-9)) {
    integrator->step(sim, std::min(dt, tEnd - sim.time));
    ++steps;
    if (steps == 1) balance0 = balanceOf(solid, sim);  // the driven layers start at v at once
    if (!damage) continue;
    D = sim.store.data(sim.store.real("damage"));
    const double* X = sim.store.data(sim.store.real("reference_position"));
    const std::int32_t* mo = sim.store.data(sim.motion);
    if (r.firstDamageTime < 0.0)
      for (Index i = 0; i < sim.store.realCount(); ++i)
        if (D[i] > 0.0 && mo[i] == kMotionFree) {
          r.firstDamageTime = sim.time;
          r.firstDamageX = std::abs(X[i]);
          break;
        }
  }
  r.steps = steps;
  const double* X = sim.store.data(sim.store.real("reference_position"));
  const std::int32_t* mo = sim.store.data(sim.motion);
  double lo = 1.0, hi = -1.0;
  for (Index i = 0; damage && i < sim.store.realCount(); ++i) {
    if (mo[i] != kMotionFree) continue;  // the driven end layers
    r.X.push_back(X[i]);
    r.D.push_back(D[i]);
    r.dmax = std::max(r.dmax, D[i]);
    if (D[i] > 0.0) {
      lo = std::min(lo, X[i]);
      hi = std::max(hi, X[i]);
      r.maxDistance = std::max(r.maxDistance, std::abs(X[i]));
    }
  }
  // damaged width: full width at half the peak damage (linear interpolation between particles,
  // which lie in order of X)
  r.width = 0.0;
  if (r.dmax > 0.0) {
    const double half = 0.5 * r.dmax;
    size_t peak = 0;
    for (size_t i = 0; i < r.D.size(); ++i)
      if (r.D[i] > r.D[peak]) peak = i;
    size_t i = peak;
    while (i > 0 && r.D[i - 1] >= half) --i;
    const double left =
        i > 0 ? r.X[i - 1] + (r.X[i] - r.X[i - 1]) * (half - r.D[i - 1]) / (r.D[i] - r.D[i - 1])
              : r.X[0];
    i = peak;
    while (i + 1 < r.D.size() && r.D[i + 1] >= half) ++i;
    const double right =
        i + 1 < r.D.size() ? r.X[i] + (r.X[i + 1] - r.X[i]) * (r.D[i] - half) / (r.D[i] - r.D[i + 1])
                           : r.X.back();
    r.width = right - left;
  }
  (void)lo;
  (void)hi;
  const auto w = solid.work(sim);
  r.work = w[0];
  r.balance = std::abs(balanceOf(solid, sim) - balance0) / std::abs(w[0]);
  r.wall = clock.seconds();
  if (std::getenv("PORESPH_DAMAGE_BAR_PROFILE")) {
    std::printf("# n %d 2h %g: X D\n", n, lambda);
    for (size_t i = 0; i < r.X.size(); ++i)
      if (r.D[i] > 0.0) std::printf("%g %g\n", r.X[i], r.D[i]);
  }
  return r;
}

}  // namespace

TEST(DamageBar, LocalisesAtTheCentreAfterTheWavesMeetWidthFollows2h) {
  const double c = std::sqrt(E / rho);
  const double lambda = 5e-3;
  std::vector<BarRun> runs;
  const BarRun elastic = run(201, lambda, false);
  std::printf("without damage (201 points): balance %.2e of the work\n", elastic.balance);
  for (int n : {101, 151, 201}) {
    runs.push_back(run(n, lambda));
    const BarRun& r = runs.back();
    std::printf("n = %d: first damage t c / L = %.3f at |x| = %.2f mm, width %.2f mm (2h = 5), "
                "D max %.3f, |x| max %.2f mm, balance %.2e of work %.3g J, %ld steps, %.2f s\n",
                n, r.firstDamageTime * c / L, 1e3 * r.firstDamageX, 1e3 * r.width, r.dmax,
                1e3 * r.maxDistance, r.balance, r.work, r.steps, r.wall);
    EXPECT_GT(r.firstDamageTime, L / c) << "damage before the waves meet";
    EXPECT_LE(r.maxDistance, lambda) << "damage away from the centre";
    EXPECT_GT(r.dmax, 0.0);
    EXPECT_LT(std::abs(r.width - lambda) / lambda, 0.30);
    EXPECT_LT(r.balance, 0.01);
    const std::string res = std::to_string(n) + " points, 2h = 5 mm, TL, AV 10/1, dt = 0.5 x Eq. 2.50";
    test::recordValidation({"damage_bar_" + std::to_string(n), "damaged width at t = 3L/(2c) [m]",
                            r.width, lambda, std::abs(r.width - lambda) / lambda, res, r.wall,
                            "within 30 % of 2h", "thesis Sec. 4.2.1, Fig. 4.6 (width ~ 2h)"});
    test::recordValidation({"damage_bar_" + std::to_string(n),
                            "first damage time / (L/c) (waves meet at 1)",
                            r.firstDamageTime * c / L, 1.0,
                            std::abs(r.firstDamageTime * c / L - 1.0), res, r.wall, "> 1",
                            "Bazant & Belytschko via thesis Sec. 4.2"});
    test::recordValidation({"damage_bar_" + std::to_string(n),
                            "energy balance residual / boundary work", r.balance, 0.0, r.balance,
                            res, r.wall, "< 1 % (issue: 1 %)", "Eqs. 4.25-4.26 with the boundary work"});
  }
  double wmin = 1e9, wmax = 0.0;
  for (const auto& r : runs) {
    wmin = std::min(wmin, r.width);
    wmax = std::max(wmax, r.width);
  }
  const double spread = (wmax - wmin) / wmin;
  EXPECT_LT(spread, 0.20);
  test::recordValidation({"damage_bar_resolution", "damaged width spread (max - min) / min, 101/151/201",
                          spread, 0.0, spread, "101, 151, 201 points, 2h = 5 mm", 0.0, "< 20 %",
                          "thesis Sec. 4.2.1 (width independent of the point density)"});
}

TEST(DamageBar, WidthGrowsWith2h) {
  const double c = std::sqrt(E / rho);
  double previous = 0.0;
  for (double lambda : {5e-3, 10e-3, 20e-3}) {
    const BarRun r = run(201, lambda);
    std::printf("2h = %.0f mm: width %.2f mm, D max %.3f, first damage t c / L = %.3f, balance %.2e, %.2f s\n",
                1e3 * lambda, 1e3 * r.width, r.dmax, r.firstDamageTime * c / L, r.balance, r.wall);
    EXPECT_GT(r.width, previous * 1.2);
    previous = r.width;
    test::recordValidation({"damage_bar_2h_" + std::to_string(static_cast<int>(std::lround(1e3 * lambda))) + "mm",
                            "damaged width at t = 3L/(2c) [m]", r.width, lambda,
                            std::abs(r.width - lambda) / lambda, "201 points", r.wall,
                            "grows with 2h (> 1.2 x the previous)", "thesis Sec. 4.2.2, Fig. 4.10"});
  }
}
