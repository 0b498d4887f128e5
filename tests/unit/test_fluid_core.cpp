// Unit tests of the fluid module core: EOS (Eq. 1.4, Tait), parameter errors, hydrostatic box at
// rest between walls (extended summation, Sec. 5.1), density-variation warning, time step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

namespace {

// A closed 2D box: fluid [0, W] x [0, H], walls (3 layers) on all four sides.
struct Tank {
  Simulation sim{2};
  FluidModule* fluid = nullptr;
  fs::Stepper stepper;
  double W = 0.02, H = 0.02, dx = 1e-3, rho0 = 1000.0, c = 5.0, g = 9.81;
  double pb = 0.0;
  Tank(bool hydrostatic, const std::string& extra = "") {
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3 * dx);
    sim.domain.lo = {-4 * dx, -4 * dx, 0};
    sim.domain.hi = {W + 4 * dx, H + 4 * dx, 0};
    const int water = fs::addMaterial(sim, "water", "fluid",
                                      "{density: 1000, sound_speed: 5, viscosity: 1.0e-3, background_pressure: " +
                                          std::to_string(pb) + "}");
    const int wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000}");
    std::string sec = "{gravity: [0, -9.81]" + std::string(", artificial_viscosity: 0.1") + std::string(hydrostatic ? ", hydrostatic_level: 0.02" : "") + extra + "}";
    fluid = fs::addFluidModule(sim, sec);
    fs::addLattice(sim, {0, 0}, {W, H}, water);
    const double t = 3 * dx;
    fs::addLattice(sim, {-t, -t}, {W + t, H + t}, wall, [&](const double* x) {
      return x[0] < 0 || x[0] > W || x[1] < 0 || x[1] > H;
    });
    fluid->initialise(sim);
  }
  double run(double tEnd) {
    while (sim.time < tEnd * (1 - 1e-12)) {
      const double dt = stepper.step(sim, tEnd - sim.time);
      if (std::getenv("FLUID_DEBUG") && sim.step % 200 == 0)
        std::printf("step %lld t %.4e dt %.3e var %.3e\n", (long long)sim.step, sim.time, dt,
                    fluid->maxDensityVariation());
    }
    return sim.time;
  }
};

}  // namespace

TEST(FluidEos, LinearAndTaitRoundTrip) {
  FluidModule::MaterialData m;
  m.rho0 = 1000.0;
  m.soundSpeed = 20.0;
  m.backgroundPressure = 50.0;
  EXPECT_DOUBLE_EQ(pressureOf(m, 1001.0), 400.0 + 50.0);  // Eq. 1.4
  EXPECT_NEAR(densityOf(m, 450.0), 1001.0, 1e-9);
  m.eos = FluidModule::Eos::Tait;
  // Tait: p = rho0 c^2 / gamma ((rho/rho0)^gamma - 1) + p_b; slope c^2 at rho0.
  const double dp = pressureOf(m, 1000.001) - pressureOf(m, 999.999);
  EXPECT_NEAR(dp / 0.002, 400.0, 1e-3);
  EXPECT_NEAR(densityOf(m, pressureOf(m, 1010.0)), 1010.0, 1e-9);
}

TEST(FluidConfig, BadInputNamesKeyAndValue) {
  Simulation sim(2);
  sim.spacing = 1e-3;
  fs::addMaterial(sim, "water", "fluid", "{density: -1, sound_speed: 5, viscosity: 1.0e-3}");
  try {
    fs::addFluidModule(sim, "");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("density"), std::string::npos) << w;
    EXPECT_NE(w.find("-1"), std::string::npos) << w;
  }
  Simulation sim2(2);
  fs::addMaterial(sim2, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3, colr: 1}");
  EXPECT_THROW(fs::addFluidModule(sim2, ""), InputError);  // unknown key
  Simulation sim3(2);
  fs::addMaterial(sim3, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3}");
  EXPECT_THROW(fs::addFluidModule(sim3, "{density: sumation}"), InputError);
  Simulation sim4(2);
  fs::addMaterial(sim4, "wall", "wall", "{density: 1000, contact_angle: 200}");
  EXPECT_THROW(fs::addFluidModule(sim4, ""), InputError);
  Simulation sim5(2);
  fs::addMaterial(sim5, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3}");
  try {
    fs::addFluidModule(sim5, "{surface_tension: 0.05, wetting: normals}");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("wetting"), std::string::npos) << w;
    EXPECT_NE(w.find("normals"), std::string::npos) << w;
  }
  Simulation sim6(2);
  fs::addMaterial(sim6, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3}");
  EXPECT_THROW(fs::addFluidModule(sim6, "{wetting_scale: 0}"), InputError);
  for (const char* bad : {"{xsph: 1.5}", "{shifting: -1}"}) {  // out of range: key and value named
    Simulation s(2);
    fs::addMaterial(s, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3}");
    try {
      fs::addFluidModule(s, bad);
      ADD_FAILURE() << "expected InputError for " << bad;
    } catch (const InputError& e) {
      const std::string w = e.what(), key = std::string(bad).substr(1, std::string(bad).find(':') - 1);
      EXPECT_NE(w.find(key), std::string::npos) << w;
      EXPECT_NE(w.find(bad[1] == 'x' ? "1.5" : "-1"), std::string::npos) << w;
    }
  }
}

TEST(FluidCore, PhasesMotionAndColours) {
  Tank t(true);
  const auto& st = t.sim.store;
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mo = st.data(t.sim.motion);
  const std::int32_t* mt = st.data(st.material());
  for (Index i = 0; i < st.realCount(); ++i) {
    if (mt[i] == 0) {
      EXPECT_EQ(ph[i], kPhaseFluid);
      EXPECT_EQ(mo[i], kMotionFree);
    } else {
      EXPECT_EQ(ph[i], kPhaseWall);
      EXPECT_EQ(mo[i], kMotionFixed);
    }
  }
  EXPECT_NEAR(t.fluid->materialData(1).colour, 0.0, 1e-15);  // 90 degrees: cos = 0 (Eq. 1.10)
}

// A tank at rest under gravity stays at rest: the walls' extrapolated pressure carries the
// hydrostatic column (p_bottom = rho0 g H), nothing penetrates the walls.
TEST(FluidCore, HydrostaticTankStaysAtRest) {
  Tank t(true);
  const double tEnd = 0.1;  // ~2 sqrt(H/g) and ~25 acoustic crossings of H
  t.run(tEnd);
  const auto& st = t.sim.store;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const double* p = st.data(t.fluid->pressure);
  const std::int32_t* ph = st.data(st.phase());
  double xv = 0, yv = 0, vmax = 0.0, pBottom = 0.0, wBottom = 0.0, yMin = 1e9, yMax = -1e9, xMin = 1e9, xMax = -1e9;
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid) continue;
    if (std::hypot(v[2 * i], v[2 * i + 1]) > vmax) {
      vmax = std::hypot(v[2 * i], v[2 * i + 1]);
      xv = x[2 * i];
      yv = x[2 * i + 1];
    }
    yMin = std::min(yMin, x[2 * i + 1]);
    yMax = std::max(yMax, x[2 * i + 1]);
    xMin = std::min(xMin, x[2 * i]);
    xMax = std::max(xMax, x[2 * i]);
    // pressure of the fluid in the middle band, second row above the bottom
    if (x[2 * i + 1] < 2 * t.dx && std::abs(x[2 * i] - 0.5 * t.W) < 0.25 * t.W) {
      pBottom += p[i];
      wBottom += 1.0;
    }
  }
  pBottom /= wBottom;
  const double pRef = t.rho0 * t.g * (t.H - 1.0 * t.dx);  // mean height of the two rows = dx
  std::printf("max speed at (%.4f, %.4f)\n", xv, yv);
  std::printf("max speed %.3e m/s (sqrt(gH) = %.3f), bottom pressure %.2f Pa (ref %.2f)\n", vmax,
              std::sqrt(t.g * t.H), pBottom, pRef);
  EXPECT_LT(vmax, 5e-3 * std::sqrt(t.g * t.H));  // at rest up to acoustic noise
  EXPECT_NEAR(pBottom, pRef, 0.03 * pRef);
  EXPECT_GT(yMin, 0.0);  // no particle penetrates the walls
  EXPECT_GT(xMin, 0.0);
  EXPECT_LT(xMax, t.W);
  EXPECT_LT(yMax, t.H);
  EXPECT_LT(t.fluid->maxDensityVariation(), 0.03);
  t.sim.checkFinite();
}

// Starting from a uniform density the column compresses, oscillates and is damped toward the
// same hydrostatic state.
TEST(FluidCore, DensityBoundWarning) {
  Tank t(false, ", density_variation_bound: 0.001");
  t.run(0.01);
  EXPECT_GT(t.fluid->densityBoundExceeded(), 0);
  EXPECT_GT(t.fluid->maxDensityVariation(), 0.001);
  auto cols = t.sim.diagnostics();
  bool found = false;
  for (const auto& c : cols)
    if (c.first == "fluid_max_density_variation") found = true;
  EXPECT_TRUE(found);
}

TEST(FluidCore, TimeStepLimits) {
  Tank t(true);
  t.sim.evaluateRates();
  const double h = t.sim.kernel.h();
  const double dt = t.fluid->timeStepLimit(t.sim);
  EXPECT_LE(dt, 0.25 * h / t.c * (1 + 1e-12));  // acoustic CFL
  EXPECT_GT(dt, 0.0);
}

// "Model only what a scene requires": a single-phase scene without surface tension allocates no
// colour (5.6), normal (5.7), curvature (5.8) or interface field; with surface tension it does.
TEST(FluidFields, InterfaceFieldsOnlyWithSurfaceTension) {
  const char* names[] = {"colour", "colour_gradient", "curvature", "interface"};
  {
    Tank t(true);
    EXPECT_FALSE(t.fluid->surfaceTensionActive());
    for (const char* nm : names) EXPECT_FALSE(t.sim.store.has(nm)) << nm;
    EXPECT_FALSE(t.fluid->colour.valid());
    t.run(2e-3);  // the stages run without those fields
    for (const char* nm : names) EXPECT_FALSE(t.sim.store.has(nm)) << nm;
    EXPECT_LT(t.fluid->maxDensityVariation(), 0.03);
  }
  {
    Tank t(true, ", surface_tension: 0.07");
    EXPECT_TRUE(t.fluid->surfaceTensionActive());
    for (const char* nm : names) EXPECT_TRUE(t.sim.store.has(nm)) << nm;
    t.run(2e-3);
    EXPECT_LT(t.fluid->maxDensityVariation(), 0.03);
  }
}

// Wetting by a prescribed contact-line normal (Eq. 1.10, "wetting: normal"): a vertical
// liquid-gas interface meeting a flat wall of 60 degrees. Where the wall's Shepard fraction chi
// reaches wetting_scale the outward liquid normal is exactly n_w cos(theta) + t_w sin(theta)
// = (sin 60, cos 60); away from the wall (chi = 0) it stays the fluid's own normal (1, 0).
TEST(FluidWetting, PrescribedContactLineNormal) {
  const double dx = 1e-4, theta = 60.0 * 3.14159265358979323846 / 180.0, scale = 0.15;
  Simulation sim{2};
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, -3 * dx, 0};
  sim.domain.hi = {20 * dx, 14 * dx, 0};
  sim.domain.periodic = {true, false, false};
  const int liq = fs::addMaterial(sim, "liquid", "fluid", "{density: 1000, sound_speed: 2, viscosity: 0.05, colour: 1}");
  const int gas = fs::addMaterial(sim, "gas", "fluid", "{density: 1000, sound_speed: 2, viscosity: 0.05, colour: -1}");
  const int wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000, contact_angle: 60}");
  FluidModule* fluid = fs::addFluidModule(sim, "{surface_tension: 0.05, wetting_scale: 0.15}");
  fs::addLattice(sim, {0, 0}, {10 * dx, 14 * dx}, liq);
  fs::addLattice(sim, {10 * dx, 0}, {20 * dx, 14 * dx}, gas);
  fs::addLattice(sim, {0, -3 * dx}, {20 * dx, 0}, wall);
  fluid->initialise(sim);
  sim.updateNeighbours();
  fluid->kinematics(sim);
  const auto& st = sim.store;
  const double* x = st.data(st.position());
  const double* ng = st.data(fluid->colourGradient);
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const std::int32_t* ph = st.data(st.phase());
  const auto& nl = sim.neighbours;
  int nPrescribed = 0, nFree = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (ph[i] != kPhaseFluid || std::abs(x[2 * i] - 10 * dx) > dx) continue;  // the two columns at the interface
    double chi = 0.0;
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const Index j = nl.index[static_cast<size_t>(k)];
      if (ph[j] == kPhaseFluid) continue;
      chi += m[j] / rho[j] * sim.kernel.value(std::hypot(x[2 * i] - x[2 * j], x[2 * i + 1] - x[2 * j + 1]));
    }
    const double nn = std::hypot(ng[2 * i], ng[2 * i + 1]);
    ASSERT_GT(nn, 0.0);
    const double mx = -ng[2 * i] / nn, my = -ng[2 * i + 1] / nn;  // outward liquid normal
    if (chi >= scale) {
      EXPECT_NEAR(mx, std::sin(theta), 1e-9) << "y = " << x[2 * i + 1];
      EXPECT_NEAR(my, std::cos(theta), 1e-9) << "y = " << x[2 * i + 1];
      ++nPrescribed;
    } else if (chi == 0.0 && x[2 * i + 1] > 4 * dx && x[2 * i + 1] < 10 * dx) {
      EXPECT_NEAR(mx, 1.0, 1e-9);
      EXPECT_NEAR(my, 0.0, 1e-6);
      ++nFree;
    }
  }
  EXPECT_GE(nPrescribed, 2);  // at least the first row on both sides
  EXPECT_GE(nFree, 4);
}

// A periodic 12 x 12 lattice of water (dx = 1 mm, quintic h = dx) with the fluid section given.
static FluidModule* periodicWaterLattice(Simulation& sim, const std::string& section) {
  const double dx = 1e-3;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {12 * dx, 12 * dx, 0};
  sim.domain.periodic = {true, true, false};
  fs::addMaterial(sim, "water", "fluid", "{density: 1000, sound_speed: 10, viscosity: 1.0e-3}");
  FluidModule* fluid = fs::addFluidModule(sim, section);
  fs::addLattice(sim, {0, 0}, {12 * dx, 12 * dx}, 0);
  fluid->initialise(sim);
  return fluid;
}

// XSPH (Eq. 2.66, fluid key `xsph`): the field exists only when epsilon > 0; in a periodic fluid
// at rest with one particle moving at u, that particle's position rate correction is
// eps sum_b m_b / rho_ab (v_b - v_a) W_ab = -eps u sum_{b != a} V_b W_ab exactly, a neighbour b
// gets +eps u V_a W_ab, and a uniform translation gives no correction at all.
TEST(FluidXsph, CorrectionMatchesClosedSumAndOnlyWhenAsked) {
  for (double eps : {0.0, 0.5}) {
    const double dx = 1e-3;
    Simulation sim{2};
    char buf[64];
    std::snprintf(buf, sizeof buf, "{xsph: %g}", eps);
    FluidModule* fluid = periodicWaterLattice(sim, buf);
    EXPECT_EQ(fluid->positionCorrection.valid(), eps > 0.0);
    EXPECT_EQ(sim.store.has("position_correction"), eps > 0.0);
    if (eps == 0.0) continue;
    auto& st = sim.store;
    const Index n = st.realCount();
    // (pointers are fetched again after every evaluation: ghosts may grow the store, and the
    // cell reordering permutes the particles)
    double* v = st.data(st.velocity());
    for (Index i = 0; i < 2 * n; ++i) v[i] = 0.3;  // uniform translation: no correction
    sim.evaluateRates();
    const double* dv = st.data(fluid->positionCorrection);
    for (Index i = 0; i < 2 * n; ++i) ASSERT_NEAR(dv[i], 0.0, 1e-14);
    v = st.data(st.velocity());
    for (Index i = 0; i < 2 * n; ++i) v[i] = 0.0;
    const double u = 0.2;
    v[0] = u;  // one particle moves (any one: the box is periodic)
    sim.evaluateRates();
    dv = st.data(fluid->positionCorrection);
    v = st.data(st.velocity());
    const double* x = st.data(st.position());
    Index a = 0;
    while (v[2 * a] == 0.0) ++a;
    const double V = dx * dx;  // m / rho at rest
    double sum = 0.0, rateB = 0.0;
    Index b = -1;
    for (Index j = 0; j < n; ++j) {
      if (j == a) continue;
      double X = x[2 * j] - x[2 * a], Y = x[2 * j + 1] - x[2 * a + 1];
      X -= 12 * dx * std::round(X / (12 * dx));
      Y -= 12 * dx * std::round(Y / (12 * dx));
      const double w = sim.kernel.value(std::hypot(X, Y));
      sum += V * w;
      if (std::abs(X - dx) < 1e-9 && std::abs(Y) < 1e-9) b = j, rateB = eps * u * V * w;
    }
    ASSERT_GE(b, 0);
    EXPECT_NEAR(dv[2 * a], -eps * u * sum, 1e-12);
    EXPECT_NEAR(dv[2 * a + 1], 0.0, 1e-14);
    EXPECT_NEAR(dv[2 * b], rateB, 1e-12);
    EXPECT_GT(rateB, 0.0);
  }
}

// Hydrostatic initialisation (`hydrostatic_level`) integrates dp/dz = -rho0 |g| down every
// column of particles, so a gas bubble in water starts at the water's pressure: in a column that
// misses the bubble p = p_b + rho_w g (L - z); below the bubble the column is lighter by
// (rho_w - rho_g) g n_gas dx (n_gas gas particles above in that column, trapezoid rule); each particle's density
// is its own EOS inverted at that pressure, and its mass is scaled so that m / rho stays dx^2.
TEST(FluidCore, HydrostaticColumnsThroughABubble) {
  const double dx = 1e-4, Wd = 20 * dx, H = 30 * dx, R = 5 * dx, g = 9.81, pb = 50.0;
  Simulation sim{2};
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {Wd, H, 0};
  sim.domain.periodic = {true, false, false};
  const int water = fs::addMaterial(sim, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3, background_pressure: 50}");
  const int gas = fs::addMaterial(sim, "gas", "fluid", "{density: 1, sound_speed: 50, viscosity: 1.0e-5, background_pressure: 50, colour: -1}");
  FluidModule* fluid = fs::addFluidModule(sim, "{gravity: [0, -9.81], hydrostatic_level: 0.003}");
  auto inBubble = [&](const double* x) { return std::hypot(x[0] - 0.5 * Wd, x[1] - 0.5 * H) < R; };
  fs::addLattice(sim, {0, 0}, {Wd, H}, gas, inBubble);
  fs::addLattice(sim, {0, 0}, {Wd, H}, water, [&](const double* x) { return !inBubble(x); });
  fluid->initialise(sim);
  const auto& st = sim.store;
  const double* x = st.data(st.position());
  const double* p = st.data(fluid->pressure);
  const double* rho = st.data(st.density());
  const std::int32_t* mt = st.data(st.material());
  const Index n = st.realCount();
  int checkedFree = 0, checkedBelow = 0;
  for (Index i = 0; i < n; ++i) {
    int gasAbove = 0;
    for (Index j = 0; j < n; ++j)
      if (mt[j] == gas && std::abs(x[2 * j] - x[2 * i]) < 1e-9 && x[2 * j + 1] > x[2 * i + 1]) ++gasAbove;
    // (a gas particle itself: the trapezoid rule has half an interval of gas above it)
    const double gasDepth = (gasAbove + (mt[i] == gas ? 0.5 : 0.0)) * dx;
    const double ref = pb + g * (1000.0 * (H - x[2 * i + 1]) - (1000.0 - 1.0) * gasDepth);
    ASSERT_NEAR(p[i], ref, 1e-9 * ref) << "particle at " << x[2 * i] << ", " << x[2 * i + 1];
    const double rho0 = mt[i] == water ? 1000.0 : 1.0, c = mt[i] == water ? 5.0 : 50.0;
    ASSERT_NEAR(rho[i], rho0 + (ref - pb) / (c * c), 1e-9 * rho0);
    // compressed in place: the particle keeps its lattice cell as volume, its mass follows
    ASSERT_NEAR(st.data(st.mass())[i] / rho[i], dx * dx, 1e-12 * dx * dx);
    if (mt[i] == water && gasAbove == 0) ++checkedFree;
    if (mt[i] == water && gasAbove > 0) ++checkedBelow;
  }
  EXPECT_GT(checkedFree, 100);
  EXPECT_GT(checkedBelow, 50);
}

// Particle shifting (fluid key `shifting`): -A h U grad C with C = sum_b V_b W_ab. On a perfect
// periodic lattice grad C = 0 (no correction); a particle pushed off its site is moved back
// toward it (the correction points against the displacement) and capped at U / 2; off, the
// correction field does not exist.
TEST(FluidShifting, MovesADisplacedParticleBackAndNothingOnALattice) {
  for (double A : {0.0, 2.0}) {
    const double dx = 1e-3, U = 0.1;
    Simulation sim{2};
    char buf[64];
    std::snprintf(buf, sizeof buf, "{shifting: %g}", A);
    FluidModule* fluid = periodicWaterLattice(sim, buf);
    EXPECT_EQ(fluid->positionCorrection.valid(), A > 0.0);
    if (A == 0.0) continue;
    auto& st = sim.store;
    const Index n = st.realCount();
    double* v = st.data(st.velocity());
    for (Index i = 0; i < n; ++i) v[2 * i] = U, v[2 * i + 1] = 0.0;  // sets the velocity scale
    sim.evaluateRates();
    const double* dv = st.data(fluid->positionCorrection);
    for (Index i = 0; i < 2 * n; ++i) ASSERT_NEAR(dv[i], 0.0, 1e-12 * U);
    double* x = st.data(st.position());
    const double shift[2] = {0.2 * dx, 0.1 * dx};
    x[0] += shift[0];  // push particle 0 off its site (ids follow it through reordering)
    x[1] += shift[1];
    const std::int32_t id0 = st.data(st.id())[0];
    sim.evaluateRates();
    dv = st.data(fluid->positionCorrection);
    const std::int32_t* id = st.data(st.id());
    Index a = 0;
    while (id[a] != id0) ++a;
    const double dot = dv[2 * a] * shift[0] + dv[2 * a + 1] * shift[1];
    const double len = std::hypot(dv[2 * a], dv[2 * a + 1]);
    EXPECT_LT(dot, -0.5 * len * std::hypot(shift[0], shift[1]));  // within 60 degrees of -shift
    EXPECT_GT(len, 0.0);
    EXPECT_LE(len, 0.5 * U * (1 + 1e-12));
  }
}

// Issue 14: `pressure_reference: background` subtracts the run's background pressure in the
// pressure force, so a uniform pressure exerts no force on a disordered arrangement (with Eq. 5.2b
// it pushes a displaced particle back: the spurious stiffness); `transport_velocity` (Adami et
// al. 2013) moves that push into the advection (position_correction = -dt p_b / m_a sum_b
// (V_a^2 + V_b^2) grad W) and needs a positive background pressure.
namespace {
FluidModule* uniformPressureLattice(Simulation& sim, const std::string& section, double pb) {
  const double dx = 1e-3;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {12 * dx, 12 * dx, 0};
  sim.domain.periodic = {true, true, false};
  char buf[160];
  std::snprintf(buf, sizeof buf, "{density: 1000, sound_speed: 10, viscosity: 1.0e-3, background_pressure: %g}", pb);
  fs::addMaterial(sim, "water", "fluid", buf);
  FluidModule* fluid = fs::addFluidModule(sim, section);
  fs::addLattice(sim, {0, 0}, {12 * dx, 12 * dx}, 0);
  fluid->initialise(sim);
  return fluid;
}
}  // namespace

TEST(FluidBackgroundPressure, ReferenceRemovesTheUniformPressureForceTransportVelocityMovesIt) {
  const double dx = 1e-3, pb = 1000.0;
  for (const char* section : {"{}", "{pressure_reference: background}",
                              "{pressure_reference: background, transport_velocity: true}"}) {
    SCOPED_TRACE(section);
    Simulation sim{2};
    FluidModule* fluid = uniformPressureLattice(sim, section, pb);
    const bool reference = std::string(section).find("reference") != std::string::npos;
    const bool transport = std::string(section).find("transport") != std::string::npos;
    EXPECT_EQ(fluid->positionCorrection.valid(), transport);
    auto& st = sim.store;
    double* x = st.data(st.position());
    const double shift[2] = {0.2 * dx, 0.1 * dx};
    x[0] += shift[0];
    x[1] += shift[1];
    const std::int32_t id0 = st.data(st.id())[0];
    sim.dt = 1e-5;
    sim.evaluateRates();
    const std::int32_t* id = st.data(st.id());
    Index a = 0;
    while (id[a] != id0) ++a;
    const double* acc = st.data(sim.acceleration);
    const double dot = acc[2 * a] * shift[0] + acc[2 * a + 1] * shift[1];
    const double len = std::hypot(acc[2 * a], acc[2 * a + 1]);
    if (reference) {
      // p_b / (rho dx) = 1 m/s^2 is the scale of the force without the reference
      for (Index i = 0; i < st.realCount(); ++i)
        ASSERT_LT(std::hypot(acc[2 * i], acc[2 * i + 1]), 1e-9) << "particle " << i;
    } else {
      EXPECT_GT(len, 1e-3);                                            // pushed ...
      EXPECT_LT(dot, -0.5 * len * std::hypot(shift[0], shift[1]));    // ... back to its site
    }
    if (transport) {
      const double* dv = st.data(fluid->positionCorrection);
      const double dot2 = dv[2 * a] * shift[0] + dv[2 * a + 1] * shift[1];
      const double len2 = std::hypot(dv[2 * a], dv[2 * a + 1]);
      EXPECT_GT(len2, 0.0);
      EXPECT_LT(dot2, -0.5 * len2 * std::hypot(shift[0], shift[1]));  // moved back
    }
  }
  Simulation sim{2};
  EXPECT_THROW(uniformPressureLattice(sim, "{transport_velocity: true}", 0.0), InputError);
}

// Continuity form (fluid key `continuity_form`, libcore continuityTerm, docs/fluid.md
// "Energy-consistent continuity"). An inviscid periodic fluid, disordered positions, densities
// and velocities: with the mass form sum_b m_b v_ab . grad W the power of the pressure forces
// (Eq. 5.2b) is exactly minus the rate of the compression energy sum_a m_a e(rho_a)
// (de/drho = p/rho^2), i.e. sum_a m_a (v_a . a_a + p_a/rho_a^2 drho_a/dt) = 0 to round-off; with
// Eq. 5.1a it is not (the residual 1/2 sum m_a m_b (v_ab . grad W)(1/rho_b - 1/rho_a)
// (p_a/rho_a - p_b/rho_b)). A misspelt value is refused, naming key and value.
TEST(FluidContinuity, MassFormConservesEnergyPairwiseVolumeFormDoesNot) {
  double relative[2] = {0.0, 0.0};
  const char* forms[2] = {"volume", "mass"};
  for (int f = 0; f < 2; ++f) {
    const double dx = 1e-3, L = 12 * dx;
    Simulation sim{2};
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3 * dx);
    sim.domain.lo = {0, 0, 0};
    sim.domain.hi = {L, L, 0};
    sim.domain.periodic = {true, true, false};
    fs::addMaterial(sim, "water", "fluid",
                    "{density: 1000, sound_speed: 10, viscosity: 0, background_pressure: 20}");
    FluidModule* fluid =
        fs::addFluidModule(sim, std::string("{continuity_form: ") + forms[f] + ", pressure_gradient: symmetric}");
    fs::addLattice(sim, {0, 0}, {L, L}, 0);
    fluid->initialise(sim);
    auto& st = sim.store;
    const Index n = st.realCount();
    double* x = st.data(st.position());
    double* v = st.data(st.velocity());
    double* rho = st.data(st.density());
    std::srand(7);
    auto noise = [] { return 2.0 * std::rand() / static_cast<double>(RAND_MAX) - 1.0; };
    for (Index i = 0; i < n; ++i) {
      for (int a = 0; a < 2; ++a) {
        x[2 * i + a] = std::fmod(x[2 * i + a] + 0.15 * dx * noise() + L, L);
        v[2 * i + a] = 0.1 * noise();
      }
      rho[i] = 1000.0 * (1.0 + 0.02 * noise());
    }
    sim.evaluateRates();
    const double* m = st.data(st.mass());
    const double* acc = st.data(sim.acceleration);
    const double* drho = st.data(fluid->densityRate);
    const double* p = st.data(fluid->pressure);
    v = st.data(st.velocity());
    rho = st.data(st.density());
    double kinetic = 0.0, compression = 0.0;
    for (Index i = 0; i < n; ++i) {
      kinetic += m[i] * (v[2 * i] * acc[2 * i] + v[2 * i + 1] * acc[2 * i + 1]);
      compression += m[i] * p[i] / (rho[i] * rho[i]) * drho[i];
    }
    relative[f] = std::abs(kinetic + compression) / std::abs(kinetic);
    std::printf("  %s: kinetic power %.6e W, compression power %.6e W, relative residual %.2e\n",
                forms[f], kinetic, compression, relative[f]);
  }
  EXPECT_LT(relative[1], 1e-10);  // mass form: round-off
  EXPECT_GT(relative[0], 1e-4);   // Eq. 5.1a: the residual power
  Simulation bad(2);
  fs::addMaterial(bad, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3}");
  try {
    fs::addFluidModule(bad, "{continuity_form: masss}");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("continuity_form"), std::string::npos) << w;
    EXPECT_NE(w.find("masss"), std::string::npos) << w;
  }
}

// Eq. 5.2b between fluids of unequal rest density throws the lighter one off its interface within
// a few steps (docs/drainage.md "A lighter gas in the throat"): the set-up warns, naming the key
// and the remedy, and only then (ratio > 2 with the symmetric form; not with the default Eq. 5.2a).
TEST(FluidConfig, SymmetricPressureGradientBetweenUnequalDensitiesWarns) {
  auto warning = [](const std::string& form, double gasDensity) {
    Simulation sim{2};
    sim.spacing = 1e-3;
    sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3e-3);
    fs::addMaterial(sim, "water", "fluid", "{density: 1000, sound_speed: 5, viscosity: 1.0e-3, colour: 1}");
    fs::addMaterial(sim, "gas", "fluid",
                    "{density: " + std::to_string(gasDensity) + ", sound_speed: 50, viscosity: 1.0e-5, colour: -1}");
    testing::internal::CaptureStderr();
    fs::addFluidModule(sim, form.empty() ? "{}" : "{pressure_gradient: " + form + "}");
    return testing::internal::GetCapturedStderr();
  };
  const std::string light = warning("symmetric", 10.0);
  EXPECT_NE(light.find("pressure_gradient"), std::string::npos) << light;
  EXPECT_NE(light.find("100x"), std::string::npos) << light;
  EXPECT_NE(light.find("use pressure_gradient: volume (Eq. 5.2a) or hu_adams"), std::string::npos) << light;
  EXPECT_EQ(warning("hu_adams", 10.0), "");
  EXPECT_EQ(warning("volume", 10.0), "");
  EXPECT_EQ(warning("", 10.0), "");  // no key: the default, Eq. 5.2a
  EXPECT_EQ(warning("symmetric", 1000.0), "");
  EXPECT_EQ(warning("symmetric", 600.0), "");  // ratio 1.67: below the warning's 2
}

namespace {
// A periodic 2D box, 12 x 12 particles (Wendland C2, h 1.3 dx), water (rho 1000, c 10) in the
// lower half and a light fluid (rho0 = 1000 / ratio, c = 10 sqrt(ratio): the same bulk modulus)
// in the upper half, both at the background pressure pb, with the fluid section `section` and
// the neighbour list `list` (full, half or cells).
FluidModule* twoFluidBox(Simulation& sim, const std::string& section, double ratio, double pb,
                         Simulation::NeighbourListChoice list) {
  const double dx = 1e-3, L = 12 * dx;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3 * dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {L, L, 0};
  sim.domain.periodic = {true, true, false};
  char buf[200];
  std::snprintf(buf, sizeof buf, "{density: 1000, sound_speed: 10, viscosity: 0, background_pressure: %g}", pb);
  const int water = fs::addMaterial(sim, "water", "fluid", buf);
  std::snprintf(buf, sizeof buf,
                "{density: %g, sound_speed: %g, viscosity: 0, background_pressure: %g, colour: -1}",
                1000.0 / ratio, 10.0 * std::sqrt(ratio), pb);
  const int light = fs::addMaterial(sim, "light", "fluid", buf);
  testing::internal::CaptureStderr();  // the symmetric form's warning about the density ratio
  FluidModule* fluid = fs::addFluidModule(sim, section);
  testing::internal::GetCapturedStderr();
  fs::addLattice(sim, {0, 0}, {L, L / 2}, water);
  fs::addLattice(sim, {0, L / 2}, {L, L}, light);
  sim.neighbourListChoice = list;
  sim.chooseNeighbourList();
  fluid->initialise(sim);
  return fluid;
}
}  // namespace

// Eq. 5.2a (`pressure_gradient: volume`, fluid_pair.hpp) with the default continuity Eq. 5.1a:
// the compression rate sum_a m_a p_a/rho_a^2 drho_a/dt = sum_ab m_a m_b p_a/(rho_a rho_b) v_ab .
// grad W is exactly minus the power sum_a m_a v_a . a_a of the pressure forces, pair by pair. On
// a disordered periodic state of two fluids (densities 1:10 +- 2 %, random velocities) the
// residual |kinetic + compression| / |kinetic| is round-off on the full list (gather loop), the
// half list (vectorised block and scalar path) and the cell walk, and the three give the same
// rates; Eq. 5.2b with 5.1a leaves its residual power. With `pressure_reference: background` the
// force uses p - p_ref, so the identity holds with (p - p_ref)/rho^2.
TEST(FluidPressureGradient, VolumeFormConservesEnergyWithEq51aOnEveryNeighbourList) {
  using NL = Simulation::NeighbourListChoice;
  struct Case {
    const char* section;
    NL list;
    double pRef;
  };
  const Case cases[] = {{"{pressure_gradient: volume}", NL::Full, 0.0},
                        {"{pressure_gradient: volume}", NL::Half, 0.0},
                        {"{pressure_gradient: volume}", NL::Cells, 0.0},
                        {"{pressure_gradient: volume, pressure_reference: background}", NL::Half, 20.0},
                        {"{pressure_gradient: symmetric}", NL::Full, 0.0}};
  std::vector<std::vector<double>> rates;
  double relative[5];
  for (int c = 0; c < 5; ++c) {
    SCOPED_TRACE(cases[c].section);
    Simulation sim{2};
    FluidModule* fluid = twoFluidBox(sim, cases[c].section, 10.0, 20.0, cases[c].list);
    auto& st = sim.store;
    const Index n = st.realCount();
    double* x = st.data(st.position());
    double* v = st.data(st.velocity());
    double* rho = st.data(st.density());
    const std::int32_t* mt = st.data(st.material());
    const double L = 12e-3, dx = 1e-3;
    std::srand(11);
    auto noise = [] { return 2.0 * std::rand() / static_cast<double>(RAND_MAX) - 1.0; };
    for (Index i = 0; i < n; ++i) {
      for (int a = 0; a < 2; ++a) {
        x[2 * i + a] = std::fmod(x[2 * i + a] + 0.15 * dx * noise() + L, L);
        v[2 * i + a] = 0.1 * noise();
      }
      rho[i] = (mt[i] == 0 ? 1000.0 : 100.0) * (1.0 + 0.02 * noise());
    }
    sim.evaluateRates();
    EXPECT_EQ(sim.halfNeighbourList, cases[c].list != NL::Full);
    EXPECT_EQ(sim.cellWalk, cases[c].list == NL::Cells);
    const double* m = st.data(st.mass());
    const double* acc = st.data(sim.acceleration);
    const double* drho = st.data(fluid->densityRate);
    const double* p = st.data(fluid->pressure);
    const std::int32_t* id = st.data(st.id());
    v = st.data(st.velocity());
    rho = st.data(st.density());
    double kinetic = 0.0, compression = 0.0;
    std::vector<double> byId(static_cast<size_t>(3 * n));
    for (Index i = 0; i < n; ++i) {
      kinetic += m[i] * (v[2 * i] * acc[2 * i] + v[2 * i + 1] * acc[2 * i + 1]);
      compression += m[i] * (p[i] - cases[c].pRef) / (rho[i] * rho[i]) * drho[i];
      for (int a = 0; a < 2; ++a) byId[static_cast<size_t>(3 * id[i] + a)] = acc[2 * i + a];
      byId[static_cast<size_t>(3 * id[i] + 2)] = drho[i];
    }
    rates.push_back(byId);
    relative[c] = std::abs(kinetic + compression) / std::abs(kinetic);
    std::printf("  %-62s list %d: kinetic power %.6e W, compression %.6e W, relative residual %.2e\n",
                cases[c].section, static_cast<int>(cases[c].list), kinetic, compression, relative[c]);
  }
  for (int c = 0; c < 4; ++c) EXPECT_LT(relative[c], 1e-10) << cases[c].section;
  EXPECT_GT(relative[4], 1e-4);  // Eq. 5.2b with 5.1a: the residual power
  // The three lists give the same rates (sums in another order: round-off).
  for (int c = 1; c < 3; ++c) {
    double diff = 0.0, scale = 0.0;
    for (size_t k = 0; k < rates[0].size(); ++k) {
      diff = std::max(diff, std::abs(rates[static_cast<size_t>(c)][k] - rates[0][k]));
      scale = std::max(scale, std::abs(rates[0][k]));
    }
    EXPECT_LT(diff, 1e-12 * scale) << "list " << c;
  }
}

// Two fluids at rest with densities 1:100 (the same bulk modulus, both at the background pressure
// 100 Pa, no gravity, no surface tension) on the periodic lattice: with Eq. 5.2a the pressure
// forces cancel at every particle (the neighbours are weighted by their volumes, equal on both
// sides) and the state stays at rest; Eq. 5.2b gives a light particle at the interface its own
// pressure m_b p_a / rho_a^2 summed over heavy neighbours, 100x what light neighbours give
// (docs/drainage.md "A lighter gas in the throat"), and sets it moving at once. 20 steps.
TEST(FluidPressureGradient, TwoFluidsOneToHundredStayAtRestWithEq52a) {
  double speed[2] = {0.0, 0.0};
  const char* forms[2] = {"volume", "symmetric"};
  for (int f = 0; f < 2; ++f) {
    Simulation sim{2};
    twoFluidBox(sim, std::string("{pressure_gradient: ") + forms[f] + "}", 100.0, 100.0,
                Simulation::NeighbourListChoice::Half);
    fs::Stepper stepper;
    for (int k = 0; k < 20; ++k) stepper.step(sim);
    const auto& st = sim.store;
    const double* v = st.data(st.velocity());
    for (Index i = 0; i < st.realCount(); ++i)
      speed[f] = std::max(speed[f], std::hypot(v[2 * i], v[2 * i + 1]));
    std::printf("  %s: largest speed after 20 steps (t = %.3e s) %.3e m/s\n", forms[f], sim.time,
                speed[f]);
  }
  // p_b / (rho_light dx) dt ~ 1e4 m/s^2 x 3e-6 s per step is the scale of a force left over
  EXPECT_LT(speed[0], 1e-9);
  EXPECT_GT(speed[1], 1e-2);
}
