// Capillarity studies (issue 14), label `long` (tests/long-tests.txt).
// DISABLED_Probe.* are manual probes driven by environment variables (run with
// --gtest_also_run_disabled_tests --gtest_filter='*Probe*'); they write no validation record.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "tests/support/fluid_drop.hpp"
#include "tests/validation/fluid_wetting_curved_case.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;

namespace {
double env(const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; }
std::string envs(const char* k, const char* d) { return std::getenv(k) ? std::getenv(k) : d; }
}  // namespace

// Static drop: PROBE_DIM, PROBE_RDX, PROBE_H (h/dx), PROBE_RHOG (gas density, liquid 1000),
// PROBE_MUL, PROBE_MUG, PROBE_CL, PROBE_CG, PROBE_PB, PROBE_GAMMA, PROBE_EXTRA (", key: value"),
// PROBE_TRELAX, PROBE_TEND, PROBE_BOX.
TEST(DISABLED_Probe, StaticDrop) {
  test::Stopwatch clock;
  test::FluidDrop::Params p;
  p.dim = static_cast<int>(env("PROBE_DIM", 2));
  p.rOverDx = env("PROBE_RDX", 10);
  p.hOverDx = env("PROBE_H", 1.0);
  p.boxOverR = env("PROBE_BOX", 3.0);
  p.gamma = env("PROBE_GAMMA", 0.05);
  p.rhoGas = env("PROBE_RHOG", 1000);
  p.muLiquid = env("PROBE_MUL", 0.3);
  p.muGas = env("PROBE_MUG", p.muLiquid);
  p.cLiquid = env("PROBE_CL", 2.0);
  p.cGas = env("PROBE_CG", p.cLiquid);
  p.backgroundPressure = env("PROBE_PB", 0.0);
  p.extra = envs("PROBE_EXTRA", "");
  test::FluidDrop d(p);
  const double tRelax = env("PROBE_TRELAX", 0.003), tEnd = env("PROBE_TEND", 0.012);
  const double window = env("PROBE_WINDOW", d.B / p.cLiquid);
  const test::FluidDrop::Measurement m = d.settleAndMeasure(tRelax, tEnd, window);
  const double ref = (p.dim == 2 ? 1.0 : 2.0) * p.gamma / p.R;
  double rl, rg;
  d.extent(rl, rg);
  std::printf("PROBE dim %d R/dx %g h/dx %g rho_g %g mu %g/%g c %g/%g pb %g extra '%s': %lld particles %ld steps\n"
              "  jump %.4f Pa (ref %.4f) error %+.2f %% swing %.2f %%; Ca max end %.3e mean %.3e rms %.3e; "
              "liquid <= %.3f R gas >= %.3f R; %.1f s\n",
              p.dim, p.rOverDx, p.hOverDx, p.rhoGas, p.muLiquid, p.muGas, p.cLiquid, p.cGas, p.backgroundPressure,
              p.extra.c_str(), static_cast<long long>(d.count()), m.steps, m.dpMean, ref,
              100 * (m.dpMean - ref) / ref, 100 * (m.dpMax - m.dpMin) / ref, p.muLiquid * m.speedEnd / p.gamma,
              p.muLiquid * m.speedMean / p.gamma, p.muLiquid * m.rmsMean / p.gamma, rl / p.R, rg / p.R,
              clock.seconds());
  const std::string dump = envs("PROBE_DUMP", "");
  if (!dump.empty()) d.dumpSlice(dump);
}

// Tilted staircase wall: PROBE_THETA, PROBE_TILT, PROBE_RDX, PROBE_TEND, PROBE_EXTRA.
#include "tests/validation/fluid_wetting_case.hpp"
TEST(DISABLED_Probe, TiltedSessile) {
  const auto r = test::runTiltedSessile(env("PROBE_THETA", 60), env("PROBE_TILT", 30),
                                        static_cast<int>(env("PROBE_RDX", 10)), env("PROBE_TEND", 0.06), false,
                                        envs("PROBE_EXTRA", ""));
  EXPECT_GT(r.theta, 0.0);
}

// The averaged tilted-wall drop of the long tests with other settings: PROBE_THETA, PROBE_TILT,
// PROBE_RDX, PROBE_BOX (box length / R0), PROBE_SETTINGS (module keys, default
// test::kWettingGhostSettings), PROBE_TEND.
TEST(DISABLED_Probe, WettingAverage) {
  const auto r = test::runWettingAverage(env("PROBE_THETA", 30), env("PROBE_TILT", 15),
                                         static_cast<int>(env("PROBE_RDX", 10)), env("PROBE_TEND", 0.12), 0.01,
                                         envs("PROBE_SETTINGS", test::kWettingGhostSettings), 0.005, env("PROBE_BOX", 8));
  EXPECT_GT(r.mean, 0.0);
}

// Drop on a curved wall (fluid_wetting_curved_case.hpp): PROBE_THETA, PROBE_OUTSIDE (1: on a
// cylinder, 0: in a cavity), PROBE_RC (wall radius / R0), PROBE_RDX, PROBE_TEND, PROBE_SETTINGS.
TEST(DISABLED_Probe, CurvedWetting) {
  const auto r = test::runCurvedWetting(env("PROBE_THETA", 60), env("PROBE_OUTSIDE", 0) > 0, env("PROBE_RC", 2.5),
                                        static_cast<int>(env("PROBE_RDX", 10)), env("PROBE_TEND", 0.12), 0.01,
                                        envs("PROBE_SETTINGS", test::kWettingGhostSettings));
  EXPECT_GT(r.mean, 0.0);
}

// Angle against time on a flat or tilted wall: PROBE_THETA, PROBE_TILT, PROBE_RDX, PROBE_TEND,
// PROBE_DT (print interval), PROBE_MU (both phases), PROBE_HALFWIDTH (start rectangle, R0), PROBE_EXTRA; circle fit and cap (height/area).
TEST(DISABLED_Probe, WettingSeries) {
  test::Stopwatch clock;
  const double theta = env("PROBE_THETA", 30), tilt = env("PROBE_TILT", 0), tEnd = env("PROBE_TEND", 0.06);
  const int rdx = static_cast<int>(env("PROBE_RDX", 10));
  test::TiltedSessile s(theta, tilt, 1.5e-3, rdx, envs("PROBE_EXTRA", ""), env("PROBE_MU", 0.05),
                          env("PROBE_HALFWIDTH", 0.9));
  const double dt = env("PROBE_DT", 0.01);
  for (double t = dt; t <= tEnd * (1 + 1e-9); t += dt) {
    s.stepper.runTo(s.sim, t);
    double rc, sc, H, A;
    int np;
    const double fit = s.contactAngle(rc, sc, np);
    const double cap = s.capAngle(H, A);
    std::printf("theta %.0f tilt %.0f R0/dx %d t %.0f ms: fit %.2f cap %.2f (H %.2f dx, r %.2f dx, %d pts) %.1f s\n", theta,
                tilt, rdx, 1e3 * t, fit, cap, H / s.dx, rc / s.dx, np, clock.seconds());
    std::fflush(stdout);
  }
  if (env("PROBE_PROFILE", 0) > 0) {  // interface particles near the right contact line
    s.sim.updateNeighbours();
    const auto& st = s.sim.store;
    const double* x = st.data(st.position());
    const double* ng = st.data(s.fluid->colourGradient);
    const double* kp = st.data(s.fluid->curvature);
    const double* ac = st.data(s.sim.acceleration);
    const std::int32_t* mt = st.data(st.material());
    const std::int32_t* itf = st.data(s.fluid->interface);
    for (Index i = 0; i < st.realCount(); ++i) {
      if (!itf[i] || (mt[i] != s.liquid && mt[i] != s.gas)) continue;
      const Eigen::Vector2d d(x[2 * i] - s.P0[0], x[2 * i + 1] - s.P0[1]);
      const double tt = d.dot(s.t), ss = d.dot(s.n);
      if (ss > 5 * s.dx || tt < 0) continue;
      const Eigen::Vector2d nn(ng[2 * i], ng[2 * i + 1]);
      const Eigen::Vector2d mo = -nn / std::max(1e-30, nn.norm());
      std::printf("  %s s %.2f t %.2f: local angle %.1f |n|dx %.3f kappa dx %.3f acc %.3e %.3e\n",
                  mt[i] == s.liquid ? "L" : "G", ss / s.dx, tt / s.dx,
                  std::atan2(mo.dot(s.t), mo.dot(s.n)) * 180 / 3.14159265358979, nn.norm() * s.dx, kp[i] * s.dx,
                  Eigen::Vector2d(ac[2 * i], ac[2 * i + 1]).dot(s.t), Eigen::Vector2d(ac[2 * i], ac[2 * i + 1]).dot(s.n));
    }
  }
  char name[96];
  std::snprintf(name, sizeof name, "probe_wetting_theta%.0f_r%d%s.txt", theta, rdx, envs("PROBE_TAG", "").c_str());
  s.dump(name);
}

// Wetting at 30, 60, 90, 120 and 150 degrees on a flat lattice-aligned wall (issue 14 item 4),
// one setting for all (test::kWettingGhostSettings: wetting: normal, wetting_scale 0.05,
// wetting_ghost: true; not the defaults, see docs/fluid.md) at
// two resolutions (R0/dx 10 and 15), rectangle start (not the answer for any angle), Oh = 0.036
// (mu 0.01 Pa s in both phases: the contact line reaches its angle within the run; at Oh 0.18 the
// 30-degree drop was still spreading after 300 ms), angle = mean of the circle fit over
// [60, 120] ms. With the defaults (scale 0.15, no ghost colour): 48.7 / 130.6 degrees at 30 / 150
// (60 ms, Oh 0.18). Spec: within 5 degrees (issue 14), asserted.
TEST(FluidWettingExtremes, FiveAnglesFlatWallTwoResolutions) {
  for (const int rdx : {10, 15}) {
    for (const double theta : {30.0, 60.0, 90.0, 120.0, 150.0}) {
      const auto r = test::runWettingAverage(theta, 0.0, rdx, 0.12, 0.01, test::kWettingGhostSettings);
      char cs[96], res[240];
      std::snprintf(cs, sizeof cs, "fluid_wetting_flat_theta%.0f_R%d", theta, rdx);
      std::snprintf(res, sizeof res,
                    "2D flat lattice-aligned wall, R0/dx = %d, rectangle start, quintic h = dx, Oh = 0.036, equal "
                    "densities, p_b = 100 Pa, mean over 60-120 ms (%.1f to %.1f), %lld steps",
                    rdx, r.lo, r.hi, r.steps);
      test::recordValidation({cs, "contact angle (degrees), circle fit above 2 dx, time mean", r.mean, theta,
                              std::abs(r.mean - theta) / theta, res, r.wall, "|error| < 5 degrees",
                              "prescribed wall angle (Eq. 1.10), wetting: normal with ghost colour, wetting_scale 0.05"});
      EXPECT_NEAR(r.mean, theta, 5.0) << "R0/dx " << rdx;
    }
  }
}

// The same setting on walls tilted by 15, 30 and 45 degrees to the lattice (issue 14 "Wetting on
// real walls": a flat wall tilted by 15, 30 and 45 degrees represented as a voxel staircase),
// R0/dx 10, the five angles, rectangle start in the wall's frame, box 8 R0 long, mean of the circle fit (wall
// frame, above 2 dx) over [60, 120] ms. Spec: within 5 degrees, asserted. With the local wall
// normal (wall_normal: local) 10 of 15 were within 5 degrees (37.0 / 159.3 for 30 / 150 at 15
// degrees of tilt: the normal turned at each step); the setting now has wall_normal: wide.
TEST(FluidWettingExtremes, FiveAnglesTiltedStaircase) {
  const double only = env("TILT_ONLY_THETA", 0.0);  // probe hook: one angle only (0 = all five)
  for (const double tilt : {15.0, 30.0, 45.0}) {
    for (const double theta : {30.0, 60.0, 90.0, 120.0, 150.0}) {
      if (only != 0.0 && theta != only) continue;
      // box 8 R0 along the wall: the 30-degree cap (4.2 R0 wide) reached the ends of the 5 R0 box
      const auto r = test::runWettingAverage(theta, tilt, 10, 0.12, 0.01, test::kWettingGhostSettings, 0.005, 8.0);
      char cs[96], res[260];
      std::snprintf(cs, sizeof cs, "fluid_wetting_tilted%.0f_theta%.0f_R10", tilt, theta);
      std::snprintf(res, sizeof res,
                    "2D wall tilted %.0f degrees as a lattice staircase, R0/dx = 10, box 8 R0, rectangle start, quintic h = dx, "
                    "Oh = 0.036, equal densities, p_b = 100 Pa, mean over 60-120 ms (%.1f to %.1f), %lld steps",
                    tilt, r.lo, r.hi, r.steps);
      test::recordValidation({cs, "contact angle (degrees), circle fit in the wall frame above 2 dx, time mean", r.mean,
                              theta, std::abs(r.mean - theta) / theta, res, r.wall, "|error| < 5 degrees",
                              "prescribed wall angle (Eq. 1.10), wetting: normal with ghost colour, wetting_scale 0.05, "
                              "wall_normal: wide"});
      EXPECT_NEAR(r.mean, theta, 5.0) << "tilt " << tilt;
    }
  }
}

// Curved walls (issue 14 "Wetting on real walls": the inside and outside of a circular wall, 2D):
// a drop in a circular cavity and on a cylinder, both of radius 2.5 R0 (voxelised circles),
// 60 and 120 degrees, the validated setting (test::kWettingGhostSettings, with the wide wall
// normal), R0/dx 10, Oh = 0.036, rectangle start in the wall's polar frame, angle against the
// local wall tangent at the contact points of the fitted circle (fluid_wetting_curved_case.hpp),
// mean over [60, 120] ms. Spec: within 5 degrees, asserted.
TEST(FluidWettingExtremes, CurvedWallsInsideAndOutside) {
  for (const bool outside : {false, true}) {
    for (const double theta : {60.0, 120.0}) {
      const auto r = test::runCurvedWetting(theta, outside, 2.5, 10, 0.12, 0.01, test::kWettingGhostSettings);
      char cs[96], res[300];
      std::snprintf(cs, sizeof cs, "fluid_wetting_curved_%s_theta%.0f_R10", outside ? "outside" : "inside", theta);
      std::snprintf(res, sizeof res,
                    "2D drop %s a circular wall of radius 2.5 R0 (voxelised), R0/dx = 10, rectangle start, quintic h = dx, "
                    "Oh = 0.036, equal densities, p_b = 100 Pa, mean over 60-120 ms (%.1f to %.1f), "
                    "%lld steps",
                    outside ? "on the outside of" : "inside", r.lo, r.hi, r.steps);
      test::recordValidation({cs, "contact angle (degrees) against the local wall tangent at the contact points, time mean",
                              r.mean, theta, std::abs(r.mean - theta) / theta, res, r.wall, "|error| < 5 degrees",
                              "prescribed wall angle (Eq. 1.10), wetting: normal with ghost colour, wetting_scale 0.05, "
                              "wall_normal: wide"});
      EXPECT_NEAR(r.mean, theta, 5.0) << (outside ? "outside" : "inside");
    }
  }
}

// Laplace jump of a 3D static drop of water in gas at density ratio 1000 and viscosity ratio 100
// (issue 14, "Surface tension and pressure": within 5 % in 2D and 3D, the spurious speed
// reported). The 2D case is the default test FluidCapillarity.LaplaceJumpDensityRatio1000 (R/dx 10,
// -2.0 %); the same fluids and settings here on a sphere of R/dx = 6 in a periodic box of 3 R
// (5,832 particles): water 1000 kg/m^3, mu 0.1 Pa s, c 2 m/s; gas 1 kg/m^3, mu 1e-3 Pa s, c 20 m/s;
// hu_adams, p_b = 100 Pa; damped to 3 ms, jump = time mean over the last B / c_l = 2.25 ms before 6 ms (the FluidDrop
// measurement). Probes (docs/fluid.md "3D at density ratio 1000"): +1.1 % at R/dx 6 (spurious
// Ca 3.9e-2), -0.29 % at R/dx 8 (1.4e-2, 933 s wall: too long for a test).
TEST(FluidCapillarity3D, LaplaceJumpDensityRatio1000) {
  test::Stopwatch clock;
  test::FluidDrop::Params p;
  p.dim = 3;
  p.rOverDx = 6;
  p.rhoLiquid = 1000, p.muLiquid = 0.1, p.cLiquid = 2.0;
  p.rhoGas = 1, p.muGas = 1e-3, p.cGas = 20.0;
  p.backgroundPressure = 100.0;
  p.extra = ", pressure_gradient: hu_adams";
  test::FluidDrop d(p);
  const test::FluidDrop::Measurement m = d.settleAndMeasure(0.003, 0.006, d.B / p.cLiquid);
  const double ref = 2.0 * p.gamma / p.R, err = std::abs(m.dpMean - ref) / ref;
  const double ca = p.muLiquid * m.speedMean / p.gamma;
  double rl, rg;
  d.extent(rl, rg);
  const double wall = clock.seconds();
  std::printf("3D, density ratio 1000, R/dx 6: jump %.3f Pa vs 2 gamma / R = %.3f (%+.2f %%, swing %.2f %%), spurious Ca "
              "%.2e, liquid <= %.3f R, gas >= %.3f R, %lld particles, %ld steps, %.1f s\n",
              m.dpMean, ref, 100 * (m.dpMean - ref) / ref, 100 * (m.dpMax - m.dpMin) / ref, ca, rl / p.R, rg / p.R,
              static_cast<long long>(d.count()), m.steps, wall);
  EXPECT_LT(err, 0.05);
  EXPECT_LT(rl, p.R + 2 * d.dx);  // no water thrown out of the drop
  EXPECT_GT(rg, p.R - 2 * d.dx);  // no gas inside it
  EXPECT_LT(ca, 6e-2);            // probe 3.9e-2
  const std::string res = "3D, R/dx = 6, periodic box 3R (5,832 particles), quintic h = dx, density ratio 1000, "
                          "viscosity ratio 100, hu_adams, p_b = 100 Pa, c = 2 / 20 m/s, t = 6 ms, " +
                          std::to_string(m.steps) + " steps";
  test::recordValidation({"fluid_static_droplet_3d_ratio1000", "Laplace pressure jump (Pa)", m.dpMean, ref, err, res,
                          wall, "< 5 %", "Young-Laplace 2 gamma / R (Eq. 1.5)"});
  test::recordValidation({"fluid_static_droplet_3d_ratio1000",
                          "spurious-current capillary number mu_l u_max / gamma (window mean)", ca, 0.0, ca, res, wall,
                          "< 6e-2", "0 (exact solution at rest)"});
}
