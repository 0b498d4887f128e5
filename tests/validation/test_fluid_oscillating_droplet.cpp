// Validation: oscillating 2D droplet, mode 2, against the Rayleigh-Lamb law in 2D:
//   omega^2 = (n^3 - n) gamma / ((rho_in + rho_out) R^3),  n = 2
// (inviscid; the Ohnesorge number here is 0.04, so the viscous frequency shift is < 1 %).
//
// Disabled (marginal): with zero background pressure the gas pressure is negative (-gamma/R / 2),
// the tensile instability of Eq. 5.2b disorders the particles and the oscillation is irregular
// (period ~0.045-0.05 s against 0.030 s, amplitude growing in a 5R box). With
// background_pressure: 100 Pa (all pressures positive) the oscillation is regular and the period
// is 0.0329 s against 0.0301 s (9.4 %) in a 3R box but 0.0343 s against 0.0300 s (14.3 %) in a
// 4R box (FLUID_BOX=4): the 10 % of issue 5 is not met robustly, so the test stays disabled.
// Run with --gtest_also_run_disabled_tests; FLUID_DEBUG=1 prints the mode-2 amplitude a(t).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

TEST(FluidOscillatingDroplet, DISABLED_Mode2FrequencyRayleighLamb2D) {
  test::Stopwatch clock;
  constexpr double kPi = 3.14159265358979323846;
  Simulation sim(2);
  const double R0 = 1.5e-3, dx = R0 / 15, B = (std::getenv("FLUID_BOX") ? std::atof(std::getenv("FLUID_BOX")) : 3.0) * R0, gamma = 0.05, rho = 1000.0, eps = 0.08;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {B, B, 0};
  sim.domain.periodic = {true, true, false};
  const int liq = fs::addMaterial(sim, "liquid", "fluid", "{density: 1000, sound_speed: 2, viscosity: 0.01, colour: 1, background_pressure: 100}");
  const int gas = fs::addMaterial(sim, "gas", "fluid", "{density: 1000, sound_speed: 2, viscosity: 0.01, colour: -1, background_pressure: 100}");
  FluidModule* fluid = fs::addFluidModule(sim, "{surface_tension: 0.05}");
  auto inside = [&](const double* x) {
    const double X = x[0] - 0.5 * B, Y = x[1] - 0.5 * B;
    return std::hypot(X, Y) < R0 * (1.0 + eps * std::cos(2.0 * std::atan2(Y, X)));
  };
  const Index nLiq = fs::addLattice(sim, {0, 0}, {B, B}, liq, inside);
  fs::addLattice(sim, {0, 0}, {B, B}, gas, [&](const double* x) { return !inside(x); });
  fluid->initialise(sim);
  const double R = std::sqrt(static_cast<double>(nLiq) * dx * dx / kPi);  // equal-area radius
  const double omega = std::sqrt(6.0 * gamma / (2.0 * rho * R * R * R));
  const double period = 2 * kPi / omega;
  // mode-2 amplitude from the second moments of the liquid about its centroid
  auto amplitude = [&]() {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* col = st.data(fluid->colour);
    double cx = 0, cy = 0, n = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (col[i] > 0) cx += x[2 * i], cy += x[2 * i + 1], n += 1;
    cx /= n;
    cy /= n;
    double a = 0, b = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (col[i] > 0) {
        const double X = x[2 * i] - cx, Y = x[2 * i + 1] - cy;
        a += X * X - Y * Y;
        b += X * X + Y * Y;
      }
    return a / b;
  };
  fs::Stepper stepper;
  std::vector<double> crossings;
  double prevA = amplitude(), prevT = 0.0;
  const double a0 = prevA;
  while (sim.time < (std::getenv("FLUID_DEBUG") ? 3.0 : 1.6) * period && crossings.size() < 3) {
    stepper.step(sim);
    const double a = amplitude();
    if (std::getenv("FLUID_DEBUG") && sim.step % 200 == 0) std::printf("t %.4e a %.5f\n", sim.time, a);
    if ((a > 0) != (prevA > 0))  // linear interpolation of the zero crossing
      crossings.push_back(prevT + (sim.time - prevT) * prevA / (prevA - a));
    prevA = a;
    prevT = sim.time;
  }
  ASSERT_GE(crossings.size(), 3u) << "no oscillation: amplitude " << a0 << " -> " << prevA;
  const double measured = crossings[2] - crossings[0];  // one full period
  const double err = std::abs(measured - period) / period;
  const double wall = clock.seconds();
  std::printf("mode 2: period %.4e s (Rayleigh-Lamb %.4e s), error %.2f %%, amplitude %.4f -> crossings at %.4e %.4e %.4e, %lld steps, %.1f s\n",
              measured, period, 100 * err, a0, crossings[0], crossings[1], crossings[2],
              static_cast<long long>(sim.step), wall);
  EXPECT_LT(err, 0.10);
  test::recordValidation({"fluid_oscillating_droplet_2d", "period of mode 2 (s)", measured, period, err,
                          "R/dx = 15, periodic box 3R, quintic h = dx, equal densities, Oh = 0.04, amplitude 8 %",
                          wall, "< 10 %", "Rayleigh-Lamb, 2D: omega^2 = 6 gamma / ((rho_i + rho_o) R^3)"});
}
