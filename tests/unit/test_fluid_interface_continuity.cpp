// Unit test of the fluid key `continuity_interface: acoustic` (issue 16, docs/drainage.md "The
// inlet meniscus at density ratio 1000"): in the continuity term of a pair of two different fluids
// the neighbour's velocity is replaced by the interface velocity of the linearised (acoustic)
// Riemann problem between them, v* = (Z_a v_a + Z_b v_b) / (Z_a + Z_b), Z = rho0 c0, so the pair
// term of Eq. 5.1a is multiplied by w_ab = 2 Z_b / (Z_a + Z_b) (physics/fluid/fluid_pair.hpp
// interfaceContinuityWeight).
//
// Scene: a periodic 2D box, water in the lower half at rest, gas in the upper half moving down at
// U (both fluids uniform, no surface tension, no density diffusion). A water particle's only
// nonzero pair terms are those of its gas neighbours, a gas particle's those of its water
// neighbours, so one evaluation gives, particle by particle,
//   water: drho/dt (acoustic) = w_wg drho/dt (mean),  gas: drho/dt (acoustic) = w_gw drho/dt (mean)
// with w_wg = 2 Z_g / (Z_w + Z_g) = 0.0613 and w_gw = 2 - w_wg at density ratio 1000 with equal
// B = rho0 c0^2. Checked on the full (gather) and the half (symmetric) neighbour lists; at equal
// impedances (density ratio 1, two materials) the option changes no bit.
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
#include "physics/fluid/fluid_pair.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

struct Rates {
  std::vector<double> rate;      // density rate over density by particle id
  std::vector<int> material;     // material by particle id
};

std::string exact(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// One evaluation of the scene's rates at the initial state.
Rates evaluate(double gasRho, double gasC, const std::string& interfaceKey, const std::string& list,
               const std::string& name) {
  const std::string text = R"(dimension: 2
domain: {lo: [0.0, 0.0], hi: [0.001, 0.002], periodic: [true, true]}
spacing: 1.0e-4
h_over_dx: 1.0
kernel: quintic_spline
integrator: leapfrog
end_time: 1.0
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 5, viscosity: 0.01, colour: 1}
  - {name: gas, model: fluid, density: )" + exact(gasRho) + R"(, sound_speed: )" + exact(gasC) +
                           R"(, viscosity: 1.0e-4, colour: -1}
geometry:
  - {shape: box, lo: [0.0, 0.0], hi: [0.001, 0.001], material: water}
  - {shape: box, lo: [0.0, 0.001], hi: [0.001, 0.002], material: gas, velocity: [0.0, -0.1]}
fluid:
  pressure_gradient: hu_adams
  continuity_interface: )" + interfaceKey + "\n";
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-fluid-interface-continuity";
  fsys::create_directories(dir);
  Scene scene = loadSceneText(text, (dir / (name + ".yaml")).string());
  Simulation& s = *scene.sim;
  EXPECT_EQ(s.neighbours.half, list == "half") << name;
  s.updateNeighbours();
  s.evaluateRatesOnTheList();
  const auto* fm = dynamic_cast<const FluidModule*>(s.module("fluid"));
  EXPECT_NE(fm, nullptr);
  const Index n = s.store.realCount();
  const double* rate = s.store.data(fm->densityRate);
  const std::int32_t* id = s.store.data(s.store.id());
  const std::int32_t* mt = s.store.data(s.store.material());
  Rates r;
  r.rate.assign(static_cast<size_t>(n), 0.0);
  r.material.assign(static_cast<size_t>(n), -1);
  const double* rho = s.store.data(s.store.density());
  for (Index i = 0; i < n; ++i) {
    r.rate[static_cast<size_t>(id[i])] = rate[i] / rho[i];  // relative: water and gas alike
    r.material[static_cast<size_t>(id[i])] = mt[i];
  }
  return r;
}

}  // namespace

TEST(FluidInterfaceContinuity, AcousticWeightsTheOtherFluidsVelocityByImpedance) {
  const double rhoG = 1.0, cG = 5.0 * std::sqrt(1000.0);  // density ratio 1000, equal B
  const double zW = 1000.0 * 5.0, zG = rhoG * cG;
  const double wWG = interfaceContinuityWeight(zW, zG), wGW = 2.0 - wWG;
  EXPECT_NEAR(wWG, 2.0 / (1.0 + std::sqrt(1000.0)), 1e-15);
  for (const std::string list : {"full", "half"}) {
    const Rates mean = evaluate(rhoG, cG, "mean", list, "mean_" + list);
    const Rates acoustic = evaluate(rhoG, cG, "acoustic", list, "acoustic_" + list);
    ASSERT_EQ(mean.rate.size(), acoustic.rate.size());
    double largest = 0.0, worst = 0.0;
    int interfaceWater = 0, interfaceGas = 0;
    for (size_t k = 0; k < mean.rate.size(); ++k) largest = std::max(largest, std::abs(mean.rate[k]));
    ASSERT_GT(largest, 0.0);
    for (size_t k = 0; k < mean.rate.size(); ++k) {
      const double w = mean.material[k] == 0 ? wWG : wGW;
      const double e = std::abs(acoustic.rate[k] - w * mean.rate[k]) / largest;
      worst = std::max(worst, e);
      if (std::abs(mean.rate[k]) > 1e-3 * largest) ++(mean.material[k] == 0 ? interfaceWater : interfaceGas);
    }
    std::printf("%s list: w_wg %.5f, w_gw %.5f; %d water and %d gas particles at the interfaces; "
                "largest |acoustic - w mean| %.3g of the largest rate\n",
                list.c_str(), wWG, wGW, interfaceWater, interfaceGas, worst);
    EXPECT_LT(worst, 1e-12);
    EXPECT_GT(interfaceWater, 0);  // both interfaces of the periodic box, 3 rows on each side
    EXPECT_GT(interfaceGas, 0);
  }
}

TEST(FluidInterfaceContinuity, EqualImpedancesChangeNoBit) {
  for (const std::string list : {"full", "half"}) {
    const Rates mean = evaluate(1000.0, 5.0, "mean", list, "eq_mean_" + list);
    const Rates acoustic = evaluate(1000.0, 5.0, "acoustic", list, "eq_acoustic_" + list);
    ASSERT_EQ(mean.rate.size(), acoustic.rate.size());
    double largest = 0.0;
    for (size_t k = 0; k < mean.rate.size(); ++k) {
      EXPECT_EQ(mean.rate[k], acoustic.rate[k]) << "particle id " << k << " (" << list << ")";
      largest = std::max(largest, std::abs(mean.rate[k]));
    }
    EXPECT_GT(largest, 0.0);
  }
}

TEST(FluidInterfaceContinuity, UnknownValueNamed) {
  try {
    evaluate(1.0, 158.0, "riemann", "full", "bad");
    FAIL() << "no error for continuity_interface: riemann";
  } catch (const std::exception& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("continuity_interface"), std::string::npos) << m;
    EXPECT_NE(m.find("riemann"), std::string::npos) << m;
  }
}
