// Validation: oscillating 2D droplet, mode 2 (issue 5): the period and damping rate of the
// mode-2 shape oscillation against the linear normal mode of a viscous drop in a viscous outer
// fluid inside the periodic box (reference and derivation: namespace ref of tests/support/oscillating_droplet.hpp).
//
// Why not the plain Rayleigh-Lamb law omega0^2 = (n^3 - n) gamma / ((rho_in + rho_out) R^3): it
// assumes an inviscid, unbounded outer fluid. With equal densities the outer fluid carries half
// the inertia, and (a) in a periodic box of side B its potential flow is confined (period +6.4 %
// at B = 3R, +1.9 % at 4R), (b) the vorticity layer at the interface lowers the frequency far more
// than the bulk damping suggests: +6.4 % (mu = 0.003 Pa s) and +11.5 % (mu = 0.01 Pa s) on the
// period in an unbounded fluid. The former disabled test compared 0.0329 s (3R box, mu = 0.01)
// with 0.0301 s; the correct reference there is 0.0362 s.
//
// Measured (docs/fluid.md): period 1.3 % off (R/dx = 15, 19 s single-threaded), 0.2-4.6 % over
// R/dx 10-20, boxes 3R-6R, amplitude 4-12 %, p_b 50-200 Pa and c = 4 m/s.
//
// Set-up: R = 1.5 mm, R/dx = 15, periodic box 4R, equal densities 1000 and viscosities
// 0.003 Pa s (Oh = 0.011), gamma = 0.05 N/m, c = 2 m/s (10x the capillary velocity
// sqrt(gamma/(rho R)) = 0.18 m/s, ~100x the largest oscillation speed), background pressure
// 100 Pa (3 gamma/R; keeps every pressure positive, see docs/fluid.md), quintic spline h = dx,
// r = R (1 + 0.08 cos 2 theta) at rest. The period and damping rate come from a least-squares fit
// of a(t) = c0 + e^{-beta t} (c1 cos wt + c2 sin wt) over 0.1 .. 2.5 reference periods, a(t) the
// mode-2 moment sum (X^2 - Y^2) / sum (X^2 + Y^2) of the liquid particles about their centroid.
//
// Environment (studies only): OSC_RDX, OSC_BOX (in R), OSC_MU, OSC_PB, OSC_EPS, OSC_C,
// OSC_PERIODS; OSC_DUMP=prefix writes a(t) and particle snapshots every quarter period.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tests/support/oscillating_droplet.hpp"

using namespace poresph;
using namespace poresph::oscdrop;

// The reference itself: limits that are known in closed form.
TEST(FluidOscillatingDroplet, ReferenceLimits) {
  // Drop in (almost) vacuum: omega -> omega0 of the free drop, beta -> 4 nu / R^2 (2D, n = 2).
  const double R = 1e-3, rho = 1000, gamma = 0.05, mu = 0.002;
  const auto free = ref::viscousMode(2, R, rho, mu, 1e-6 * rho, 1e-6 * mu, gamma, 0.0);
  const double w0 = std::sqrt(6 * gamma / (rho * R * R * R)), b0 = 4 * mu / (rho * R * R);
  EXPECT_NEAR(free.omega / w0, 1.0, 2e-3);
  EXPECT_NEAR(free.beta / b0, 1.0, 0.05);
  // Inviscid limit with equal fluids in a huge box: Rayleigh-Lamb with rho_in + rho_out.
  const auto inv = ref::viscousMode(2, R, rho, 1e-9, rho, 1e-9, gamma, 40 * R);
  EXPECT_NEAR(inv.boxFactor, 1.0, 1e-4);  // F - 1 ~ 2 (R/R_b)^4 ~ 1e-5 at B = 40R
  EXPECT_NEAR(inv.omega / std::sqrt(6 * gamma / (2 * rho * R * R * R)), 1.0, 1e-3);
  // Box factor of a square against the circle it is replaced with: F grows as the box shrinks
  // and lies between the inscribed and circumscribed circles' (1 + q)/(1 - q).
  for (double bh : {1.5, 2.0}) {
    const double F = ref::squareBoxFactor(2, bh);
    const double qi = std::pow(1 / bh, 4), qc = std::pow(1 / (bh * std::sqrt(2.0)), 4);
    EXPECT_LT(F, (1 + qi) / (1 - qi));
    EXPECT_GT(F, (1 + qc) / (1 - qc));
  }
}

TEST(FluidOscillatingDroplet, Mode2PeriodAndDampingViscousBox) {
  const double rdx = env("OSC_RDX", 15), boxR = env("OSC_BOX", 4), mu = env("OSC_MU", 0.003),
               pb = env("OSC_PB", 100), eps = env("OSC_EPS", 0.08), c = env("OSC_C", 2),
               periods = env("OSC_PERIODS", 2.5);
  const double R0 = 1.5e-3, rho = 1000, gamma = 0.05;
  // Reference period for the run length and the fit's start (nominal radius).
  const auto nominal = ref::viscousMode(2, R0, rho, mu, rho, mu, gamma, boxR * R0);
  const DropletRun run = runDroplet(rdx, boxR, mu, pb, eps, c, periods, 2 * kPi / nominal.omega);
  const double B = boxR * R0;
  const auto m = ref::viscousMode(2, run.R, rho, mu, rho, mu, gamma, B);  // at the equal-area radius
  const auto unbounded = ref::viscousMode(2, run.R, rho, mu, rho, mu, gamma, 0.0);
  const double T = 2 * kPi / run.omega, Tref = 2 * kPi / m.omega;
  const double Trl = 2 * kPi / std::sqrt(6 * gamma / (2 * rho * run.R * run.R * run.R));
  const double err = std::abs(T - Tref) / Tref, errBeta = std::abs(run.beta - m.beta) / m.beta;
  std::printf("R/dx %.1f box %gR mu %g pb %g eps %g c %g: period %.5e s, reference %.5e s (error %.2f %%); "
              "damping %.2f 1/s, reference %.2f (error %.1f %%)\n"
              "  [inviscid unbounded Rayleigh-Lamb %.5e s, inviscid box %.5e s, viscous unbounded %.5e s; "
              "fit rms %.1e, amplitude %.4f (a0 %.4f)] %lld steps, %.1f s\n",
              run.R / (R0 / rdx), boxR, mu, pb, eps, c, T, Tref, 100 * err, run.beta, m.beta, 100 * errBeta, Trl,
              2 * kPi / m.omegaInviscid, 2 * kPi / unbounded.omega, run.rms, run.amp, run.a0, run.steps, run.wall);
  EXPECT_LT(err, 0.10);
  // The fitted damping rate is much less robust than the period (9-25 1/s against 13.5 over the
  // variations in docs/fluid.md: the fit also absorbs the start transient and lattice noise), so
  // it is checked only to within a factor of 2 (no damping, or the over-damping of a too viscous
  // interface, fails).
  EXPECT_GT(run.beta, 0.5 * m.beta);
  EXPECT_LT(run.beta, 2.0 * m.beta);
  EXPECT_LT(run.rms, 0.1 * run.amp);  // the signal is a damped oscillation, not noise
  char res[400];
  std::snprintf(res, sizeof res, "R/dx = %g, periodic box %gR, quintic h = dx, equal densities and viscosities "
                "(mu %g Pa s, Oh %.3f), amplitude %g %%, p_b %g Pa, c %g m/s, %lld steps", rdx, boxR, mu,
                mu / std::sqrt(rho * gamma * R0), 100 * eps, pb, c, run.steps);
  const std::string src = "linear viscous normal mode in the box (2D Rayleigh-Lamb with outer fluid, "
                          "box added mass, interface vorticity layer; derivation in tests/support/oscillating_droplet.hpp)";
  test::recordValidation({"fluid_oscillating_droplet_2d", "period of mode 2 (s)", T, Tref, err, res, run.wall,
                          "< 10 %", src});
  test::recordValidation({"fluid_oscillating_droplet_2d", "damping rate of mode 2 (1/s)", run.beta, m.beta, errBeta,
                          res, run.wall, "within a factor 2", src});
}
