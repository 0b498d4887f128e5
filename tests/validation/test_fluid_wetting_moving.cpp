// Validation: contact angle on a translating plate (issue 14, "a wall that moves").
// Scene and readings: fluid_wetting_moving_case.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/validation/fluid_wetting_moving_case.hpp"

using namespace poresph;

namespace {
double env(const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; }
}  // namespace

// Manual probe: PROBE_THETA, PROBE_RDX, PROBE_U, PROBE_LIDU (default U), PROBE_START (fluid's
// initial x velocity), PROBE_MODE (0 rest, 1 moving particles, 2 mirror only), PROBE_BOX, PROBE_TEND.
TEST(DISABLED_Probe, MovingWall) {
  test::MovingSessileParams p;
  p.theta = env("PROBE_THETA", 60);
  p.rOverDx = static_cast<int>(env("PROBE_RDX", 10));
  p.U = env("PROBE_U", 0.01);
  p.lidU = env("PROBE_LIDU", p.U);
  p.fluidStart = env("PROBE_START", 0.0);
  const int mode = static_cast<int>(env("PROBE_MODE", 1));
  p.motion = mode == 0 ? test::WallMotion::Rest : mode == 1 ? test::WallMotion::Moving : test::WallMotion::Mirror;
  p.boxLength = env("PROBE_BOX", 5);
  p.settings = std::getenv("PROBE_SETTINGS") ? std::getenv("PROBE_SETTINGS") : test::kWettingGhostSettings;
  char name[128];
  std::snprintf(name, sizeof name, "probe_moving_theta%.0f_mode%d_U%g.txt", p.theta, mode, p.U);
  const auto r = test::runMovingWetting(p, env("PROBE_TEND", 0.12), 0.005, name);
  EXPECT_GT(r.mean, 0.0);
}

// The plate really translates: wall particles whose motion is `prescribed` (a scene region's
// `motion: prescribed`) keep it through the fluid module's set-up and move with their material's
// velocity; a fixed wall with the same velocity stays in place (its velocity enters the no-slip
// mirror only). 200 steps of the 60-degree scene (~1 s).
TEST(FluidWettingMoving, PrescribedWallTranslatesFixedWallStays) {
  for (const auto motion : {test::WallMotion::Moving, test::WallMotion::Mirror}) {
    test::MovingSessileParams p;
    p.U = p.lidU = 0.05;
    p.motion = motion;
    p.settings = test::kWettingGhostSettings;
    test::MovingSessile s(p);
    const auto& st = s.sim.store;
    std::vector<double> x0(st.data(st.position()), st.data(st.position()) + 2 * st.realCount());
    std::vector<std::int32_t> id0(st.data(st.id()), st.data(st.id()) + st.realCount());
    for (int k = 0; k < 200; ++k) s.stepper.step(s.sim);
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    const std::int32_t* mt = st.data(st.material());
    const std::int32_t* id = st.data(st.id());
    std::vector<Index> row(static_cast<size_t>(*std::max_element(id0.begin(), id0.end())) + 1, -1);
    for (Index i = 0; i < static_cast<Index>(id0.size()); ++i) row[static_cast<size_t>(id0[static_cast<size_t>(i)])] = i;
    const double shift = motion == test::WallMotion::Moving ? p.U * s.sim.time : 0.0;
    double worst = 0.0, worstV = 0.0;
    int walls = 0;
    for (Index i = 0; i < st.realCount(); ++i) {
      if (mt[i] != s.floor && mt[i] != s.lid) continue;
      const Index i0 = row[static_cast<size_t>(id[i])];
      double dxp = x[2 * i] - x0[static_cast<size_t>(2 * i0)] - shift;
      dxp -= s.Lx * std::round(dxp / s.Lx);  // periodic along x
      worst = std::max({worst, std::abs(dxp), std::abs(x[2 * i + 1] - x0[static_cast<size_t>(2 * i0 + 1)])});
      worstV = std::max({worstV, std::abs(v[2 * i] - p.U), std::abs(v[2 * i + 1])});
      ++walls;
    }
    std::printf("%s walls: %d particles, t = %.3e s, plate shift %.3e m, worst position error %.2e m, velocity %.2e\n",
                motion == test::WallMotion::Moving ? "prescribed" : "fixed", walls, s.sim.time, shift, worst, worstV);
    ASSERT_GT(walls, 100);
    EXPECT_LT(worst, 1e-12);
    EXPECT_LT(worstV, 1e-15);
  }
}

// Contact angle on a translating plate (issue 14): the drop starts at rest as a rectangle on a
// plate (and lid) sliding at U = 0.05 m/s (Ca = mu U / gamma = 0.01), the plate's particles move
// (motion prescribed); by 60-120 ms the drop beads up to the prescribed angle while the plate
// drags it along. Asserted: the circle-fit angle and the front (downstream) and rear angles within
// the 5 degrees, and the drop travelling with the plate (mean liquid speed over the window
// 0.7-1.05 U: it is still catching up, 0.83 U measured; a plate whose velocity did not reach the
// fluid leaves it at 0). Measured (R0/dx 10, ~14 s CPU each on a loaded machine): 60 -> 60.42
// (front 58.90, rear 61.36), 0.831 U; 120 -> 119.94 (117.81 / 123.62), 0.815 U; the same drops on
// the plate at rest 60.41 / 120.49 (docs/fluid.md "Contact angle on a moving wall").
namespace {
void checkMoving(double theta) {
  test::MovingSessileParams p;
  p.theta = theta;
  p.U = p.lidU = 0.05;
  p.motion = test::WallMotion::Moving;
  p.settings = test::kWettingGhostSettings;
  char name[96];
  std::snprintf(name, sizeof name, "fluid_wetting_moving_theta%.0f_r10.txt", theta);
  const auto r = test::runMovingWetting(p, 0.12, 0.005, name);
  char cs[96], res[300];
  std::snprintf(cs, sizeof cs, "fluid_wetting_moving_plate_theta%.0f_R10", theta);
  std::snprintf(res, sizeof res,
                "2D flat plate translating at U = 0.05 m/s (Ca 0.01, particles move), drop from rest, R0/dx = 10, "
                "rectangle start, Oh = 0.036, mean over 60-120 ms (%.1f to %.1f; front %.2f, rear %.2f; drop "
                "speed %.3f U), %lld steps",
                r.lo, r.hi, r.front, r.rear, r.speed, r.steps);
  test::recordValidation({cs, "contact angle (degrees), circle fit above 2 dx in the drop's frame, time mean", r.mean,
                          theta, std::abs(r.mean - theta) / theta, res, r.wall,
                          "|error| < 5 degrees (also front and rear); drop speed 0.7-1.05 U",
                          "prescribed wall angle (Eq. 1.10), kWettingGhostSettings, moving wall"});
  EXPECT_NEAR(r.mean, theta, 5.0);
  EXPECT_NEAR(r.front, theta, 5.0);
  EXPECT_NEAR(r.rear, theta, 5.0);
  EXPECT_GT(r.speed, 0.7);
  EXPECT_LT(r.speed, 1.05);
}
}  // namespace

TEST(FluidWettingMoving, SixtyDegreesOnATranslatingPlate) { checkMoving(60.0); }
TEST(FluidWettingMoving, OneHundredTwentyDegreesOnATranslatingPlate) { checkMoving(120.0); }
