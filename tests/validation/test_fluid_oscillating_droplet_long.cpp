// Validation (label `long`): oscillating 2D droplet, mode 2 - the period against the linear
// viscous normal mode in the periodic box (see tests/support/oscillating_droplet.hpp and
// test_fluid_oscillating_droplet.cpp) at R/dx = 10, 15, 20 (box 4R) and in boxes 3R and 6R
// (R/dx = 15). Measured: 1.41 / 1.26 / 2.91 % and 0.97 / 2.58 %, ~150 s on one thread.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tests/support/oscillating_droplet.hpp"

using namespace poresph;
using namespace poresph::oscdrop;

namespace {
void study(double rdx, double boxR) {
  const double R0 = 1.5e-3, rho = 1000, gamma = 0.05, mu = 0.003, pb = 100, eps = 0.08, c = 2;
  const auto nominal = ref::viscousMode(2, R0, rho, mu, rho, mu, gamma, boxR * R0);
  const DropletRun run = runDroplet(rdx, boxR, mu, pb, eps, c, 2.5, 2 * kPi / nominal.omega);
  const auto m = ref::viscousMode(2, run.R, rho, mu, rho, mu, gamma, boxR * R0);
  const double T = 2 * kPi / run.omega, Tref = 2 * kPi / m.omega, err = std::abs(T - Tref) / Tref;
  std::printf("R/dx %g box %gR: period %.5e s, reference %.5e s, error %.2f %%; damping %.2f (reference %.2f) 1/s; "
              "%lld steps, %.1f s\n", rdx, boxR, T, Tref, 100 * err, run.beta, m.beta, run.steps, run.wall);
  EXPECT_LT(err, 0.10);
  EXPECT_GT(run.beta, 0.5 * m.beta);
  EXPECT_LT(run.beta, 2.0 * m.beta);
  char res[300], q[120];
  std::snprintf(res, sizeof res, "R/dx = %g, periodic box %gR, quintic h = dx, equal densities and viscosities "
                "(mu 0.003 Pa s), amplitude 8 %%, p_b 100 Pa, c 2 m/s, %lld steps", rdx, boxR, run.steps);
  std::snprintf(q, sizeof q, "period of mode 2 (s), R/dx %g, box %gR", rdx, boxR);
  test::recordValidation({"fluid_oscillating_droplet_2d_study", q, T, Tref, err, res, run.wall, "< 10 %",
                          "linear viscous normal mode in the box (derivation in tests/support/oscillating_droplet.hpp)"});
}
}  // namespace

TEST(FluidOscillatingDropletLong, PeriodOverResolution) {
  for (double rdx : {10.0, 15.0, 20.0}) study(rdx, 4.0);
}

TEST(FluidOscillatingDropletLong, PeriodOverBoxSize) {
  for (double box : {3.0, 6.0}) study(15.0, box);
}
