// The fluid's ramped gravity, key `gravity_schedule` (docs/fluid.md "Ramped gravity"): the
// libcore TimeSchedule (libcore/time_schedule.hpp) and linearRamp, the refusal of bad tables
// (file, key, value named; `poresph info` exits with 2), and the fluid module applying
// gravity x factor(sim.time) at an evaluation (every particle of a uniform periodic box at rest
// accelerates with exactly factor(t) g, full and half neighbour lists) and in the hydrostatic
// initial state (the factor at the start, t = 0).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "libcore/time_schedule.hpp"
#include "physics/fluid/fluid_setup.hpp"

using namespace poresph;
namespace fs = poresph::fluidsetup;

namespace {

// A periodic 12 x 12 box of one fluid at rest at its rest density (p = 0: no pressure force)
// with the fluid section `section`.
FluidModule* periodicBox(Simulation& sim, const std::string& section, Simulation::NeighbourListChoice list) {
  const double dx = 1e-3, L = 12 * dx;
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3 * dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {L, L, 0};
  sim.domain.periodic = {true, true, false};
  fs::addMaterial(sim, "water", "fluid", "{density: 1000, sound_speed: 10, viscosity: 1.0e-3}");
  FluidModule* fluid = fs::addFluidModule(sim, section);
  fs::addLattice(sim, {0, 0}, {L, L}, 0);
  sim.neighbourListChoice = list;
  sim.chooseNeighbourList();
  fluid->initialise(sim);
  return fluid;
}

// The InputError message of configuring the periodic box with `section` ("" if none).
std::string errorOf(const std::string& section) {
  try {
    Simulation sim{2};
    periodicBox(sim, section, Simulation::NeighbourListChoice::Full);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TimeSchedule, LinearExponentialHeldAndTheLoadsRamp) {
  // the loads' ramp_time (solid, rigid plates, drainage reservoir): min(1, max(0, t / T))
  EXPECT_DOUBLE_EQ(linearRamp(0.25, 1.0), 0.25);
  EXPECT_EQ(linearRamp(2.0, 1.0), 1.0);
  EXPECT_EQ(linearRamp(-1.0, 1.0), 0.0);
  EXPECT_EQ(linearRamp(0.5, 0.0), 1.0);  // no ramp: applied at once
  EXPECT_DOUBLE_EQ(linearRampRate(0.5, 2.0), 0.5);
  EXPECT_EQ(linearRampRate(3.0, 2.0), 0.0);
  EXPECT_EQ(TimeSchedule().factor(7.0), 1.0);
  EXPECT_TRUE(TimeSchedule().constant());

  const TimeSchedule lin({0.0, 0.1, 0.3}, {0.0, 1.0, 0.25});
  EXPECT_EQ(lin.factor(0.0), 0.0);
  EXPECT_NEAR(lin.factor(0.05), 0.5, 1e-15);
  EXPECT_EQ(lin.factor(0.1), 1.0);
  EXPECT_NEAR(lin.factor(0.2), 0.625, 1e-15);
  EXPECT_EQ(lin.factor(0.3), 0.25);
  EXPECT_EQ(lin.factor(5.0), 0.25);  // held after the last point
  EXPECT_EQ(lin.largestFactor(), 1.0);
  // the ramp_time T is the table (0, 0), (T, 1)
  const TimeSchedule ramp({0.0, 0.02}, {0.0, 1.0});
  for (double t : {0.0, 0.003, 0.011, 0.0199, 0.02, 0.5}) EXPECT_NEAR(ramp.factor(t), linearRamp(t, 0.02), 1e-15);

  // exponential: f0 exp((t - t0) / tau) between (t0, f0) and (t0 + tau ln(f1 / f0), f1), held before
  const double f0 = 0.2, f1 = 1.0, t0 = 0.03, tau = 0.2, t1 = t0 + tau * std::log(f1 / f0);
  const TimeSchedule ex({0.0, t0, t1}, {f0, f0, f1}, TimeSchedule::Interpolation::Exponential);
  for (double t : {0.0, 0.01, 0.03, 0.1, 0.2, t1, t1 + 1.0}) {
    const double want = f0 * std::exp((std::min(std::max(t, t0), t1) - t0) / tau);
    EXPECT_NEAR(ex.factor(t), want, 1e-14 * want) << "t = " << t;
  }

  EXPECT_THROW(TimeSchedule({0.1, 0.1}, {1.0, 2.0}), std::invalid_argument);  // not increasing
  EXPECT_THROW(TimeSchedule({-0.1, 0.1}, {1.0, 2.0}), std::invalid_argument);  // negative time
  EXPECT_THROW(TimeSchedule({0.0, 0.1}, {0.0, 1.0}, TimeSchedule::Interpolation::Exponential),
               std::invalid_argument);  // ln 0
  EXPECT_THROW(TimeSchedule({}, {}), std::invalid_argument);
}

TEST(FluidGravitySchedule, BadTablesAreRefusedNamingFileKeyAndValue) {
  struct Case {
    const char* section;
    std::vector<std::string> expect;  // substrings of the message
  };
  const std::vector<Case> cases = {
      {"{gravity: [1, 0], gravity_schedule: {times: [-0.1, 0.2], factors: [0, 1]}}",
       {"<test>", "fluid.gravity_schedule.times", "-0.1", "negative"}},
      {"{gravity: [1, 0], gravity_schedule: {times: [0, 0.2, 0.2], factors: [0, 1, 2]}}",
       {"fluid.gravity_schedule.times", "increase strictly", "times[2] = 0.2"}},
      {"{gravity: [1, 0], gravity_schedule: {times: [0, 0.3, 0.2], factors: [0, 1, 2]}}",
       {"fluid.gravity_schedule.times", "increase strictly"}},
      {"{gravity: [1, 0], gravity_schedule: {times: [0, 0.2], factors: [0, 1, 1]}}",
       {"fluid.gravity_schedule.factors", "3 factors"}},
      {"{gravity: [1, 0], gravity_schedule: {times: [0, 0.2], factors: [0, 1], interpolation: smooth}}",
       {"fluid.gravity_schedule.interpolation", "smooth", "exponential"}},
      {"{gravity: [1, 0], gravity_schedule: {times: [0, 0.2], factors: [0, 1], interpolation: exponential}}",
       {"fluid.gravity_schedule.factors", "factors[0] = 0", "> 0"}},
      {"{gravity: [1, 0], gravity_schedule: {times: [0, 0.2], factors: [0, 1], time: 3}}",
       {"fluid.gravity_schedule", "time"}},
      {"{gravity: [1, 0], gravity_schedule: {factors: [0, 1]}}", {"fluid.gravity_schedule", "times"}},
      {"{gravity_schedule: {times: [0, 0.2], factors: [0, 1]}}", {"fluid.gravity_schedule", "scales `gravity`"}},
  };
  for (const Case& c : cases) {
    const std::string msg = errorOf(c.section);
    ASSERT_FALSE(msg.empty()) << c.section << " was accepted";
    for (const std::string& s : c.expect) EXPECT_NE(msg.find(s), std::string::npos) << c.section << ": " << msg;
  }
  // a good table is accepted
  EXPECT_EQ(errorOf("{gravity: [1, 0], gravity_schedule: {times: [0, 0.2], factors: [0, 1]}}"), "");
}

// The command line: a scene with a bad table stops `poresph info` with exit code 2 and names
// file, key and value.
TEST(FluidGravitySchedule, PoresphInfoRefusesABadTableWithExitCode2) {
  namespace stdfs = std::filesystem;
  const stdfs::path dir = stdfs::path(PORESPH_BINARY_DIR) / "tmp_test_gravity_schedule";
  stdfs::create_directories(dir);
  const stdfs::path scene = dir / ("bad_" + std::to_string(getpid()) + ".yaml");
  const stdfs::path log = dir / ("log_" + std::to_string(getpid()) + ".txt");
  {
    std::ofstream f(scene);
    f << "dimension: 2\n"
         "domain: {lo: [0, 0], hi: [0.01, 0.01], periodic: [true, true]}\n"
         "spacing: 1.0e-3\n"
         "end_time: 0.001\n"
         "time_step: {adaptive: true}\n"
         "output: {every_time: 0.001}\n"
         "materials:\n"
         "  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 0.001}\n"
         "geometry:\n"
         "  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: water}\n"
         "fluid:\n"
         "  gravity: [1, 0]\n"
         "  gravity_schedule: {times: [0, 0.5, 0.4], factors: [0, 1, 1]}\n";
  }
  const std::string cmd = "\"" + (stdfs::path(PORESPH_BINARY_DIR) / "poresph").string() + "\" info \"" +
                          scene.string() + "\" > \"" + log.string() + "\" 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::ostringstream s;
  s << in.rdbuf();
  const std::string out = s.str();
  stdfs::remove(scene);
  stdfs::remove(log);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2) << out;
  EXPECT_NE(out.find(scene.filename().string() + ":13: key 'fluid.gravity_schedule.times'"), std::string::npos) << out;
  EXPECT_NE(out.find("times[2] = 0.4"), std::string::npos) << out;
}

// A uniform periodic box at rest: every fluid particle's acceleration is exactly the gravity of
// the evaluation's time, factor(sim.time) x gravity (the pressure, viscous and surface terms
// vanish), and sim.published.fluidGravity is the same vector. Without the schedule applied the
// acceleration would be g at every time.
TEST(FluidGravitySchedule, AccelerationFollowsTheFactorAtTheEvaluationTime) {
  const double gx = 2.0, gy = -1.5;
  struct Case {
    std::string table;
    TimeSchedule schedule;
  };
  const std::vector<Case> cases = {
      {"{times: [0, 0.1, 0.3], factors: [0, 1, 0.25]}", TimeSchedule({0.0, 0.1, 0.3}, {0.0, 1.0, 0.25})},
      {"{times: [0, 0.01, 0.07437752], factors: [0.2, 0.2, 1], interpolation: exponential}",
       TimeSchedule({0.0, 0.01, 0.07437752}, {0.2, 0.2, 1.0}, TimeSchedule::Interpolation::Exponential)},
  };
  for (const auto list : {Simulation::NeighbourListChoice::Full, Simulation::NeighbourListChoice::Half}) {
    for (const Case& c : cases) {
      SCOPED_TRACE(c.table + (list == Simulation::NeighbourListChoice::Half ? " (half list)" : " (full list)"));
      Simulation sim{2};
      char sec[300];
      std::snprintf(sec, sizeof sec, "{gravity: [%g, %g], gravity_schedule: %s}", gx, gy, c.table.c_str());
      FluidModule* fluid = periodicBox(sim, sec, list);
      for (double t : {0.0, 0.005, 0.03, 0.05, 0.1, 0.17, 0.3, 0.6}) {
        const double f = c.schedule.factor(t);
        EXPECT_EQ(fluid->gravitySchedule().factor(t), f);
        sim.time = t;
        sim.evaluateRates();
        const auto& st = sim.store;
        const double* acc = st.data(sim.acceleration);
        double err = 0.0, meanX = 0.0;
        for (Index i = 0; i < st.realCount(); ++i) {
          err = std::max({err, std::abs(acc[2 * i] - f * gx), std::abs(acc[2 * i + 1] - f * gy)});
          meanX += acc[2 * i] / static_cast<double>(st.realCount());
        }
        EXPECT_LT(err, 1e-12) << "t = " << t << ": mean a_x " << meanX << ", factor x g_x " << f * gx;
        EXPECT_EQ(sim.published.fluidGravity[0], f * gx) << "t = " << t;
        EXPECT_EQ(sim.published.fluidGravity[1], f * gy) << "t = " << t;
      }
    }
  }
}

// The hydrostatic initial state (hydrostatic_level) is in equilibrium with the gravity of the
// start: gravity x factor(0). A closed column of water under a schedule starting at 1/2: the
// pressure at depth z is p_b + rho0 (g / 2) z.
TEST(FluidGravitySchedule, HydrostaticInitialStateUsesTheStartFactor) {
  for (double f0 : {1.0, 0.5}) {
    Simulation sim{2};
    const double dx = 1e-3, W = 0.006, H = 0.02;
    sim.spacing = dx;
    sim.kernel = Kernel(KernelType::WendlandC2, 2, 1.3 * dx);
    sim.domain.lo = {0, -4 * dx, 0};
    sim.domain.hi = {W, H + 4 * dx, 0};
    sim.domain.periodic = {true, false, false};
    const int water = fs::addMaterial(sim, "water", "fluid", "{density: 1000, sound_speed: 20, viscosity: 1.0e-3}");
    const int wall = fs::addMaterial(sim, "wall", "wall", "{density: 1000}");
    char sec[300];
    std::snprintf(sec, sizeof sec,
                  "{gravity: [0, -9.81], hydrostatic_level: 0.02, gravity_schedule: {times: [0, 0.1], factors: [%g, 1]}}",
                  f0);
    FluidModule* fluid = fs::addFluidModule(sim, sec);
    fs::addLattice(sim, {0, 0}, {W, H}, water);
    fs::addLattice(sim, {0, -3 * dx}, {W, 0}, wall);
    fluid->initialise(sim);
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* p = st.data(fluid->pressure);
    const std::int32_t* mt = st.data(st.material());
    double err = 0.0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (mt[i] == water) err = std::max(err, std::abs(p[i] - 1000.0 * 9.81 * f0 * (H - x[2 * i + 1])));
    EXPECT_LT(err, 1e-8) << "factor at t = 0: " << f0;
  }
}
