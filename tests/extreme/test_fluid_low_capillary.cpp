// Extreme (issue 5): very low capillary number, where spurious currents dominate - report them,
// do not hide them. A 2D water-like droplet (rho 1000, mu 1e-3 Pa s in both phases, gamma =
// 0.05 N/m, R = 1.5 mm: Laplace number rho gamma R / mu^2 = 75 000, Ohnesorge 3.7e-3) translates
// with the surrounding fluid at U in a periodic box 3R (imposed flow: every particle starts with
// velocity U e_x). The imposed-flow capillary number is Ca = mu U / gamma = 1e-4 (U = 5 mm/s).
// The exact solution is the drop at rest in the frame moving with U; every deviation from it is
// a spurious current. Checked: the run stays finite and stable for 3 capillary times
// sqrt(rho R^3 / gamma) (6600 steps), the drop stays intact and round about its centroid, it is
// carried with the flow (liquid centroid displacement = U t within 0.2 dx; measured equal to 4
// digits: the CSF force has no net resultant on the drop), the mean velocity stays U, the density
// variation stays small. Printed and recorded: the largest spurious speed |v - U e_x| relative to
// U (measured: time mean 9, peak 19 - the spurious currents are an order of magnitude larger
// than the imposed flow; as a capillary number ~1e-3). FLUID_LOW_CA=<Ca> overrides the imposed
// capillary number for manual studies (the spurious speed does not depend on it: at 1e-6 the
// same 1.93e-3 as a capillary number, i.e. 1933 U).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "tests/support/fluid_drop.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

TEST(FluidExtreme, LowCapillaryNumberTranslatingDroplet) {
  test::Stopwatch clock;
  test::FluidDrop::Params p;
  p.dim = 2;
  p.rOverDx = 10;
  p.muLiquid = p.muGas = 1e-3;
  p.cLiquid = p.cGas = 10.0;  // >> the spurious speeds (~0.1 m/s): density variation ~0.2 %
  const double caImposed = std::getenv("FLUID_LOW_CA") ? std::atof(std::getenv("FLUID_LOW_CA")) : 1e-4;
  const double U = caImposed * p.gamma / p.muLiquid;  // 5 mm/s
  test::FluidDrop d(p);
  auto& st = d.sim.store;
  const Index n = d.count();
  {
    double* v = st.data(st.velocity());
    for (Index i = 0; i < n; ++i) v[i * 2] = U, v[i * 2 + 1] = 0.0;
  }
  auto liquidCentroidX = [&]() {
    const double* x = st.data(st.position());
    const double* col = st.data(d.fluid->colour);
    double s = 0, c = 0;
    for (Index i = 0; i < n; ++i)
      if (col[i] > 0) s += x[i * 2], c += 1;
    return s / c;
  };
  const double x0 = liquidCentroidX();
  const double tCap = std::sqrt(p.rhoLiquid * p.R * p.R * p.R / p.gamma);  // 8.2 ms
  const double tEnd = 3.0 * tCap;
  double spMax = 0, spSum = 0, varMax = 0, rlMax = 0, rgMin = 1e300;
  long samples = 0;
  while (d.sim.time < tEnd * (1 - 1e-12)) {
    d.stepper.step(d.sim, tEnd - d.sim.time);
    varMax = std::max(varMax, d.fluid->maxDensityVariation());
    if (d.sim.step % 50 != 0) continue;
    // spurious speed: largest |v - U e_x|
    const double* v = st.data(st.velocity());
    double m2 = 0;
    for (Index i = 0; i < n; ++i) {
      const double ux = v[i * 2] - U, uy = v[i * 2 + 1];
      m2 = std::max(m2, ux * ux + uy * uy);
    }
    spMax = std::max(spMax, std::sqrt(m2));
    spSum += std::sqrt(m2);
    ++samples;
    double rl, rg;
    d.extent(rl, rg);
    rlMax = std::max(rlMax, rl);
    rgMin = std::min(rgMin, rg);
  }
  d.sim.checkFinite();
  const double drift = liquidCentroidX() - x0;
  // mean velocity of all particles (equal masses): the imposed flow as the scheme carries it
  const double* v = st.data(st.velocity());
  double vmean = 0;
  for (Index i = 0; i < n; ++i) vmean += v[i * 2];
  vmean /= static_cast<double>(n);
  const double spMean = spSum / static_cast<double>(samples);
  const double wall = clock.seconds();
  std::printf("low capillary number: Ca_imposed = %.1e (U = %.2e m/s), La = %.0f, %lld particles, "
              "%lld steps, t = %.1f ms (%.1f capillary times)\n"
              "  spurious speed max |v - U| / U: largest %.2f, time mean %.2f (as Ca: %.2e / %.2e)\n"
              "  liquid centroid moved %.5e m vs U t = %.5e m; mean velocity of all particles %.4e m/s "
              "(%.2f U); liquid extent <= %.3f R, nearest gas >= %.3f R; max density variation %.3f %%; %.1f s\n",
              caImposed, U, p.rhoLiquid * p.gamma * p.R / (p.muLiquid * p.muLiquid),
              static_cast<long long>(n), static_cast<long long>(d.sim.step), 1e3 * d.sim.time,
              d.sim.time / tCap, spMax / U, spMean / U, p.muLiquid * spMax / p.gamma,
              p.muLiquid * spMean / p.gamma, drift, U * d.sim.time, vmean, vmean / U, rlMax / p.R,
              rgMin / p.R, 100 * varMax, wall);
  EXPECT_LT(rlMax, p.R + 2 * d.dx);   // intact: no liquid thrown out of the drop
  EXPECT_GT(rgMin, p.R - 2 * d.dx);   // no gas inside
  EXPECT_LT(varMax, 0.03);            // c large enough for the spurious speeds
  EXPECT_LT(std::abs(drift - U * d.sim.time), 0.2 * d.dx);  // carried with the flow
  EXPECT_NEAR(vmean, U, 0.1 * U);     // the imposed flow is not lost
  EXPECT_LT(p.muLiquid * spMax / p.gamma, 1e-2);  // bounded (measured 1.9e-3; the ratio to U is the finding)
  test::recordValidation({"fluid_low_capillary_translating_droplet_2d",
                          "time mean of the largest spurious speed / imposed speed U (Ca_imposed = 1e-4)", spMean / U, 0.0,
                          spMean / U,
                          "2D, R/dx = 10, La = 75000, periodic box 3R, c = 10 m/s, 3 capillary times",
                          wall, "reported (asserted: spurious Ca < 1e-2, drop intact, carried with U)",
                          "0 (drop at rest in the frame moving with U)"});
}
