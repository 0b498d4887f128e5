// fluid: {wall_overlap_pressure: true} (issue 16, docs/fluid.md "Fluid creeping through the walls
// at a positive gauge pressure"): a fluid particle past the level S_w = sum_w V_w W_aw = 1/2 of
// the fixed walls' kernel sum (the face of a flat wall) gets
//   a_a += -(rho0 c0^2 / rho_a) (S_w - 1/2) grad_a S_w,
// and nothing changes for a particle on the fluid side. Scene: a closed 2D box 12 x 10 dx of water
// at rest (dx = 0.1 mm, quintic h = dx, three wall layers, c = 5 m/s, p_b = 600 Pa with
// pressure_reference: background and wall_push_only: the main job's fluid settings).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

namespace {

constexpr double kDx = 1e-4, kL = 12 * kDx, kH = 10 * kDx, kT = 3 * kDx;
const std::string kPush = ", wall_push_only: true", kOverlap = ", wall_overlap_pressure: true";

struct Box {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  int water = -1, wall = -1;
};

// The box with `keys` appended to the fluid section (after pressure_reference: background);
// each of `moves` places that particle at that position.
void build(Box& b, const std::string& keys, Simulation::NeighbourListChoice list,
           const std::vector<std::pair<Index, std::array<double, 2>>>& moves = {}, bool disturb = false) {
  Simulation& sim = b.sim;
  sim.spacing = kDx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, kDx);
  sim.domain.lo = {-kT, -kT, 0};
  sim.domain.hi = {kL + kT, kH + kT, 0};
  sim.domain.periodic = {false, false, false};
  b.water = fs::addMaterial(sim, "water", "fluid",
                            "{density: 1000, sound_speed: 5, viscosity: 0.01, background_pressure: 600}");
  b.wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000}");
  b.fluid = fs::addFluidModule(sim, "{pressure_reference: background" + keys + "}");
  fs::addLattice(sim, {0, 0}, {kL, kH}, b.water);
  fs::addLattice(sim, {-kT, -kT}, {kL + kT, kH + kT}, b.wall, [](const double* x) {
    return !(x[0] > 0 && x[0] < kL && x[1] > 0 && x[1] < kH);
  });
  double* x = sim.store.data(sim.store.position());
  if (disturb) {  // +-1 % densities (+-250 Pa): a pressure field for the pair sums to carry
    double* rho = sim.store.data(sim.store.density());
    const std::int32_t* mt = sim.store.data(sim.store.material());
    for (Index i = 0; i < sim.store.realCount(); ++i)
      if (mt[i] == b.water) rho[i] = 1000.0 * (1.0 + 0.01 * std::sin(12.9898 * static_cast<double>(i)));
  }
  for (const auto& [i, at] : moves) {
    x[2 * i] = at[0];
    x[2 * i + 1] = at[1];
  }
  sim.neighbourListChoice = list;
  sim.chooseNeighbourList();
  b.fluid->initialise(sim);
}

// The walls' kernel sum S_w and its gradient at fluid particle i, summed here over every wall
// particle (not through the module's neighbour list).
double wallSum(const Box& b, Index i, double grad[2]) {
  const auto& st = b.sim.store;
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const std::int32_t* mt = st.data(st.material());
  double s = 0.0;
  grad[0] = grad[1] = 0.0;
  for (Index j = 0; j < st.realCount(); ++j) {
    if (mt[j] != b.wall) continue;
    const double r[2] = {x[2 * i] - x[2 * j], x[2 * i + 1] - x[2 * j + 1]};
    const double d = std::hypot(r[0], r[1]);
    const double V = m[j] / rho[j];
    s += V * b.sim.kernel.value(d);
    const double F = d > 0.0 ? b.sim.kernel.F(d) : 0.0;
    grad[0] += V * F * r[0];
    grad[1] += V * F * r[1];
  }
  return s;
}

// The accelerations after one evaluation, by particle id (the store may reorder the particles).
std::vector<double> accelerations(Box& b) {
  b.sim.evaluateRates();
  const auto& st = b.sim.store;
  const double* a = st.data(b.sim.acceleration);
  const std::int32_t* id = st.data(st.id());
  std::vector<double> out(2 * static_cast<size_t>(st.realCount()));
  for (Index i = 0; i < st.realCount(); ++i) {
    out[2 * static_cast<size_t>(id[i])] = a[2 * i];
    out[2 * static_cast<size_t>(id[i]) + 1] = a[2 * i + 1];
  }
  return out;
}

// The store index of the particle with this id.
Index indexOf(const Box& b, Index id) {
  const auto& st = b.sim.store;
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.id())[i] == id) return i;
  return -1;
}

}  // namespace

// On the lattice no fluid particle reaches S_w = 1/2 (the corner sites included: 2D quintic
// h = dx), so the key changes no acceleration, bit for bit, with a +-1 % density field.
TEST(FluidWallOverlap, FluidOnTheLatticeIsUnchanged) {
  Box off, on;
  build(off, kPush, Simulation::NeighbourListChoice::Full, {}, true);
  build(on, kPush + kOverlap, Simulation::NeighbourListChoice::Full, {}, true);
  double largest = 0.0, g[2];
  for (Index i = 0; i < on.sim.store.realCount(); ++i)
    if (on.sim.store.data(on.sim.store.material())[i] == on.water) largest = std::max(largest, wallSum(on, i, g));
  EXPECT_GT(largest, 0.3);  // the corner sites (two walls)
  EXPECT_LT(largest, 0.5);
  const std::vector<double> a0 = accelerations(off), a1 = accelerations(on);
  ASSERT_EQ(a0.size(), a1.size());
  double largestA = 0.0;
  for (size_t k = 0; k < a0.size(); ++k) largestA = std::max(largestA, std::abs(a0[k]));
  EXPECT_GT(largestA, 1000.0);  // the disturbed densities' pressure forces, m/s^2
  for (size_t k = 0; k < a0.size(); ++k) ASSERT_EQ(a0[k], a1[k]) << "component " << k;
}

// A particle moved 0.2 dx past the left face (on a wall particle's row and between two rows)
// gets exactly the term above, pointing out of the wall; without the key the wall pair alone
// does not push it out at all (the fluid at rest is at p_b: zero gauge, so no pressure force).
TEST(FluidWallOverlap, ParticlePastTheFaceIsPushedOutByTheOverlapPressure) {
  // id 0 starts at (0.5, 0.5) dx, id 12 * 4 at (0.5, 4.5) dx: the first column (moved before the
  // module's initialisation, while the store still has the creation order)
  const Index p = 12 * 4, q = 12 * 6;
  const std::vector<std::pair<Index, std::array<double, 2>>> moves = {
      {p, {-0.2 * kDx, 4.5 * kDx}},   // a wall particle's row (y = 4.5 dx)
      {q, {-0.2 * kDx, 7.0 * kDx}}};  // between two rows
  Box off, on;
  build(off, kPush, Simulation::NeighbourListChoice::Full, moves);
  build(on, kPush + kOverlap, Simulation::NeighbourListChoice::Full, moves);
  const std::vector<double> a0 = accelerations(off), a1 = accelerations(on);
  for (Index i : {p, q}) {  // ids (the particles' creation order: rows of 12 from the bottom)
    double g[2];
    const Index at = indexOf(on, i);
    ASSERT_GE(at, 0);
    const double s = wallSum(on, at, g);
    const double rho = on.sim.store.data(on.sim.store.density())[at];
    EXPECT_GT(s, 0.55) << i;  // 0.2 dx past the face: ~0.5 + 0.62 x 0.2 in 3D, similar in 2D
    const double k = 1000.0 * 25.0 / rho * (s - 0.5);
    const double expect[2] = {-k * g[0], -k * g[1]};
    const double dax = a1[2 * i] - a0[2 * i], day = a1[2 * i + 1] - a0[2 * i + 1];
    EXPECT_NEAR(dax, expect[0], 1e-9 * std::abs(expect[0])) << i;
    EXPECT_NEAR(day, expect[1], 1e-9 * std::abs(expect[0]) + 1e-9) << i;
    EXPECT_GT(dax, 1000.0) << i;  // out of the wall (+x), m/s^2
    EXPECT_LT(std::abs(a0[2 * i]), 0.01 * dax) << i << ": without the key (zero gauge) nothing pushes";
  }
  // every other particle: the same bits
  for (Index i = 0; i < on.sim.store.realCount(); ++i) {  // by id
    if (i == p || i == q) continue;
    ASSERT_EQ(a0[2 * i], a1[2 * i]) << "id " << i;
    ASSERT_EQ(a0[2 * i + 1], a1[2 * i + 1]) << "id " << i;
  }
}

// The key needs the full list (the gather loop): a half list is refused when the list is chosen,
// naming the fluid module; without the key the same box takes the half list.
TEST(FluidWallOverlap, HalfNeighbourListIsRefused) {
  Box b;
  try {
    build(b, kOverlap, Simulation::NeighbourListChoice::Half);
    FAIL() << "the half list was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("module 'fluid'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("full or auto"), std::string::npos) << e.what();
  }
  Box plain;
  build(plain, "", Simulation::NeighbourListChoice::Half);
  EXPECT_TRUE(plain.sim.halfNeighbourList);
}
