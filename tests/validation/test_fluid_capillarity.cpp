// Validation (issue 14): surface tension at a large density ratio and a background pressure
// that no longer stiffens the interface.
//  - Static 2D drop of water in gas (density ratio 1000, viscosity ratio 100, Hu-Adams pressure
//    gradient, background pressure 100 Pa, R/dx = 10): Laplace jump gamma / R within 5 %. Before
//    issue 14 the jump was +20.2 % (+6.5 % at p_b = 0): the curvature was that of the heavy
//    side's band (the density-weighted normal left the gas without a reliable normal).
//  - Oscillating drop (mode 2, R/dx = 10, box 3R, mu = 0.01 Pa s) with `pressure_reference:
//    background` and `transport_velocity`: the period depends much less on the background
//    pressure: at 150 and 300 Pa it is -1.7 % and +1.2 % off (2.9 % apart, asserted < 4.5 %);
//    with p_b in the pressure force (Eq. 5.2b) it is 5.8 % and 14.8 % short (9 % apart). With
//    the transport velocity p_b must stay well above the Laplace pressure (at 100 Pa = 3 gamma/R
//    the period came out 15.6 % short: the gauge pressure outside the drop is negative and the
//    regularisation too weak).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "tests/support/fluid_drop.hpp"
#include "tests/support/oscillating_droplet.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

TEST(FluidCapillarity, LaplaceJumpDensityRatio1000) {
  test::Stopwatch clock;
  test::FluidDrop::Params p;
  p.dim = 2;
  p.rOverDx = 10;
  p.rhoLiquid = 1000, p.muLiquid = 0.1, p.cLiquid = 2.0;  // water-like drop, Oh = 0.37
  p.rhoGas = 1, p.muGas = 1e-3, p.cGas = 20.0;            // gas: density 1, viscosity ratio 100
  p.backgroundPressure = 100.0;                            // ~3 gamma/R: every pressure positive
  p.extra = ", pressure_gradient: hu_adams";
  test::FluidDrop d(p);
  const double tEnd = 0.008;
  const test::FluidDrop::Measurement m = d.settleAndMeasure(0.003, tEnd, d.B / p.cLiquid);
  const double ref = p.gamma / p.R, err = std::abs(m.dpMean - ref) / ref;
  const double ca = p.muLiquid * m.speedMean / p.gamma, caRms = p.muLiquid * m.rmsMean / p.gamma;
  double rl, rg;
  d.extent(rl, rg);
  const double wall = clock.seconds();
  std::printf("density ratio 1000, R/dx 10: jump %.3f Pa vs %.3f (%+.2f %%, swing %.2f %%), spurious Ca (mu_l u_max / "
              "gamma) %.2e, rms %.2e, liquid <= %.3f R, gas >= %.3f R, %ld steps, %.1f s\n",
              m.dpMean, ref, 100 * (m.dpMean - ref) / ref, 100 * (m.dpMax - m.dpMin) / ref, ca, caRms, rl / p.R,
              rg / p.R, m.steps, wall);
  EXPECT_LT(err, 0.05);
  EXPECT_LT(rl, p.R + 2 * d.dx);
  EXPECT_GT(rg, p.R - 2 * d.dx);
  EXPECT_LT(ca, 2e-2);  // measured 9e-3 (1.3e-2 before issue 14)
  const std::string res = "2D, R/dx = 10, periodic box 3R, quintic h = dx, density ratio 1000, viscosity ratio 100, "
                          "hu_adams, p_b = 100 Pa, c = 2 / 20 m/s, t = 8 ms, " + std::to_string(m.steps) + " steps";
  test::recordValidation({"fluid_static_droplet_2d_ratio1000", "Laplace pressure jump (Pa)", m.dpMean, ref, err, res,
                          wall, "< 5 %", "Young-Laplace gamma / R (Eq. 1.5)"});
  test::recordValidation({"fluid_static_droplet_2d_ratio1000",
                          "spurious-current capillary number mu_l u_max / gamma (window mean)", ca, 0.0, ca, res, wall,
                          "< 2e-2", "0 (exact solution at rest)"});
}

TEST(FluidCapillarity, OscillationPeriodIndependentOfBackgroundPressure) {
  using namespace poresph::oscdrop;
  test::Stopwatch clock;
  const double rdx = 10, boxR = 3, mu = 0.01, eps = 0.08, c = 2, periods = 2.5;
  const double R0 = 1.5e-3, rho = 1000, gamma = 0.05;
  const auto nominal = ref::viscousMode(2, R0, rho, mu, rho, mu, gamma, boxR * R0);
  const double tRef = 2 * kPi / nominal.omega;
  const char* tvf = ", pressure_reference: background, transport_velocity: true";
  const DropletRun a = runDroplet(rdx, boxR, mu, 150.0, eps, c, periods, tRef, tvf);
  const DropletRun b = runDroplet(rdx, boxR, mu, 300.0, eps, c, periods, tRef, tvf);
  const auto m = ref::viscousMode(2, a.R, rho, mu, rho, mu, gamma, boxR * R0);
  const double Tref = 2 * kPi / m.omega, Ta = 2 * kPi / a.omega, Tb = 2 * kPi / b.omega;
  const double spread = std::abs(Ta - Tb) / Tref, errA = std::abs(Ta - Tref) / Tref, errB = std::abs(Tb - Tref) / Tref;
  const double wall = clock.seconds();
  std::printf("oscillating drop, transport velocity: period %.5e s (p_b 150) / %.5e s (p_b 300) vs %.5e s: errors "
              "%.2f / %.2f %%, spread %.2f %%; damping %.1f / %.1f 1/s vs %.1f; %.1f s\n",
              Ta, Tb, Tref, 100 * errA, 100 * errB, 100 * spread, a.beta, b.beta, m.beta, wall);
  EXPECT_LT(spread, 0.045);  // measured 2.9 %; with p_b in the force: 9 % apart
  EXPECT_LT(errA, 0.05);
  EXPECT_LT(errB, 0.05);
  EXPECT_LT(a.rms, 0.1 * a.amp);
  EXPECT_LT(b.rms, 0.1 * b.amp);
  const std::string res = "2D, R/dx = 10, periodic box 3R, mu = 0.01 Pa s, amplitude 8 %, c = 2 m/s, "
                          "pressure_reference: background, transport_velocity, p_b = 150 and 300 Pa";
  const std::string src = "linear viscous normal mode in the box (tests/support/oscillating_droplet.hpp)";
  test::recordValidation({"fluid_oscillating_droplet_background_pressure", "mode-2 period spread between p_b = 150 "
                          "and 300 Pa / reference period", spread, 0.0, spread, res, wall, "< 4.5 % (9 % with p_b in the force)", src});
  test::recordValidation({"fluid_oscillating_droplet_background_pressure", "period of mode 2 at p_b = 300 Pa (s)", Tb,
                          Tref, errB, res, wall, "< 5 %", src});
}
