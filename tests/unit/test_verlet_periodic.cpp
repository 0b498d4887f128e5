// The Verlet skin with periodic axes (Simulation::updateNeighbours, PeriodicHalo::refresh): the
// halo is built with the width support + skin and kept between two searches (ghosts follow their
// sources, real particles are wrapped only at a search). A run with a skin must equal the run
// without one to round-off while particles cross the periodic faces:
//  - a 2D shear layer of water in a box periodic along both axes (every particle crosses);
//  - the 2D drainage sample (fluids, TL clay with damage, rigid plates, drainage body force,
//    periodic along the flow axis), 120 steps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

std::string shearLayer(double skin) {
  return std::string(R"(
dimension: 2
domain: {lo: [0, 0], hi: [0.2, 0.2], periodic: [true, true]}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 1.0
max_steps: 700
time_step: {adaptive: true, cfl: 1.0}
output: {every_steps: 100000}
neighbour_skin: )") + std::to_string(skin) + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.2, 0.1], material: water, velocity: [1.0, 0.3]}
  - {shape: box, lo: [0, 0.1], hi: [0.2, 0.2], material: water, velocity: [-1.0, 0.3]}
fluid:
  artificial_viscosity: 0.1
)";
}

std::string drainageSample(double skin) {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/drainage_pores_2d.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const size_t e = text.find("end_time: 0.04");
  EXPECT_NE(e, std::string::npos);
  text.replace(e, 14, "end_time: 0.04\nmax_steps: 120\nneighbour_skin: " + std::to_string(skin));
  return text;
}

struct Difference {
  double dx = 0, dv = 0, vmax = 0;
};

/// Largest position (minimum image over the periodic axes) and velocity differences by id.
Difference compare(const Simulation& a, const Simulation& b) {
  const int d = a.dimension();
  std::vector<Index> ia(static_cast<size_t>(a.store.realCount())), ib(ia.size());
  for (Index i = 0; i < a.store.realCount(); ++i) {
    ia[static_cast<size_t>(a.store.data(a.store.id())[i])] = i;
    ib[static_cast<size_t>(b.store.data(b.store.id())[i])] = i;
  }
  const double* xa = a.store.data(a.store.position());
  const double* xb = b.store.data(b.store.position());
  const double* va = a.store.data(a.store.velocity());
  const double* vb = b.store.data(b.store.velocity());
  Difference r;
  for (size_t k = 0; k < ia.size(); ++k)
    for (int c = 0; c < d; ++c) {
      double dx = xa[ia[k] * d + c] - xb[ib[k] * d + c];
      if (a.domain.periodic[static_cast<size_t>(c)]) {
        const double L = a.domain.length(c);
        dx -= L * std::round(dx / L);
      }
      r.dx = std::max(r.dx, std::abs(dx));
      r.dv = std::max(r.dv, std::abs(va[ia[k] * d + c] - vb[ib[k] * d + c]));
      r.vmax = std::max(r.vmax, std::abs(va[ia[k] * d + c]));
    }
  return r;
}

}  // namespace

TEST(VerletPeriodic, ShearLayerWithASkinEqualsTheRunWithout) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-verlet-periodic";
  fsys::remove_all(dir);
  fsys::create_directories(dir);
  RunOptions o;
  o.handleSignals = false;
  Scene plain = loadSceneText(shearLayer(0.0), (dir / "plain.yaml").string());
  o.outDir = (dir / "plain").string();
  ASSERT_EQ(runScene(plain, o).status, RunStatus::Finished);
  Scene skinned = loadSceneText(shearLayer(0.3), (dir / "skin.yaml").string());
  o.outDir = (dir / "skin").string();
  ASSERT_EQ(runScene(skinned, o).status, RunStatus::Finished);
  const Simulation& a = *plain.sim;
  const Simulation& b = *skinned.sim;
  ASSERT_EQ(a.step, b.step);
  ASSERT_GT(b.store.ghostCount(), 0);
  // The layers crossed the periodic faces several spacings deep: a lost image pair would show.
  ASSERT_GT(1.0 * a.time, 5.0 * a.spacing);
  EXPECT_GT(b.verlet.rebuildCount(), 1);
  EXPECT_LT(b.verlet.rebuildCount(), b.step / 2);
  const Difference r = compare(a, b);
  std::printf("shear layer, skin 0.3 dx: %lld searches in %lld steps (t = %.3g s); positions "
              "%.3g dx, velocities %.3g of vmax %.3g\n",
              static_cast<long long>(b.verlet.rebuildCount()), static_cast<long long>(b.step),
              a.time, r.dx / a.spacing, r.dv / r.vmax, r.vmax);
  EXPECT_LT(r.dx, 1e-10 * a.spacing);
  EXPECT_LT(r.dv, 1e-9 * r.vmax);
}

TEST(VerletPeriodic, DrainageSampleWithASkinEqualsTheRunWithout) {
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-verlet-periodic";
  fsys::create_directories(dir);
  RunOptions o;
  o.handleSignals = false;
  Scene plain = loadSceneText(drainageSample(0.0), (dir / "drain_plain.yaml").string());
  o.outDir = (dir / "drain_plain").string();
  ASSERT_EQ(runScene(plain, o).status, RunStatus::Finished);
  Scene skinned = loadSceneText(drainageSample(0.3), (dir / "drain_skin.yaml").string());
  o.outDir = (dir / "drain_skin").string();
  ASSERT_EQ(runScene(skinned, o).status, RunStatus::Finished);
  const Simulation& a = *plain.sim;
  const Simulation& b = *skinned.sim;
  ASSERT_EQ(a.step, 120);
  ASSERT_EQ(b.step, 120);
  EXPECT_LT(b.verlet.rebuildCount(), b.step / 2);
  const Difference r = compare(a, b);
  std::printf("drainage sample, skin 0.3 dx: %lld searches in %lld steps; positions %.3g dx, "
              "velocities %.3g of vmax %.3g\n",
              static_cast<long long>(b.verlet.rebuildCount()), static_cast<long long>(b.step),
              r.dx / a.spacing, r.dv / r.vmax, r.vmax);
  EXPECT_LT(r.dx, 1e-10 * a.spacing);
  EXPECT_LT(r.dv, 1e-9 * r.vmax);
  // Every module's columns agree (energies, plates, drainage, damage).
  const auto ca = a.diagnostics(), cb = b.diagnostics();
  ASSERT_EQ(ca.size(), cb.size());
  for (size_t k = 0; k < ca.size(); ++k) {
    if (std::isnan(ca[k].second) && std::isnan(cb[k].second)) continue;
    const double scale = std::max({std::abs(ca[k].second), std::abs(cb[k].second), 1e-30});
    EXPECT_LT(std::abs(ca[k].second - cb[k].second) / scale, 1e-7) << ca[k].first;
  }
}
