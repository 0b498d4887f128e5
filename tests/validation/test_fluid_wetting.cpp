// Validation: contact angles 30 and 150 degrees on a flat lattice-aligned wall (issue 14 item 4),
// wetting: normal (the prescribed contact-line normal of the wall colour cos(theta), Eq. 1.10)
// with the option wetting_ghost (the wall's ghost colour completing the interface delta at the
// contact line) and wetting_scale 0.05 (test::kWettingGhostSettings; not the default: with it the
// 60-degree capillary entry threshold moves above 1.1 times Young-Laplace, docs/fluid.md). The drop starts as a rectangle standing on the wall (the
// area of a half disc of radius R0: not the answer for either angle), R0/dx = 10, Oh = 0.036; the
// angle is the circle fit (above 2 dx, in the wall frame) averaged over [60, 120] ms. Scene and
// measurement: fluid_wetting_case.hpp. The five angles at two resolutions are the long test
// FluidWettingExtremes.FiveAnglesFlatWallTwoResolutions (test_fluid_capillarity_long.cpp).
// Without the ghost colour: 150 degrees settled at ~140 (wetting_scale 0.05) / ~133 (0.15);
// 30 degrees crept (48.7 at 60 ms, 34.8 at 300 ms at Oh 0.18).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "tests/validation/fluid_wetting_case.hpp"

using namespace poresph;

namespace {
void check(double theta, double tolerance = 5.0) {
  const auto r = test::runWettingAverage(theta, 0.0, 10, 0.12, 0.01, test::kWettingGhostSettings);
  char cs[96], res[240];
  std::snprintf(cs, sizeof cs, "fluid_wetting_flat_theta%.0f_R10", theta);
  std::snprintf(res, sizeof res,
                "2D flat lattice-aligned wall, R0/dx = 10, rectangle start, quintic h = dx, Oh = 0.036, equal densities, "
                "p_b = 100 Pa, mean over 60-120 ms (%.1f to %.1f), %lld steps",
                r.lo, r.hi, r.steps);
  test::recordValidation({cs, "contact angle (degrees), circle fit above 2 dx, time mean", r.mean, theta,
                          std::abs(r.mean - theta) / theta, res, r.wall,
                          tolerance == 5.0 ? "|error| < 5 degrees" : "|error| < 2.5 degrees",
                          "prescribed wall angle (Eq. 1.10), wetting: normal with ghost colour, wetting_scale 0.05, "
                          "wetting_curvature"});
  EXPECT_NEAR(r.mean, theta, tolerance);
  // the end state is a cap, not a film or a detached drop: the cap angle (height and area) agrees
  EXPECT_NEAR(r.cap, theta, 10.0);
}
}  // namespace

TEST(FluidWettingAngles, Thirty) { check(30.0); }
TEST(FluidWettingAngles, OneHundredFifty) { check(150.0); }
// 120 degrees (issue 14, 2026-11-27): with theta prescribed at every height of the ~2 dx band
// near the wall the 120-degree caps (r ~ 8 dx at R0/dx 10) read ~+4 degrees high on every wall
// (flat 123.87, cap reading 125.1); with wetting_curvature (the prescribed normal follows the
// circle that meets the wall at theta) 120.44 (~17 s CPU). Asserted within 2.5 degrees, tighter
// than the 5, so that the bias (3.9) fails the test.
TEST(FluidWettingAngles, OneHundredTwentyWithoutTheFootBias) { check(120.0, 2.5); }

// Wall on a voxel staircase (issue 14 "Wetting on real walls"): the wall tilted by 15 degrees
// to the lattice (steps 3.7 dx long), where the local wall normal (the gradient of the wall
// indicator over one support) turned by up to ~20 degrees at each step and the drops settled
// too non-wetting: 159.3 degrees for 150 and 37.0 for 30 (docs/fluid.md). The set-up field
// wall_normal (option wall_normal: wide, in test::kWettingGhostSettings) must follow the plane:
// on the wall particles of the top row (within 1 dx of the plane) away from the box's ends,
// within 6 degrees of the plane's normal (a step-following normal deviates by more).
TEST(FluidWettingWalls, WideWallNormalFollowsFifteenDegreeStaircase) {
  test::TiltedSessile s(150.0, 15.0, 1.5e-3, 10, test::kWettingGhostSettings, 0.01, 0.9, 5.0);
  const auto& st = s.sim.store;
  ASSERT_TRUE(s.fluid->wallNormal.valid());
  const double* x = st.data(st.position());
  const double* g = st.data(s.fluid->wallNormal);
  const std::int32_t* mt = st.data(st.material());
  double worst = 0.0, sum2 = 0.0;
  int count = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (mt[i] != s.wall) continue;
    const Eigen::Vector2d d(x[2 * i] - s.P0[0], x[2 * i + 1] - s.P0[1]);
    if (d.dot(s.n) < -s.dx || std::abs(d.dot(s.t)) > 1.5 * s.R0) continue;
    const Eigen::Vector2d gi(g[2 * i], g[2 * i + 1]);
    const double dev = std::atan2(gi.dot(s.t), gi.dot(s.n)) * 180.0 / test::TiltedSessile::kPi;
    worst = std::max(worst, std::abs(dev));
    sum2 += dev * dev;
    ++count;
  }
  std::printf("wall_normal on the 15-degree staircase: %d top-row wall particles, deviation rms %.2f, max %.2f deg\n",
              count, std::sqrt(sum2 / count), worst);
  ASSERT_GT(count, 20);
  EXPECT_LT(worst, 6.0);
}

// 90 degrees on the 30-degree staircase (box 5 R0 along the wall: the 90-degree cap is 2 R0
// wide; ~17 s CPU), the validated setting with the wide wall normal. With the local normal this
// drop settled at 96.7 (box 8 R0, docs/fluid.md); with the wide normal 91.2 (box 5) / 91.9 (box 8).
TEST(FluidWettingAngles, NinetyOnThirtyDegreeStaircase) {
  const auto r = test::runWettingAverage(90.0, 30.0, 10, 0.12, 0.01, test::kWettingGhostSettings, 0.005, 5.0);
  char res[260];
  std::snprintf(res, sizeof res,
                "2D wall tilted 30 degrees as a lattice staircase, R0/dx = 10, box 5 R0, rectangle start, quintic h = dx, "
                "Oh = 0.036, equal densities, p_b = 100 Pa, mean over 60-120 ms (%.1f to %.1f), %lld steps",
                r.lo, r.hi, r.steps);
  test::recordValidation({"fluid_wetting_tilted30_theta90_R10_box5",
                          "contact angle (degrees), circle fit in the wall frame above 2 dx, time mean", r.mean, 90.0,
                          std::abs(r.mean - 90.0) / 90.0, res, r.wall, "|error| < 5 degrees",
                          "prescribed wall angle (Eq. 1.10), wetting: normal with ghost colour, wetting_scale 0.05, "
                          "wall_normal: wide"});
  EXPECT_NEAR(r.mean, 90.0, 5.0);
  EXPECT_NEAR(r.cap, 90.0, 10.0);
}
