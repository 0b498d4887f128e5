// Unit test of the fluid key `wall_pressure: light_mirror` (issue 14, docs/fluid.md "Gas bubble
// trapped in a dead-end pore", ratio 1000): a fluid lighter than the heaviest fluid of the scene
// takes its own pressure and density at wall particles (the mirror model) instead of the wall's
// extrapolated pressure, the Shepard mean over all its fluid neighbours (Adami et al. 2012).
//
// Scene: a 2D channel periodic in x between two walls (3 rows each), water (1000 kg/m^3) in the
// left half and gas (1 kg/m^3, the water's bulk modulus) in the right half, at rest; the gas at
// 200 Pa and the water at 100 Pa (their background pressures), as a gas held by a meniscus' Laplace
// pressure. One evaluation of the accelerations (hu_adams, no surface tension):
//  - extrapolated: a wall particle under the interface carries the mean of the two pressures, and
//    the gas particles next to the wall near the interface are pushed sideways (the pair with the
//    wall is weaker on the water's side): the pull that carried the trapped bubble's corner gas
//    into the wall;
//  - light_mirror: the same gas particles see their own pressure at the wall: the sideways push is
//    gone (what remains is the Hu-Adams gas-water pair's 1/1000 share of the water's pressure);
//  - the water's accelerations do not change (it keeps the extrapolation), nor does any particle's
//    at equal densities (no fluid is lighter than the heaviest).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"
#include "physics/fluid/fluid_module.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

struct State {
  std::vector<double> ax, ay, x, y;
  std::vector<int> material;
};

State evaluate(double gasRho, double gasC, const std::string& key, const std::string& name) {
  char gas[200];
  std::snprintf(gas, sizeof gas,
                "  - {name: gas, model: fluid, density: %.17g, sound_speed: %.17g, viscosity: 1.0e-4, colour: -1, "
                "background_pressure: 200}\n",
                gasRho, gasC);
  const std::string text = std::string(R"(dimension: 2
domain: {lo: [0.0, -0.0003], hi: [0.002, 0.0013], periodic: [true, false]}
spacing: 1.0e-4
h_over_dx: 1.0
kernel: quintic_spline
integrator: leapfrog
end_time: 1.0
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_list: full
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 2, viscosity: 0.01, colour: 1, background_pressure: 100}
)") + gas + R"(  - {name: wall, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [0.0, 0.0], hi: [0.001, 0.001], material: water}
  - {shape: box, lo: [0.001, 0.0], hi: [0.002, 0.001], material: gas}
  - {shape: box, lo: [0.0, -0.0003], hi: [0.002, 0.0], material: wall}
  - {shape: box, lo: [0.0, 0.001], hi: [0.002, 0.0013], material: wall}
fluid:
  pressure_gradient: hu_adams
  wall_pressure: )" + key + "\n";
  const std::string& scene = text;
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-fluid-wall-pressure";
  fsys::create_directories(dir);
  Scene sc = loadSceneText(scene, (dir / (name + ".yaml")).string());
  Simulation& s = *sc.sim;
  s.updateNeighbours();
  s.evaluateRatesOnTheList();
  const Index n = s.store.realCount();
  const double* a = s.store.data(s.acceleration);
  const double* x = s.store.data(s.store.position());
  const std::int32_t* id = s.store.data(s.store.id());
  const std::int32_t* mt = s.store.data(s.store.material());
  State r;
  r.ax.assign(static_cast<size_t>(n), 0.0);
  r.ay = r.ax, r.x = r.ax, r.y = r.ax;
  r.material.assign(static_cast<size_t>(n), -1);
  for (Index i = 0; i < n; ++i) {
    const size_t k = static_cast<size_t>(id[i]);
    r.ax[k] = a[2 * i], r.ay[k] = a[2 * i + 1], r.x[k] = x[2 * i], r.y[k] = x[2 * i + 1];
    r.material[k] = mt[i];
  }
  return r;
}

}  // namespace

TEST(FluidWallPressure, LightMirrorRemovesTheSidewaysPullOnTheGasAtTheWall) {
  const double cG = 2.0 * std::sqrt(1000.0);
  const State ex = evaluate(1.0, cG, "extrapolated", "ratio1000_extrapolated");
  const State mi = evaluate(1.0, cG, "light_mirror", "ratio1000_light_mirror");
  ASSERT_EQ(ex.ax.size(), mi.ax.size());
  // the gas particles of the bottom row (y = dx/2) next to the interface at x = 1 mm (within 3 dx)
  double exSide = 0.0, miSide = 0.0;
  int count = 0;
  for (size_t k = 0; k < ex.ax.size(); ++k) {
    if (ex.material[k] == 0) {
      EXPECT_EQ(ex.ax[k], mi.ax[k]) << "water particle id " << k;
      EXPECT_EQ(ex.ay[k], mi.ay[k]) << "water particle id " << k;
    }
    if (ex.material[k] != 1 || ex.y[k] > 1e-4 || std::abs(ex.x[k] - 1e-3) > 3e-4) continue;
    exSide = std::max(exSide, std::abs(ex.ax[k]));
    miSide = std::max(miSide, std::abs(mi.ax[k]));
    ++count;
  }
  std::printf("bottom-row gas next to the interface (%d particles): largest |a_x| %.4g m/s^2 (extrapolated), "
              "%.4g (light_mirror)\n", count, exSide, miSide);
  EXPECT_EQ(count, 3);
  EXPECT_GT(exSide, 100.0);           // the pull: of order (p_g - p_w) / (rho_g dx) / a few
  EXPECT_LT(miSide, 0.05 * exSide);   // gone but for the Hu-Adams pair's 1/1000 share
}

TEST(FluidWallPressure, EqualDensitiesChangeNoBit) {
  const State ex = evaluate(1000.0, 2.0, "extrapolated", "ratio1_extrapolated");
  const State mi = evaluate(1000.0, 2.0, "light_mirror", "ratio1_light_mirror");
  ASSERT_EQ(ex.ax.size(), mi.ax.size());
  for (size_t k = 0; k < ex.ax.size(); ++k) {
    EXPECT_EQ(ex.ax[k], mi.ax[k]) << "particle id " << k;
    EXPECT_EQ(ex.ay[k], mi.ay[k]) << "particle id " << k;
  }
}

TEST(FluidWallPressure, UnknownValueNamed) {
  try {
    evaluate(1.0, 63.0, "mirror_all", "bad");
    FAIL() << "no error for wall_pressure: mirror_all";
  } catch (const std::exception& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("wall_pressure"), std::string::npos) << m;
  }
}
