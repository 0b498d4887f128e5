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
