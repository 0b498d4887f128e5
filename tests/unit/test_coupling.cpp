// Pair classes and the fluid-solid coupling (libcore/phases.hpp, physics/coupling): one owner per
// pair class, refused scenes, phases set before any module initialises, action = reaction of
// every pair force, the coupling added only where fluid and solid meet, the solid's wetting
// colour, one rate per integrated field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "libcore/integrator.hpp"
#include "libcore/scene.hpp"

using namespace poresph;

namespace {

std::string scene(const std::string& materials, const std::string& geometry,
                  const std::string& extra = "") {
  return R"(dimension: 2
domain: {lo: [0, 0], hi: [0.02, 0.02]}
spacing: 0.001
kernel: wendland_c2
end_time: 0.001
time_step: {adaptive: true}
output: {every_steps: 10}
materials:
)" + materials + "geometry:\n" + geometry + extra;
}

const std::string kWater =
    "  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3}\n";
const std::string kClay =
    "  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, poisson_ratio: 0.25, "
    "contact_angle: 60}\n";

std::string message(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

// A disturbed state: random-ish fluid densities (+-1 % of 1000 kg/m^3) so that the pressure varies.
void disturbFluidDensities(Simulation& sim) {
  ParticleStore& st = sim.store;
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseFluid)
      st.data(st.density())[i] = 1000.0 * (1.0 + 0.01 * std::sin(12.9898 * static_cast<double>(i)));
}

}  // namespace

TEST(PairClasses, CouplingIsAddedWhereFluidAndSolidMeetOnly) {
  Scene both = loadSceneText(scene(kWater + kClay,
                                   "  - {shape: box, lo: [0, 0], hi: [0.02, 0.01], material: clay}\n"
                                   "  - {shape: box, lo: [0, 0.01], hi: [0.02, 0.02], material: water}\n"),
                             "both.yaml");
  EXPECT_NE(both.sim->module("coupling"), nullptr);
  Scene fluid = loadSceneText(
      scene(kWater, "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"), "f.yaml");
  EXPECT_EQ(fluid.sim->module("coupling"), nullptr);
  // A solid material defined but no solid particle: no fluid-solid pairs, no coupling.
  Scene unused = loadSceneText(
      scene(kWater + kClay, "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"),
      "u.yaml");
  EXPECT_EQ(unused.sim->module("coupling"), nullptr);
}

namespace {
// A module of "rigid" test bodies that owns only rigid-rigid pairs: next to water, the
// fluid-rigid pairs have no owner.
class RigidProbe : public Module {
 public:
  std::string name() const override { return "rigid_probe"; }
  std::vector<std::string> materialModels() const override { return {"rigid_probe_body"}; }
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseRigid, kPhaseRigid)};
  }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet*) override {
    for (const Material* m : materials) {
      m->parameters.real("density", Range::positive());
      m->parameters.finish();
      sim.materials[static_cast<size_t>(m->id)].phase = kPhaseRigid;
    }
  }
};
PORESPH_REGISTER_MODULE(RigidProbe, "rigid_probe")
}  // namespace

TEST(PairClasses, AClassWithoutOwnerIsRefused) {
  const std::string m = message([] {
    loadSceneText(scene(kWater + "  - {name: grain, model: rigid_probe_body, density: 2650}\n",
                        "  - {shape: box, lo: [0, 0], hi: [0.02, 0.01], material: grain}\n"
                        "  - {shape: box, lo: [0, 0.01], hi: [0.02, 0.02], material: water}\n"),
                  "fluid_rigid.yaml");
  });
  EXPECT_NE(m.find("fluid_rigid.yaml"), std::string::npos) << m;
  EXPECT_NE(m.find("fluid and rigid particles"), std::string::npos) << m;
  EXPECT_NE(m.find("fluid-rigid pair forces"), std::string::npos) << m;
}

// A solid next to fixed wall particles gets the contact module (Eq. A.18 repulsion): a block
// thrown at a wall bounces off without entering it.
TEST(PairClasses, SolidBouncesOffAWall) {
  std::string text = scene(kClay + "  - {name: steel, model: wall, density: 7800}\n",
                           "  - {shape: box, lo: [0, 0], hi: [0.003, 0.02], material: steel}\n"
                           "  - {shape: box, lo: [0.004, 0.006], hi: [0.012, 0.014], "
                           "material: clay, velocity: [-2.0, 0]}\n");
  text.replace(text.find("end_time: 0.001"), 15, "end_time: 0.003");
  Scene s = loadSceneText(text, "bounce.yaml");
  Simulation& sim = *s.sim;
  ASSERT_NE(sim.module("contact"), nullptr);
  ParticleStore& st = sim.store;
  auto integrator = makeIntegrator("leapfrog");
  double closest = 1e300;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] != kPhaseSolid) continue;
      closest = std::min(closest, (st.data(st.position())[2 * i] - 0.0025) / 0.001);
    }
  }
  double momentum = 0.0;
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseSolid)
      momentum += st.data(st.mass())[i] * st.data(st.velocity())[2 * i];
  std::printf("  closest solid particle to the wall's last layer: %.2f dx; block momentum after "
              "%.4f s: %.3g (was %.3g)\n",
              closest, sim.time, momentum, -2.0 * 2000.0 * 0.008 * 0.008);
  EXPECT_GT(closest, 0.5);    // never closer than half a spacing to the wall particles
  EXPECT_GT(momentum, 0.0);   // it came back
}

namespace {
class ClaimingModule : public Module {
 public:
  explicit ClaimingModule(std::string n) : name_(std::move(n)) {}
  std::string name() const override { return name_; }
  std::vector<std::string> materialModels() const override { return {}; }
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseFluid, kPhaseFluid)};
  }
  void configure(Simulation&, const std::vector<const Material*>&, const ParameterSet*) override {}

 private:
  std::string name_;
};
}  // namespace

TEST(PairClasses, AClassClaimedTwiceIsRefused) {
  Simulation sim(2);
  sim.addModule(std::make_unique<ClaimingModule>("first"));
  sim.addModule(std::make_unique<ClaimingModule>("second"));
  sim.store.addParticles(3);  // phase 0 = fluid
  const std::string m = message([&] { sim.checkPairOwners(); });
  EXPECT_NE(m.find("fluid-fluid pair forces are claimed by several modules ('first', 'second')"),
            std::string::npos)
      << m;
  sim.store.data(sim.store.phase())[1] = kPhaseUnset;
  EXPECT_NE(message([&] { sim.checkPairOwners(); }).find("has no phase"), std::string::npos);
}

TEST(PairClasses, OneRatePerIntegratedFieldAndOneParticleSet) {
  Simulation sim(2);
  const RealField f = sim.store.addReal("f", 1);
  const RealField r = sim.store.addReal("f_rate", 1);
  sim.addIntegrated(f, r, true);
  EXPECT_NO_THROW(sim.addIntegrated(f, r, true));  // the same registration twice is harmless
  // The same rate for another set of particles used to be dropped silently.
  EXPECT_THROW(sim.addIntegrated(f, r, false), std::logic_error);
  // Fluid and solid XSPH both add into the one core position correction.
  EXPECT_EQ(sim.positionCorrection().id, sim.positionCorrection().id);
}

// A hydrostatic start with a solid block in the water: the solid's particles have their phase
// before the fluid initialises (they used to be phase 0 = fluid, and the fluid divided by their
// zero sound speed).
TEST(PairClasses, HydrostaticStartWithASolidPresent) {
  Scene s = loadSceneText(
      scene(kWater + kClay,
            "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"
            "  - {shape: box, lo: [0.008, 0.004], hi: [0.012, 0.008], material: clay}\n",
            "fluid: {gravity: [0, -9.81], hydrostatic_level: 0.02}\n"),
      "hydro.yaml");
  const ParticleStore& st = s.sim->store;
  const RealField p = st.real("pressure");
  Index solids = 0;
  for (Index i = 0; i < st.realCount(); ++i) {
    ASSERT_TRUE(std::isfinite(st.data(p)[i])) << i;
    ASSERT_TRUE(std::isfinite(st.data(st.density())[i])) << i;
    if (st.data(st.phase())[i] != kPhaseSolid) continue;
    ++solids;
    EXPECT_DOUBLE_EQ(st.data(st.density())[i], 2000.0);  // the fluid left the solid's density
  }
  EXPECT_EQ(solids, 16);
}

// Every pair force of the coupled step is applied to both particles: with no gravity, the sum
// of m a over all particles vanishes to round-off, and the solid feels the water.
TEST(PairClasses, CoupledForcesSumToZero) {
  Scene s = loadSceneText(
      scene(kWater + kClay,
            "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"
            "  - {shape: sphere, centre: [0.01, 0.01], radius: 0.004, material: clay, "
            "velocity: [0.3, -0.2]}\n",
            "fluid: {artificial_viscosity: 0.1}\n"),
      "sum.yaml");
  Simulation& sim = *s.sim;
  disturbFluidDensities(sim);
  ParticleStore& st = sim.store;
  sim.evaluateRates();
  Vec<2> sum = Vec<2>::Zero(), solid = Vec<2>::Zero();
  double scale = 0.0;
  for (Index i = 0; i < st.realCount(); ++i) {
    const Vec<2> f = st.data(st.mass())[i] * st.vec<2>(sim.acceleration, i);
    sum += f;
    scale += f.norm();
    if (st.data(st.phase())[i] == kPhaseSolid) solid += f;
  }
  EXPECT_GT(solid.norm(), 1e-3 * scale) << "the solid feels the fluid";
  EXPECT_LT(sum.norm(), 1e-12 * scale);
}

TEST(PairClasses, SolidParticlesCarryTheirWettingColour) {
  Scene s = loadSceneText(
      scene(kWater + kClay,
            "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"
            "  - {shape: box, lo: [0, 0], hi: [0.02, 0.004], material: clay}\n",
            "fluid: {surface_tension: 0.07}\n"),
      "wet.yaml");
  const ParticleStore& st = s.sim->store;
  const RealField c = st.real("colour");
  for (Index i = 0; i < st.realCount(); ++i)
    if (st.data(st.phase())[i] == kPhaseSolid) {
      EXPECT_NEAR(st.data(c)[i], 0.5, 1e-12);  // cos 60 degrees
      break;
    }
}

// Issue 11: "the position correction (XSPH 2.66 / shifting) as one core field that modules add
// into (today fluid and solid XSPH collide on the position rate)". A scene with the fluid's
// `xsph` and the clay's `xsph_epsilon` both on, on a disturbed velocity field: the core field
// `position_correction` holds the fluid's correction on the fluid particles and the solid's on
// the solid particles, each equal to what the run with only that module's XSPH gives (neither
// drops nor overwrites the other), and both are non-zero.
TEST(PairClasses, FluidAndSolidXsphAddIntoOnePositionCorrection) {
  auto correction = [](double fluidEps, double solidEps) {
    char clay[200];
    std::snprintf(clay, sizeof clay,
                  "  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e6, "
                  "poisson_ratio: 0.25, xsph_epsilon: %g}\n", solidEps);
    char fluid[80];
    std::snprintf(fluid, sizeof fluid, "fluid: {xsph: %g}\n", fluidEps);
    Scene s = loadSceneText(
        scene(kWater + clay,
              "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"
              "  - {shape: box, lo: [0.006, 0.006], hi: [0.014, 0.014], material: clay}\n",
              fluid),
        "xsph.yaml");
    Simulation& sim = *s.sim;
    ParticleStore& st = sim.store;
    double* v = st.data(st.velocity());
    for (Index i = 0; i < st.realCount(); ++i) {
      v[2 * i] = 0.1 * std::sin(12.9898 * i);
      v[2 * i + 1] = 0.1 * std::cos(78.233 * i);
    }
    sim.evaluateRates();
    const double* c = st.data(sim.positionCorrection());
    std::vector<double> out(c, c + 2 * st.realCount());
    std::vector<int> phase(st.data(st.phase()), st.data(st.phase()) + st.realCount());
    return std::make_pair(out, phase);
  };
  const auto both = correction(0.5, 0.5), fluidOnly = correction(0.5, 0.0), solidOnly = correction(0.0, 0.5);
  ASSERT_EQ(both.first.size(), fluidOnly.first.size());
  double fluidMax = 0.0, solidMax = 0.0, worst = 0.0;
  for (size_t i = 0; i < both.second.size(); ++i)
    for (int a = 0; a < 2; ++a) {
      const size_t k = 2 * i + static_cast<size_t>(a);
      const double expected = fluidOnly.first[k] + solidOnly.first[k];
      worst = std::max(worst, std::abs(both.first[k] - expected));
      if (both.second[i] == kPhaseFluid) fluidMax = std::max(fluidMax, std::abs(fluidOnly.first[k]));
      if (both.second[i] == kPhaseSolid) solidMax = std::max(solidMax, std::abs(solidOnly.first[k]));
    }
  std::printf("  largest correction: fluid %.3e, solid %.3e m/s; both on minus the sum of each "
              "alone: %.1e m/s\n", fluidMax, solidMax, worst);
  EXPECT_GT(fluidMax, 1e-3);  // 0.1 m/s disturbances: corrections of order 0.01-0.1 m/s
  EXPECT_GT(solidMax, 1e-3);
  EXPECT_LE(worst, 1e-12 * std::max(fluidMax, solidMax));
}

// Issue 11, Eq. 1.37 (no slip at the fluid-solid interface): plane Couette flow between a fixed
// fluid `wall` (below) and an elastic clay plate translating at U (region `motion: prescribed`,
// above; small-strain stress form: a Total-Lagrangian plate inverts once its translation passes
// half the period, J < 0 at 5 mm here, the minimum image of the displacement flipping),
// periodic along x, 10 fluid rows, Re = U H / nu = 0.1. At steady state (t = 0.5 s, five
// times H^2 / nu) the mean u of each fluid row follows the closed form u(y) = U y / H, H the gap
// between the wall surface and the plate surface (each dx/2 beyond the last fluid row), within
// 1 % of U on every row (measured: printed); the solid carries the velocity the fluid sees
// through the pairs' no-slip term (both boundary models).
TEST(PairClasses, CouetteFlowBetweenAWallAndAMovingSolidIsLinear) {
  for (const char* model : {"mirror", "extrapolated"}) {
    SCOPED_TRACE(model);
    const double dx = 0.001, H = 10 * dx, U = 0.01;
    std::string text = std::string(R"(dimension: 2
domain: {lo: [0, -0.004], hi: [0.01, 0.014], periodic: [true, false]}
spacing: 0.001
kernel: wendland_c2
end_time: 0.5
time_step: {adaptive: true}
output: {every_steps: 100000}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 1, viscosity: 1.0}
  - {name: floor, model: wall, density: 1000}
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e5, poisson_ratio: 0.25, formulation: small_strain_stress}
geometry:
  - {shape: box, lo: [0, -0.004], hi: [0.01, 0.0], material: floor}
  - {shape: box, lo: [0, 0.0], hi: [0.01, 0.01], material: water}
  - {shape: box, lo: [0, 0.01], hi: [0.01, 0.014], material: clay, motion: prescribed, velocity: [0.01, 0]}
coupling: {fluid_solid: )") + model + "}\n";
    Scene s = loadSceneText(text, "couette.yaml");
    Simulation& sim = *s.sim;
    auto integrator = makeIntegrator("leapfrog");
    int steps = 0;
    while (!s.finished()) {
      integrator->step(sim, s.nextTimeStep());
      ++steps;
    }
    sim.checkFinite();
    ParticleStore& st = sim.store;
    const double* x = st.data(st.position());
    const double* v = st.data(st.velocity());
    double sum[10] = {0}, y[10] = {0};
    int count[10] = {0};
    for (Index i = 0; i < st.realCount(); ++i) {
      if (st.data(st.phase())[i] != kPhaseFluid) continue;
      const int row = static_cast<int>(std::floor(x[2 * i + 1] / dx));
      ASSERT_GE(row, 0);
      ASSERT_LT(row, 10);
      sum[row] += v[2 * i];
      y[row] += x[2 * i + 1];
      ++count[row];
    }
    double worst = 0.0;
    for (int r = 0; r < 10; ++r) {
      ASSERT_GT(count[r], 0);
      const double u = sum[r] / count[r], yr = y[r] / count[r];
      worst = std::max(worst, std::abs(u - U * yr / H) / U);
    }
    std::printf("  Couette, %s pairs: %d steps to t = %.3f s, largest row deviation from U y / H: "
                "%.2e U; top row %.4f U (closed form %.4f)\n",
                model, steps, sim.time, worst, sum[9] / count[9] / U, y[9] / count[9] / H);
    EXPECT_LT(worst, 0.01);
  }
}

// pressure_reference: solid_gauge (issue 16 W1, docs/fluid.md "The solid-only gauge"): the fluid's
// side of every pair uses the absolute pressure (as with none), the solid receives p - p_b (as
// with background). The same disturbed state evaluated with the three references: the solid's
// accelerations are background's, the fluid's are none's, and none's solid differs by p_b's load.
TEST(PairClasses, SolidGaugeLoadsTheSolidWithTheGaugePressureOnly) {
  auto accelerations = [](const std::string& reference) {
    Scene s = loadSceneText(
        scene("  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3, "
              "background_pressure: 600}\n" + kClay,
              "  - {shape: box, lo: [0, 0], hi: [0.02, 0.02], material: water}\n"
              "  - {shape: sphere, centre: [0.01, 0.01], radius: 0.004, material: clay}\n",
              "fluid: {pressure_reference: " + reference + "}\n"),
        "gauge.yaml");
    Simulation& sim = *s.sim;
    disturbFluidDensities(sim);
    ParticleStore& st = sim.store;
    sim.evaluateRates();
    std::vector<std::pair<int, Vec<2>>> a;  // phase, acceleration
    for (Index i = 0; i < st.realCount(); ++i)
      a.emplace_back(st.data(st.phase())[i], st.vec<2>(sim.acceleration, i));
    return a;
  };
  const auto bg = accelerations("background"), sg = accelerations("solid_gauge"),
             none = accelerations("none");
  ASSERT_EQ(bg.size(), sg.size());
  ASSERT_EQ(none.size(), sg.size());
  double solidVsBg = 0.0, fluidVsNone = 0.0, solidNoneVsSg = 0.0, fluidBgVsSg = 0.0, scale = 0.0;
  Index solids = 0;
  for (size_t k = 0; k < sg.size(); ++k) {
    scale = std::max(scale, sg[k].second.norm());
    if (sg[k].first == kPhaseSolid) {
      ++solids;
      solidVsBg = std::max(solidVsBg, (sg[k].second - bg[k].second).norm());
      solidNoneVsSg = std::max(solidNoneVsSg, (sg[k].second - none[k].second).norm());
    } else if (sg[k].first == kPhaseFluid) {
      fluidVsNone = std::max(fluidVsNone, (sg[k].second - none[k].second).norm());
      fluidBgVsSg = std::max(fluidBgVsSg, (sg[k].second - bg[k].second).norm());
    }
  }
  ASSERT_GT(solids, 0);
  EXPECT_EQ(solidVsBg, 0.0) << "the solid sees p - p_b, as with background";
  EXPECT_EQ(fluidVsNone, 0.0) << "the fluid sees the absolute pressure, as with none";
  EXPECT_GT(solidNoneVsSg, 1e-3 * scale) << "with none the solid carries p_b as well";
  EXPECT_GT(fluidBgVsSg, 1e-3 * scale) << "the fluid's forces differ from background's";
}
