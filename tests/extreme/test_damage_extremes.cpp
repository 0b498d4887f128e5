// Extremes of the elasto-damage solid (issue 13): damage driven to s_l over a region, 2h from
// 1.25 to 20 mm, loading 10x faster than the validation bar, compressive crushing (Rankine /
// Mohr-Coulomb), Poisson ratio up to 0.45. Each run must stay finite (no NaN), keep
// 0 <= D <= s_l, keep a positive time step and pass the solid's health checks (damage range,
// J > 0, Mach).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "libcore/health.hpp"
#include "physics/solid/solid_scenes.hpp"

using namespace poresph;
using namespace poresph::solid;

namespace {

struct Outcome {
  double dmax = 0.0, dmin = 1.0;
  bool finite = true;
  double dtMin = 1e300;
  long clipped = 0;
  std::string health;
  double farthest = 0.0;  ///< bar: largest |X| of a damaged particle
};

void inspect(Simulation& sim, ElasticSolidModule& solid, Outcome& o) {
  const double* D = sim.store.data(sim.store.real("damage"));
  const double* x = sim.store.data(sim.store.position());
  const int d = sim.dimension();
  for (Index i = 0; i < sim.store.realCount(); ++i) {
    o.dmax = std::max(o.dmax, D[i]);
    o.dmin = std::min(o.dmin, D[i]);
    for (int c = 0; c < d; ++c) o.finite = o.finite && std::isfinite(x[i * d + c]);
    o.finite = o.finite && std::isfinite(D[i]);
  }
  o.finite = o.finite && std::isfinite(solid.elasticEnergy(sim)) &&
             std::isfinite(solid.damageDissipation(sim));
  std::vector<HealthIssue> issues;
  solid.checkHealth(sim, HealthLimits{}, issues);
  if (!issues.empty() && o.health.empty()) o.health = issues.front().check + ": " + issues.front().detail;
  o.clipped = solid.clippedDamageUpdates();
}

// 1D bar of Tab. 4.1 pulled at +-v, support 2h; driven layers one support deep.
Outcome bar(double v, double lambda, int n = 201,
           const std::string& formulation = "total_lagrangian") {
  Simulation sim(1);
  addMaterial(sim, "bar", "elastic",
              "{density: 1550, young_modulus: 70.8e9, formulation: " + formulation + ", "
              "artificial_viscosity: {alpha: 10, beta: 1}, "
              "damage: {law: pcw, strain_onset: 0.022, strain_ultimate: 0.060}}");
  const double L = 0.1, dx = 2 * L / (n - 1);
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 1, 0.5 * lambda);
  sim.store.addParticles(n);
  double* x = sim.store.data(sim.store.position());
  for (int i = 0; i < n; ++i) x[i] = -L + i * dx;
  sim.domain.lo = {-1, 0, 0};
  sim.domain.hi = {1, 1, 1};
  char sec[512];
  std::snprintf(sec, sizeof sec,
                "{boundaries: [{name: l, type: velocity, velocity: [%g], box: {min: [-1], max: [%.9g]}}, "
                "{name: r, type: velocity, velocity: [%g], box: {min: [%.9g], max: [1]}}]}",
                -v, -L + std::max(lambda, dx) - 0.25 * dx, v, L - std::max(lambda, dx) + 0.25 * dx);
  ElasticSolidModule& solid = addSolidModule(sim, sec);
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double tEnd = 1.5 * L / std::sqrt(70.8e9 / 1550);
  Outcome o;
  while (sim.time < tEnd * (1 - 1e-9)) {
    const double dt = std::min(0.5 * solid.timeStepLimit(sim), tEnd - sim.time);
    o.dtMin = std::min(o.dtMin, dt);
    integrator->step(sim, dt);
  }
  inspect(sim, solid, o);
  const double* D = sim.store.data(sim.store.real("damage"));
  const double* X = sim.store.data(sim.store.real("reference_position"));
  for (Index i = 0; i < sim.store.realCount(); ++i)
    if (D[i] > 0.0) o.farthest = std::max(o.farthest, std::abs(X[i]));
  return o;
}

// 2D block (plane strain) squeezed along y between a clamped bottom layer and a top layer moved
// by uTop over `ramp` seconds; law given.
Outcome block(const std::string& law, double nu, double uTop, double rampCrossings) {
  Simulation sim(2);
  const double E = 3e9, rho = 2000, dx = 1e-3, Lb = 20e-3;
  char mat[512];
  std::snprintf(mat, sizeof mat,
                "{density: %g, young_modulus: %g, poisson_ratio: %g, formulation: total_lagrangian, "
                "hourglass: 1, damping: 2e4, damage: %s}",
                rho, E, nu, law.c_str());
  addMaterial(sim, "rock", "elastic", mat);
  const int n = static_cast<int>(Lb / dx);
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 1.25 * dx);
  buildBlock<2>(sim, Vec<2>(0, 0), {n, n, 1}, dx, 0);
  sim.domain.lo = {-0.1, -0.1, 0};
  sim.domain.hi = {0.1, 0.1, 1};
  const double c = std::sqrt(E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / rho);
  const double ramp = rampCrossings * Lb / c;
  char sec[512];
  std::snprintf(sec, sizeof sec,
                "{boundaries: [{name: bottom, type: clamped, box: {min: [-1, -1], max: [1, %.9g]}}, "
                "{name: top, type: displacement, displacement: [0, %.9g], ramp_time: %.9g, "
                "box: {min: [-1, %.9g], max: [1, 1]}}]}",
                2.5 * dx, uTop, ramp, Lb - 2.5 * dx);
  ElasticSolidModule& solid = addSolidModule(sim, sec);
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  Outcome o;
  while (sim.time < ramp * (1 - 1e-9)) {
    const double dt = std::min(0.5 * solid.timeStepLimit(sim), ramp - sim.time);
    o.dtMin = std::min(o.dtMin, dt);
    integrator->step(sim, dt);
  }
  inspect(sim, solid, o);
  return o;
}

void expectSane(const Outcome& o, double limit = 0.99) {
  EXPECT_TRUE(o.finite);
  EXPECT_GE(o.dmin, 0.0);
  EXPECT_LE(o.dmax, limit);
  EXPECT_GT(o.dtMin, 0.0);
  EXPECT_TRUE(o.health.empty()) << o.health;
}

}  // namespace

TEST(DamageExtremes, TenTimesFasterLoadingDrivesARegionToTheLimit) {
  // v = 700 m/s: v / c = 0.10, beyond eps_u in the first wave: the driven ends break at once
  const Outcome o = bar(700.0, 5e-3);
  std::printf("v = 700 m/s: D max %.3f, clipped updates %ld, dt min %.3g s\n", o.dmax, o.clipped, o.dtMin);
  expectSane(o);
  EXPECT_DOUBLE_EQ(o.dmax, 0.99);
  EXPECT_GT(o.clipped, 0);
}

TEST(DamageExtremes, SupportFrom1p25To20mm) {
  for (double lambda : {1.25e-3, 20e-3}) {
    SCOPED_TRACE(lambda);
    // 2h = 1.25 mm needs dx <= 0.5 mm for h/dx >= 1.25: 401 points
    const Outcome o = bar(70.0, lambda, lambda < 2e-3 ? 401 : 201);
    std::printf("2h = %.2f mm: D max %.3f, dt min %.3g s\n", 1e3 * lambda, o.dmax, o.dtMin);
    expectSane(o);
  }
}

TEST(DamageExtremes, CompressiveCrushingMohrCoulomb) {
  // 5 % shortening of a block, Mohr-Coulomb onset at 0.5 %: crushes to s_l
  const Outcome o = block("{law: rankine_mohr_coulomb, tensile_strain_onset: 0.0013, "
                          "tensile_strain_ultimate: 0.0026, compressive_strain_onset: 0.005, "
                          "friction_angle: 25}",
                          0.1, -1e-3, 10);
  std::printf("crushing: D max %.3f, clipped %ld, dt min %.3g s\n", o.dmax, o.clipped, o.dtMin);
  expectSane(o);
  EXPECT_GT(o.dmax, 0.5);
}

TEST(DamageExtremes, PoissonRatio0p45) {
  // nearly incompressible AT-1 under 2 % shortening: the shear is degraded, the bulk kept
  const Outcome o = block("{law: at1, strain_onset: 0.0013}", 0.45, -4e-4, 10);
  std::printf("nu = 0.45: D max %.3f, dt min %.3g s\n", o.dmax, o.dtMin);
  expectSane(o);
  EXPECT_GT(o.dmax, 0.0);
}

TEST(DamageExtremes, SmallStrainStressFormCarriesDamage) {
  // the same softening bar with the small-strain stress form (sigma from eps, Eq. 2.84 -> 4.18a):
  // damage appears, at the centre only, and stays sane
  const Outcome o = bar(70.0, 5e-3, 201, "small_strain_stress");
  std::printf("small strain: D max %.3f, farthest damaged |X| %.1f mm, dt min %.3g s\n", o.dmax,
              1e3 * o.farthest, o.dtMin);
  expectSane(o);
  EXPECT_GT(o.dmax, 0.0);
  EXPECT_LE(o.farthest, 5e-3);
}
