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
// U (measured: time mean 9.2, peak 19 - the spurious currents are an order of magnitude larger
// than the imposed flow; as a capillary number ~1e-3); the time mean is asserted below 11 U
// (issue 14), so that a regression fails. FLUID_LOW_CA=<Ca> overrides the imposed
// capillary number for manual studies (the spurious speed does not depend on it: at 1e-6 the
// same 1.93e-3 as a capillary number, i.e. 1933 U).
// Second case: the same translation at density ratio 1000 and viscosity ratio 100 (Ca = 1e-4
// with the liquid viscosity 0.1 Pa s, U = 5e-5 m/s): spurious speeds 186 U on average since issue
// 14 (244 U before; 1000 U at the start, 77 U at the end), asserted below 230 U; momentum kept,
// drop intact.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "tests/support/fluid_drop.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {

struct LowCaResult {
  double U = 0, spMax = 0, spMean = 0, spLast = 0, varMax = 0, rlMax = 0, rgMin = 1e300, drift = 0, ut = 0;
  double vMomentum = 0;  ///< mass-weighted mean x velocity at the end
  double dx = 0, wall = 0;
  long long steps = 0, particles = 0;
};

// Runs the drop of p translating at U = Ca mu_liquid / gamma for `capillaryTimes` times
// sqrt(rho_l R^3 / gamma); samples the largest spurious speed |v - U e_x| every 50 steps.
LowCaResult runTranslatingDrop(const test::FluidDrop::Params& p, double caImposed, double capillaryTimes,
                               const char* label) {
  test::Stopwatch clock;
  LowCaResult r;
  r.U = caImposed * p.gamma / p.muLiquid;
  const double U = r.U;
  test::FluidDrop d(p);
  r.dx = d.dx;
  auto& st = d.sim.store;
  const Index n = d.count();
  {
    double* v = st.data(st.velocity());
    for (Index i = 0; i < n; ++i) v[i * 2] = U, v[i * 2 + 1] = 0.0;
  }
  auto liquidCentroidX = [&]() {
    const double* x = st.data(st.position());
    const double* col = st.data(d.fluid->colour);
    double sx = 0, c = 0;
    for (Index i = 0; i < n; ++i)
      if (col[i] > 0) sx += x[i * 2], c += 1;
    return sx / c;
  };
  const double x0 = liquidCentroidX();
  const double tCap = std::sqrt(p.rhoLiquid * p.R * p.R * p.R / p.gamma);  // 8.2 ms
  const double tEnd = capillaryTimes * tCap;
  double spSum = 0;
  long samples = 0;
  while (d.sim.time < tEnd * (1 - 1e-12)) {
    d.stepper.step(d.sim, tEnd - d.sim.time);
    r.varMax = std::max(r.varMax, d.fluid->maxDensityVariation());
    if (d.sim.step % 50 != 0) continue;
    const double* v = st.data(st.velocity());
    double m2 = 0;
    for (Index i = 0; i < n; ++i) {
      const double ux = v[i * 2] - U, uy = v[i * 2 + 1];
      m2 = std::max(m2, ux * ux + uy * uy);
    }
    r.spMax = std::max(r.spMax, std::sqrt(m2));
    spSum += std::sqrt(m2);
    r.spLast = std::sqrt(m2);
    ++samples;
    double rl, rg;
    d.extent(rl, rg);
    r.rlMax = std::max(r.rlMax, rl);
    r.rgMin = std::min(r.rgMin, rg);
  }
  d.sim.checkFinite();
  r.drift = liquidCentroidX() - x0;
  r.ut = U * d.sim.time;
  const double* v = st.data(st.velocity());
  const double* m = st.data(st.mass());
  double mv = 0, ms = 0;
  for (Index i = 0; i < n; ++i) mv += m[i] * v[i * 2], ms += m[i];
  r.vMomentum = mv / ms;
  r.spMean = spSum / static_cast<double>(samples);
  r.steps = static_cast<long long>(d.sim.step);
  r.particles = static_cast<long long>(n);
  r.wall = clock.seconds();
  std::printf("%s: Ca_imposed = %.1e (U = %.2e m/s), La = %.0f, %lld particles, %lld steps, t = %.1f ms "
              "(%.1f capillary times)\n"
              "  spurious speed max |v - U| / U: largest %.2f, time mean %.2f, last sample %.2f (as Ca: %.2e / %.2e)\n"
              "  liquid centroid moved %.5e m vs U t = %.5e m; momentum-mean velocity %.5e m/s (%.4f U); "
              "liquid extent <= %.3f R, nearest gas >= %.3f R; max density variation %.3f %%; %.1f s\n",
              label, caImposed, U, p.rhoLiquid * p.gamma * p.R / (p.muLiquid * p.muLiquid), r.particles, r.steps,
              1e3 * d.sim.time, d.sim.time / tCap, r.spMax / U, r.spMean / U, r.spLast / U, p.muLiquid * r.spMax / p.gamma,
              p.muLiquid * r.spMean / p.gamma, r.drift, r.ut, r.vMomentum, r.vMomentum / U, r.rlMax / p.R,
              r.rgMin / p.R, 100 * r.varMax, r.wall);
  std::fflush(stdout);
  return r;
}

double imposedCa() {
  return std::getenv("FLUID_LOW_CA") ? std::atof(std::getenv("FLUID_LOW_CA")) : 1e-4;
}

}  // namespace

TEST(FluidExtreme, LowCapillaryNumberTranslatingDroplet) {
  test::FluidDrop::Params p;
  p.dim = 2;
  p.rOverDx = 10;
  p.muLiquid = p.muGas = 1e-3;
  p.cLiquid = p.cGas = 10.0;  // >> the spurious speeds (~0.1 m/s): density variation ~0.3 %
  const LowCaResult r = runTranslatingDrop(p, imposedCa(), 3.0, "low capillary number, La = 75000");
  EXPECT_LT(r.rlMax, p.R + 2 * r.dx);  // intact: no liquid thrown out of the drop
  EXPECT_GT(r.rgMin, p.R - 2 * r.dx);  // no gas inside
  EXPECT_LT(r.varMax, 0.03);           // c large enough for the spurious speeds
  EXPECT_LT(std::abs(r.drift - r.ut), 0.2 * r.dx);  // carried with the flow (U t = 0.8 dx)
  EXPECT_NEAR(r.vMomentum, r.U, 0.1 * r.U);         // the imposed flow is not lost
  EXPECT_LT(p.muLiquid * r.spMax / p.gamma, 1e-2);  // bounded (measured 1.9e-3; the ratio to U is the finding)
  if (imposedCa() == 1e-4) EXPECT_LT(r.spMean / r.U, 11.0);  // measured 9.15
  test::recordValidation({"fluid_low_capillary_translating_droplet_2d",
                          "time mean of the largest spurious speed / imposed speed U (Ca_imposed = 1e-4)",
                          r.spMean / r.U, 0.0, r.spMean / r.U,
                          "2D, R/dx = 10, La = 75000, periodic box 3R, c = 10 m/s, 3 capillary times", r.wall,
                          "< 11 (and spurious Ca < 1e-2, drop intact, carried with U)",
                          "0 (drop at rest in the frame moving with U)"});
}

// The same at density ratio 1000 and viscosity ratio 100 (water drop, mu 0.1 Pa s, c 2 m/s, in
// gas rho 1, mu 1e-3, c 20 m/s; `pressure_gradient: hu_adams`, background pressure 100 Pa):
// Ca = mu_l U / gamma = 1e-4 gives U = 5e-5 m/s, U t = 0.008 dx over the run, so here the
// centroid check only says that the drop does not wander.
TEST(FluidExtreme, LowCapillaryNumberTranslatingDropletDensityRatio1000) {
  test::FluidDrop::Params p;
  p.dim = 2;
  p.rOverDx = 10;
  p.rhoLiquid = 1000, p.muLiquid = 0.1, p.cLiquid = 2.0;
  p.rhoGas = 1, p.muGas = 1e-3, p.cGas = 20.0;
  p.backgroundPressure = 100.0;
  p.extra = ", pressure_gradient: hu_adams";
  const LowCaResult r = runTranslatingDrop(p, imposedCa(), 3.0, "low capillary number, density ratio 1000");
  EXPECT_LT(r.rlMax, p.R + 2 * r.dx);
  EXPECT_GT(r.rgMin, p.R - 2 * r.dx);
  EXPECT_LT(r.varMax, 0.08);  // measured 4 % (the gas, early; the warning reports it)
  EXPECT_LT(std::abs(r.drift - r.ut), 0.2 * r.dx);
  EXPECT_NEAR(r.vMomentum, r.U, 0.1 * r.U);
  EXPECT_LT(p.muLiquid * r.spMax / p.gamma, 0.5);  // bounded (measured 0.10: the gas, early)
  if (imposedCa() == 1e-4) EXPECT_LT(r.spMean / r.U, 230.0);  // measured 186 (244 before issue 14)
  test::recordValidation({"fluid_low_capillary_translating_droplet_2d_ratio1000",
                          "time mean of the largest spurious speed / imposed speed U (Ca_imposed = 1e-4)",
                          r.spMean / r.U, 0.0, r.spMean / r.U,
                          "2D, R/dx = 10, density ratio 1000, viscosity ratio 100, hu_adams, p_b = 100 Pa, "
                          "periodic box 3R, 3 capillary times",
                          r.wall, "< 230 (and drop intact, momentum kept)",
                          "0 (drop at rest in the frame moving with U)"});
}
