// Validation item 5 of issue 13: a pressurised circular pore in a damageable clay disc (the
// drainage mechanism in its simplest form: the pore pressure as a load on the pore wall).
// Disc a <= r <= b = 3a, plane strain, COx data of Table 5.1 (E = 3 GPa, nu = 0.1) with the PCW
// law of App. B / Eq. 5.9 (eps_0 = 0.0013, eps_u = 0.0026, Yc0 from the peak at eps_0), total
// Lagrangian with hourglass control, body-fitted rings, the pore pressure ramped slowly with
// viscous damping (quasi-static). Lame's thick cylinder gives at the wall sigma_rr = -p,
// sigma_tt = p (b^2 + a^2) / (b^2 - a^2): the maximum principal stress is largest there, and the
// law's criterion psi+(eps(p)) = Yc0 / (1 + b) gives the pressure at onset in closed form.
// Asserted: damage starts at the pore wall (first damaged particle in the first ring), the
// pressure at onset within 10 % of the Lame prediction, the damage rotationally uniform at onset.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>

#include "physics/solid/solid_scenes.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using namespace poresph::solid;

TEST(DamagePore, OnsetAtTheWallAtTheLamePressure) {
  test::Stopwatch clock;
  const double E = 3e9, nu = 0.1, rho = 2300, dx = 1e-3, a = 12 * dx, b = 3 * a;
  const std::string law = "{law: pcw, strain_onset: 0.0013, strain_ultimate: 0.0026}";
  // closed form: eps at r = a from Lame (plane strain), psi+ by the law itself
  double lam = 0.0, mu = 0.0;
  lameParameters(E, nu, 2, Plane::Strain, lam, mu);
  ConstitutiveLaw cl(E, lam, mu, 3);
  cl.configureDamage(ParameterSet(YAML::Load(law), "test", "damage"));
  const double k = (b * b + a * a) / (b * b - a * a);
  const double sr = -1.0, st = k;  // per unit pressure
  Mat<2> eps = Mat<2>::Zero();
  eps(0, 0) = (1 + nu) / E * ((1 - nu) * sr - nu * st);
  eps(1, 1) = (1 + nu) / E * ((1 - nu) * st - nu * sr);
  const double pOnset = std::sqrt(cl.onsetEnergy() / cl.psiPlus(cl.split<2>(eps)));
  // the same at the radius of the first ring of particles, r1 = a + dx/2 (what the particles
  // next to the wall carry): sigma = p a^2 / (b^2 - a^2) (1 -+ b^2 / r^2)
  const double r1 = a + 0.5 * 1e-3;
  const double f = a * a / (b * b - a * a);
  Mat<2> eps1 = Mat<2>::Zero();
  {
    const double s1r = f * (1 - b * b / (r1 * r1)), s1t = f * (1 + b * b / (r1 * r1));
    eps1(0, 0) = (1 + nu) / E * ((1 - nu) * s1r - nu * s1t);
    eps1(1, 1) = (1 + nu) / E * ((1 - nu) * s1t - nu * s1r);
  }
  const double pOnsetRing = std::sqrt(cl.onsetEnergy() / cl.psiPlus(cl.split<2>(eps1)));

  Simulation sim(2);
  char mat[400];
  std::snprintf(mat, sizeof mat,
                "{density: %g, young_modulus: %g, poisson_ratio: %g, formulation: total_lagrangian, "
                "hourglass: 1, damping: %g, damage: %s}",
                rho, E, nu, 0.0, law.c_str());
  // damping ~ the lowest (breathing) mode, omega ~ c_p / b
  const double c = std::sqrt((lam + 2 * mu) / rho);
  std::snprintf(mat, sizeof mat,
                "{density: %g, young_modulus: %g, poisson_ratio: %g, formulation: total_lagrangian, "
                "hourglass: 1, damping: %g, damage: %s}",
                rho, E, nu, c / b, law.c_str());
  addMaterial(sim, "clay", "elastic", mat);
  std::vector<double> xy, vol;
  const int rings = static_cast<int>(std::lround((b - a) / dx));
  appendRings(a, dx, rings, xy, vol);
  const Index np = static_cast<Index>(vol.size());
  sim.store.addParticles(np);
  double* x = sim.store.data(sim.store.position());
  double* m = sim.store.data(sim.store.mass());
  for (Index i = 0; i < np; ++i) {
    x[2 * i] = xy[static_cast<size_t>(2 * i)];
    x[2 * i + 1] = xy[static_cast<size_t>(2 * i + 1)];
    m[i] = rho * vol[static_cast<size_t>(i)];
  }
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::CubicSpline, 2, 1.3 * dx);
  sim.domain.lo = {-2 * b, -2 * b, 0};
  sim.domain.hi = {2 * b, 2 * b, 1};
  const double pMax = 1.3 * pOnset;
  const double ramp = 40.0 * b / c;
  char sec[400];
  std::snprintf(sec, sizeof sec,
                "{boundaries: [{name: pore, type: pressure, pressure: %.9g, ramp_time: %.9g, "
                "shell: {centre: [0, 0], r_min: 0, r_max: %.9g}}]}",
                pMax, ramp, a + sim.kernel.support());
  ElasticSolidModule& solid = addSolidModule(sim, sec);
  solid.initialise(sim);
  auto integrator = makeIntegrator("leapfrog");
  const double dt = 0.5 * solid.elasticTimeStepLimit(sim);
  const double* X = sim.store.data(sim.store.real("reference_position"));
  double pFirst = -1.0, rFirst = 0.0, spread = 0.0;
  long steps = 0;
  while (sim.time < ramp * (1 - 1e-9) && pFirst < 0.0) {
    integrator->step(sim, std::min(dt, ramp - sim.time));
    ++steps;
    const double* D = sim.store.data(sim.store.real("damage"));
    for (Index i = 0; i < np; ++i)
      if (D[i] > 0.0) {
        pFirst = pMax * sim.time / ramp;
        rFirst = std::hypot(X[2 * i], X[2 * i + 1]);
        break;
      }
    if (pFirst > 0.0) {
      // uniformity: fraction of the first ring damaged at onset
      int ring = 0, hit = 0;
      for (Index i = 0; i < np; ++i)
        if (std::hypot(X[2 * i], X[2 * i + 1]) < a + dx) {
          ++ring;
          hit += D[i] > 0.0;
        }
      spread = static_cast<double>(hit) / ring;
    }
  }
  const double secsOnset = clock.seconds();
  // past the onset to the end of the ramp (1.3 x the wall prediction): the energy balance with
  // the damage growing (Eq. 4.25: kinetic + stored + hourglass + damped + released = work of the
  // pore pressure), asserted within 1 % of the work (issue 13: "the balance closes to 1 % in
  // every validation"), with a released energy well above that tolerance
  while (sim.time < ramp * (1 - 1e-9)) {
    integrator->step(sim, std::min(dt, ramp - sim.time));
    ++steps;
  }
  const auto w = solid.work(sim);
  const double released = solid.damageDissipation(sim), workIn = w[0] + w[1];
  const double residual = solid.kineticEnergy(sim) + solid.elasticEnergy(sim) + solid.hourglassEnergy(sim) + w[2] +
                          released - workIn;
  int damagedEnd = 0;
  {
    const double* D = sim.store.data(sim.store.real("damage"));
    for (Index i = 0; i < np; ++i) damagedEnd += D[i] >= 0.5;
  }
  std::printf("end of the ramp (p = %.4g MPa, %ld steps): work %.5g J/m, released %.5g J/m (%.1f %%), damped %.5g, "
              "residual %.3g of the work, %d particles at D >= 0.5, %.1f s\n",
              1e-6 * pMax, steps, workIn, released, 100 * released / workIn, w[2], residual / workIn, damagedEnd,
              clock.seconds());
  EXPECT_LT(std::abs(residual) / workIn, 0.01) << "energy balance at the end of the ramp";
  EXPECT_GT(released / workIn, 0.05) << "the check needs damage that released energy";
  test::recordValidation({"damage_pressurised_pore", "energy balance residual / work of the pore pressure, end of the ramp (1.3 x onset)",
                          std::abs(residual) / workIn, 0.0, std::abs(residual) / workIn,
                          "disc a = 12 dx, b = 3a, body-fitted rings, h = 1.3 dx, TL + hourglass 1",
                          clock.seconds(), "< 1 %", "Eq. 4.25 (with 4.26: released energy)"});
  const double err = std::abs(pFirst - pOnset) / pOnset;
  const double errRing = std::abs(pFirst - pOnsetRing) / pOnsetRing;
  std::printf("Lame onset p = %.4g MPa at the wall, %.4g MPa at the first ring; SPH: first damage at "
              "p = %.4g MPa (%.1f %% / %.1f %%), r = %.2f a, first ring damaged %.0f %%, %ld particles, "
              "%ld steps, %.1f s\n",
              1e-6 * pOnset, 1e-6 * pOnsetRing, 1e-6 * pFirst, 100 * err, 100 * errRing, rFirst / a,
              100 * spread, static_cast<long>(np), steps, clock.seconds());
  EXPECT_LT(errRing, 0.05);
  test::recordValidation({"damage_pressurised_pore", "pore pressure at onset vs Lame at the first ring [Pa]",
                          pFirst, pOnsetRing, errRing,
                          "disc a = 12 dx, b = 3a, body-fitted rings, h = 1.3 dx, TL + hourglass 1",
                          secsOnset, "< 5 %",
                          "Lame thick cylinder at r = a + dx/2 + the PCW criterion (Eqs. 4.19, 5.9)"});
  ASSERT_GT(pFirst, 0.0) << "no damage up to 1.3 x the predicted pressure";
  EXPECT_LT(rFirst, a + dx) << "damage must start in the first ring (the pore wall)";
  EXPECT_LT(err, 0.10);
  test::recordValidation({"damage_pressurised_pore", "pore pressure at damage onset [Pa]", pFirst,
                          pOnset, err,
                          "disc a = 12 dx, b = 3a, body-fitted rings, h = 1.3 dx, TL + hourglass 1",
                          secsOnset, "< 10 %",
                          "Lame thick cylinder + the PCW criterion (Eqs. 4.19, 5.9)"});
}
