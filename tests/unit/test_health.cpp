// Health checks (libcore/health.hpp, docs/reliability.md): runs that blow up while staying
// finite are stopped with the check, field, particle, step and time named and the last state
// that passed every check kept; bad initial states are refused as input; checkpoints of another
// scene or past end_time are refused; a restarted run's first timeseries row equals the row the
// interrupted run wrote; the printed resume command works as printed.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "libcore/checkpoint.hpp"
#include "libcore/health.hpp"
#include "libcore/runner.hpp"

namespace fs = std::filesystem;
using namespace poresph;

namespace {

fs::path tmpDir() {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_health";
  fs::create_directories(d);
  return d;
}

Scene load(const std::string& name, const std::string& text) {
  const fs::path p = tmpDir() / name;
  std::ofstream(p) << text;
  return loadScene(p.string());
}

RunOptions quiet(const std::string& name) {
  RunOptions o;
  o.outDir = (tmpDir() / name).string();
  fs::remove_all(o.outDir);
  o.handleSignals = false;
  return o;
}

// A 2D water column of 20 x 20 particles under gravity between wall layers (as
// samples/fluid_box_at_rest.yaml), with the sound speed, start and end time given.
std::string waterColumn(double soundSpeed, const std::string& extraFluid, double endTime,
                        const std::string& waterExtra = "") {
  std::ostringstream s;
  s << R"(dimension: 2
domain: {lo: [-0.003, -0.003], hi: [0.023, 0.023]}
spacing: 0.001
kernel: wendland_c2
end_time: )" << endTime << R"(
time_step: {adaptive: true}
output: {every_time: 0.01}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: )" << soundSpeed
    << R"(, viscosity: 1.0e-3}
  - {name: steel, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.003, -0.003], hi: [0.023, 0.023], material: steel}
  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.02], material: water)" << waterExtra << R"(}
fluid:
  gravity: [0, -9.81]
)" << extraFluid;
  return s.str();
}

// A 1D elastic bar clamped at both ends, vibrating in its first mode (samples/solid_bar_cc.yaml
// at 50 particles, h = 1.3 dx, 6 mirror layers each side).
const char* kBar = R"(dimension: 1
domain: {lo: [0.0], hi: [0.1333]}
spacing: 2.666e-3
h_over_dx: 1.3
end_time: 2.0e-5
time_step: {dt: 2.0e-8}
output: {every_time: 1.0e-5}
materials:
  - {name: steel, model: elastic, density: 7833, young_modulus: 2.0e11, formulation: total_lagrangian}
geometry:
  - {shape: box, lo: [-0.015996], hi: [0.149296], material: steel}
solid:
  initial_velocity: {amplitude: [7.937264], wavevector: [23.567837]}
  boundaries:
    - {name: left,  type: clamped, box: {min: [-1.0], max: [0.0]},    mirror: {point: [0.0], normal: [1.0]}}
    - {name: right, type: clamped, box: {min: [0.1333], max: [1.0]}, mirror: {point: [0.1333], normal: [1.0]}}
)";

// A free 2D Total-Lagrangian block.
const char* kBlock = R"(dimension: 2
domain: {lo: [0, 0], hi: [0.01, 0.01]}
spacing: 0.001
end_time: 1.0e-4
time_step: {adaptive: true}
output: {every_steps: 100}
materials:
  - {name: clay, model: elastic, density: 2000, young_modulus: 1.0e7, poisson_ratio: 0.25, formulation: total_lagrangian, hourglass: 1.0}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: clay}
)";

bool hasCheck(const std::vector<HealthIssue>& issues, const std::string& check) {
  for (const auto& i : issues)
    if (i.check == check) return true;
  return false;
}

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  std::string l;
  while (std::getline(in, l)) out.push_back(l);
  return out;
}

std::vector<double> numbers(const std::string& row) {
  std::vector<double> v;
  std::stringstream s(row);
  std::string cell;
  while (std::getline(s, cell, ',')) v.push_back(std::stod(cell));
  return v;
}

struct Interrupted {
  int code = -1;  // exit code (-1: killed by a signal)
  std::string output;
};

/// Runs `bin args...` in `dir` with stdout and stderr in a pipe, sends `signal` (SIGINT unless
/// given) once the first progress line ("step ...") shows the time loop is running, and returns
/// the exit code and the output (deterministic, unlike a timer, on a loaded machine).
Interrupted runThenInterrupt(const fs::path& dir, const std::vector<std::string>& args, int signal = SIGINT) {
  int fd[2];
  if (pipe(fd) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(fd[1], 1);
    dup2(fd[1], 2);
    close(fd[0]);
    close(fd[1]);
    if (chdir(dir.c_str()) != 0) _exit(127);
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(fd[1]);
  Interrupted r;
  char buf[4096];
  bool sent = false;
  ssize_t got;
  while ((got = read(fd[0], buf, sizeof buf)) > 0) {
    r.output.append(buf, static_cast<size_t>(got));
    if (!sent && r.output.find("\nstep ") != std::string::npos) {
      kill(pid, signal);
      sent = true;
    }
  }
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

}  // namespace

// A water column whose sound speed is far too low for its height (g H / c^2 = 0.4; c is above
// the free-fall speed 0.63 m/s, so the scene is accepted with a warning): the old loop ran such
// a run to end_time with a density variation of tens of percent and said "finished".
TEST(Health, CompressibleBlowUpStopsWithTheCheckNamedAndAHealthyState) {
  Scene s = load("low_c.yaml", waterColumn(0.7, "", 0.5));
  const RunResult r = runScene(s, quiet("low_c"));
  ASSERT_EQ(r.status, RunStatus::Failed) << "the run ended " << r.time << " s";
  EXPECT_NE(r.message.find("health check 'density_variation'"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("particle "), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("at step "), std::string::npos) << r.message;
  EXPECT_LT(r.time, 0.5);
  // The state kept (in memory and in the checkpoint) passes every check.
  HealthMonitor monitor(s.health);
  monitor.start(*s.sim, s.initialStableTimeStep);
  EXPECT_TRUE(monitor.check(*s.sim).empty());
  Scene again = load("low_c.yaml", waterColumn(0.7, "", 0.5));
  readCheckpoint(*again.sim, r.checkpoint, sceneSignature(again));
  again.sim->evaluateRates();
  HealthMonitor m2(again.health);
  m2.start(*again.sim, again.initialStableTimeStep);
  EXPECT_TRUE(m2.check(*again.sim).empty());
}

// The same scene with keep_going runs to its end and warns.
TEST(Health, KeepGoingTurnsTheStopIntoAWarning) {
  Scene s = load("low_c_keep.yaml", waterColumn(0.7, "", 0.1) + "health: {keep_going: true}\n");
  std::ostringstream log;
  RunOptions o = quiet("low_c_keep");
  o.progress = &log;
  o.progressInterval = 1e9;
  const RunResult r = runScene(s, o);
  EXPECT_EQ(r.status, RunStatus::Finished);
  EXPECT_NE(log.str().find("warning: health check 'density_variation'"), std::string::npos)
      << log.str();
}

TEST(Health, InitialStatesThatFailAreBadInput) {
  // A velocity of 1e30 m/s: the adaptive step was ~1e-34 s and the old loop never ended. Now
  // the sound speed check refuses it at load (c far below the flow speed).
  try {
    load("fast.yaml", waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.1, ", velocity: [1.0e30, 0]"));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("fast.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("sound_speed"), std::string::npos) << m;
  }
  // 4 m/s with c = 5 m/s is accepted (with a warning) but Mach 0.8 fails the initial check.
  Scene fast = load("mach.yaml", waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.1,
                                            ", velocity: [4.0, 0]"));
  try {
    runScene(fast, quiet("mach"));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("mach.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("'max_mach'"), std::string::npos) << m;
    EXPECT_NE(m.find("health.max_mach"), std::string::npos) << m;
  }
  // A hydrostatic start with c = 1 m/s compresses the bottom by 20 %: accepted (c is above the
  // free-fall speed, with a warning), refused by the density check of the initial state.
  Scene slow = load("slow.yaml", waterColumn(1.0, "  hydrostatic_level: 0.02\n", 0.1));
  EXPECT_THROW(checkInitialHealth(slow, "slow.yaml"), InputError);
  // c = 0.1 m/s is below the free-fall speed sqrt(2 g H) = 0.63 m/s: refused at load, naming
  // the material's key.
  try {
    load("slower.yaml", waterColumn(0.1, "  hydrostatic_level: 0.02\n", 0.1));
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("slower.yaml"), std::string::npos) << m;
    EXPECT_NE(m.find("materials[0].sound_speed"), std::string::npos) << m;
    EXPECT_NE(m.find("sqrt(2 g H)"), std::string::npos) << m;
  }
}

TEST(Health, EachCheckFiresOnItsOwnFault) {
  // dt floor: only for adaptive steps, relative to the initial stable step.
  {
    Scene s = load("box_dt.yaml", waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.1));
    HealthMonitor m(s.health);
    m.start(*s.sim, s.initialStableTimeStep);
    s.sim->dt = 0.5 * s.initialStableTimeStep;
    EXPECT_TRUE(m.check(*s.sim).empty());
    s.sim->dt = 1e-4 * s.initialStableTimeStep;
    EXPECT_TRUE(hasCheck(m.check(*s.sim), "dt_floor"));
    HealthMonitor fixedStep(s.health);
    fixedStep.start(*s.sim, 0.0);  // what the runner passes for a fixed dt
    EXPECT_FALSE(hasCheck(fixedStep.check(*s.sim), "dt_floor"));
  }
  // A particle outside the box of the domain and the initial particles, and a density that is
  // not positive: at 676 particles (the one-pass path below 4,096) and at dx / 4 (10,816
  // particles: the parallel pass).
  for (const std::string dx : {"0.001", "0.00025"}) {
    SCOPED_TRACE("spacing " + dx);
    std::string text = waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.1);
    text.replace(text.find("spacing: 0.001"), 14, "spacing: " + dx);
    Scene s = load("box_out.yaml", text);
    ASSERT_EQ(s.sim->store.realCount(), dx == "0.001" ? 676 : 10816);
    HealthMonitor m(s.health);
    m.start(*s.sim, s.initialStableTimeStep);
    EXPECT_TRUE(m.check(*s.sim).empty());
    double* x = s.sim->store.data(s.sim->store.position());
    x[2 * 7 + 1] = 0.023 + 0.2 * 0.026;  // inside the 25 % margin
    EXPECT_FALSE(hasCheck(m.check(*s.sim), "domain_margin"));
    x[2 * 7 + 1] = 0.023 + 0.3 * 0.026;  // outside it
    const auto issues = m.check(*s.sim);
    ASSERT_TRUE(hasCheck(issues, "domain_margin"));
    for (const auto& i : issues) {
      if (i.check == "domain_margin") {
        EXPECT_EQ(i.particle, 7);
      }
    }
    // The low side of the other axis (the check first takes each coordinate's range, then
    // looks up the particle: issue 11 speed).
    x[2 * 7 + 1] = 0.01;
    EXPECT_TRUE(m.check(*s.sim).empty());
    x[2 * 11] = -0.003 - 0.3 * 0.026;
    const auto low = m.check(*s.sim);
    ASSERT_TRUE(hasCheck(low, "domain_margin"));
    for (const auto& i : low)
      if (i.check == "domain_margin") {
        EXPECT_EQ(i.particle, 11);
        EXPECT_NEAR(i.value, 0.05 * 0.026, 1e-12);
      }
  }
  // A negative density anywhere.
  for (const std::string dx : {"0.001", "0.00025"}) {
    SCOPED_TRACE("spacing " + dx);
    std::string text = waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.1);
    text.replace(text.find("spacing: 0.001"), 14, "spacing: " + dx);
    Scene s = load("box_rho.yaml", text);
    HealthMonitor m(s.health);
    m.start(*s.sim, s.initialStableTimeStep);
    EXPECT_TRUE(m.check(*s.sim).empty());
    s.sim->store.data(s.sim->store.density())[3] = -1.0;
    EXPECT_TRUE(hasCheck(m.check(*s.sim), "density_variation"));
    s.sim->store.data(s.sim->store.density())[3] = 0.0;  // zero is not positive either
    const auto zero = m.check(*s.sim);
    ASSERT_TRUE(hasCheck(zero, "density_variation"));
    for (const auto& i : zero)
      if (i.check == "density_variation") {
        EXPECT_EQ(i.particle, 3);
      }
  }
  // Energy put into a vibrating bar without work: velocities doubled (energy x ~4 of the scale).
  {
    Scene s = load("bar.yaml", kBar);
    HealthMonitor m(s.health);
    m.start(*s.sim, 0.0);
    EXPECT_TRUE(m.check(*s.sim).empty());
    double* v = s.sim->store.data(s.sim->store.velocity());
    for (Index i = 0; i < s.sim->store.realCount(); ++i) v[i] *= 1.3;  // 1.69 x: within 1.0 growth
    EXPECT_FALSE(hasCheck(m.check(*s.sim), "energy_growth"));
    for (Index i = 0; i < s.sim->store.realCount(); ++i) v[i] *= 2.0 / 1.3;  // 4 x: beyond
    EXPECT_TRUE(hasCheck(m.check(*s.sim), "energy_growth"));
  }
  // An inverted solid particle (J = det F <= 0) and a solid faster than half its wave speed.
  {
    Scene s = load("block.yaml", kBlock);
    HealthMonitor m(s.health);
    m.start(*s.sim, s.initialStableTimeStep);
    EXPECT_TRUE(m.check(*s.sim).empty());
    const RealField F = s.sim->store.real("deformation_gradient");
    double* f = s.sim->store.data(F);
    f[4 * 5 + 0] = -1.0;  // particle 5: F = diag(-1, 1)
    auto issues = m.check(*s.sim);
    ASSERT_TRUE(hasCheck(issues, "jacobian"));
    f[4 * 5 + 0] = 1.0;
    // c = sqrt((lambda + 2 mu) / rho) = 77.5 m/s for E 1e7, nu 0.25, rho 2000 (plane strain)
    s.sim->store.data(s.sim->store.velocity())[2 * 9] = 50.0;
    issues = m.check(*s.sim);
    ASSERT_TRUE(hasCheck(issues, "max_mach"));
    for (const auto& i : issues)
      if (i.check == "max_mach") {
        EXPECT_EQ(i.particle, 9);
        EXPECT_NEAR(i.value, 50.0 / std::sqrt(1.2e7 / 2000.0), 1e-9);
      }
  }
}

TEST(Health, CheckpointsOfAnotherSceneOrPastTheEndAreRefused) {
  Scene a = load("ck_a.yaml", waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.002));
  const RunResult r = runScene(a, quiet("ck_a"));
  ASSERT_EQ(r.status, RunStatus::Finished);
  // Same particle count, other physics (viscosity): the signature differs.
  std::string other = waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.01);
  other.replace(other.find("viscosity: 1.0e-3"), 17, "viscosity: 2.0e-3");
  Scene b = load("ck_b.yaml", other);
  RunOptions o = quiet("ck_b");
  o.restartFrom = r.checkpoint;
  try {
    runScene(b, o);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene signature"), std::string::npos) << e.what();
  }
  // Another particle count.
  std::string bigger = waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.01);
  bigger.replace(bigger.find("hi: [0.023, 0.023], material: steel"), 35,
                 "hi: [0.023, 0.026], material: steel");  // three more wall rows
  Scene c = load("ck_c.yaml", bigger);
  RunOptions oc = quiet("ck_c");
  oc.restartFrom = r.checkpoint;
  try {
    runScene(c, oc);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("particles but the scene builds"), std::string::npos)
        << e.what();
  }
  // The same scene: the checkpoint is at its end_time; "finished" would be a lie.
  Scene same = load("ck_a.yaml", waterColumn(5.0, "  hydrostatic_level: 0.02\n", 0.002));
  RunOptions os = quiet("ck_same");
  os.restartFrom = r.checkpoint;
  try {
    runScene(same, os);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("raise end_time"), std::string::npos) << e.what();
  }
}

// Run to T1, then continue to T2 in the same directory: the row at T1 is rewritten by the
// restarted run and must equal the one the first run wrote (fluid and solid columns).
TEST(Health, RestartedFirstRowEqualsTheInterruptedRow) {
  struct Case {
    std::string name, t1, t2;
    std::string text;
  };
  const std::string water = waterColumn(5.0, "  hydrostatic_level: 0.02\n  artificial_viscosity: 0.1\n", 0.004);
  std::string water2 = water;
  water2.replace(water2.find("end_time: 0.004"), 15, "end_time: 0.006");
  std::string bar2 = kBar;
  bar2.replace(bar2.find("end_time: 2.0e-5"), 16, "end_time: 3.0e-5");
  const std::vector<std::pair<std::string, std::string>> cases = {{water, water2}, {kBar, bar2}};
  int k = 0;
  for (const auto& [first, second] : cases) {
    SCOPED_TRACE(k);
    const std::string name = "row" + std::to_string(k++);
    Scene a = load(name + "_a.yaml", first);
    RunOptions o = quiet(name);
    const RunResult r = runScene(a, o);
    ASSERT_EQ(r.status, RunStatus::Finished);
    const auto before = lines(fs::path(o.outDir) / "timeseries.csv");
    ASSERT_GE(before.size(), 3u);
    const std::string header = before[0];
    const std::vector<double> last = numbers(before.back());

    Scene b = load(name + "_b.yaml", second);
    RunOptions o2;
    o2.outDir = o.outDir;  // continue in the same directory
    o2.handleSignals = false;
    o2.restartFrom = r.checkpoint;
    const RunResult r2 = runScene(b, o2);
    ASSERT_EQ(r2.status, RunStatus::Finished);
    const auto after = lines(fs::path(o.outDir) / "timeseries.csv");
    ASSERT_EQ(after[0], header);
    // Rows before T1 kept, the row at T1 rewritten once, rows after it appended.
    bool found = false;
    for (size_t row = 1; row < after.size(); ++row) {
      const auto v = numbers(after[row]);
      if (v[0] != last[0]) continue;
      EXPECT_FALSE(found) << "two rows at t = " << last[0];
      found = true;
      ASSERT_EQ(v.size(), last.size());
      std::stringstream names(header);
      std::string col;
      for (size_t c = 0; c < v.size() && std::getline(names, col, ','); ++c)
        EXPECT_NEAR(v[c], last[c], 1e-9 * std::max(1.0, std::abs(last[c])) + 1e-12)
            << "column " << col;
    }
    EXPECT_TRUE(found);
    EXPECT_GT(after.size(), before.size());
  }
}

// The command the interrupted run prints resumes the run as printed (no --force needed).
TEST(Health, ResumeCommandWorksAsPrinted) {
  const fs::path bin = fs::path(PORESPH_BINARY_DIR) / "poresph";
  const fs::path dir = tmpDir() / "resume";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path scenePath = dir / "column.yaml";
  std::ofstream(scenePath)
      << waterColumn(5.0, "  hydrostatic_level: 0.02\n  artificial_viscosity: 0.1\n", 100.0);
  const fs::path out = dir / "run";
  const Interrupted first =
      runThenInterrupt(dir, {bin.string(), "run", "column.yaml", "--out", "run", "--threads", "1"});
  EXPECT_EQ(first.code, 130) << first.output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(first.output, m, std::regex("resume with: poresph (run [^\\n]*)")))
      << first.output;
  const std::string resume = m[1];
  EXPECT_EQ(resume, "run column.yaml --restart run/checkpoint.h5");
  const auto rowsBefore = lines(out / "timeseries.csv").size();
  std::vector<std::string> args = {bin.string()};
  std::stringstream words(resume);
  for (std::string w; words >> w;) args.push_back(w);
  args.push_back("--threads");
  args.push_back("1");
  const Interrupted second = runThenInterrupt(dir, args);
  EXPECT_EQ(second.code, 130) << second.output;
  EXPECT_NE(second.output.find("restarted from run/checkpoint.h5"), std::string::npos)
      << second.output;
  // The series goes on in the same directory, its times increasing.
  const auto rows = lines(out / "timeseries.csv");
  EXPECT_GT(rows.size(), rowsBefore);
  double previous = -1.0;
  for (size_t r = 1; r < rows.size(); ++r) {
    const double time = numbers(rows[r])[0];
    EXPECT_GT(time, previous) << "row " << r;
    previous = time;
  }
}

// SIGTERM on the coupled main job (issue 16, "SIGINT / SIGTERM / blow-up behave as today for
// every module"): samples/drainage_ketton_3d.yaml runs fluid, solid with damage, rigid plates,
// drainage, contact and coupling. A SIGTERM once the time loop runs finishes the step, writes a
// checkpoint, prints the resume command and exits 143; the command as printed resumes the run in
// the same folder (a second SIGTERM stops it again: 143), and the time series goes on with
// increasing times. Measured (1 thread, 2026-11-27): ~14 steps per run before the first progress
// line (1 s wall), ~2.5 s CPU for the test.
TEST(Health, SigtermStopsTheCoupledMainJobWithACheckpointThatResumes) {
  const fs::path bin = fs::path(PORESPH_BINARY_DIR) / "poresph";
  const fs::path dir = tmpDir() / "sigterm_main_job";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/drainage_ketton_3d.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const std::string image = "file: ../data/ketton_128.raw";
  const size_t at = text.find(image);
  ASSERT_NE(at, std::string::npos) << "the main job's image line moved";
  text.replace(at, image.size(), "file: " + std::string(PORESPH_SOURCE_DIR) + "/data/ketton_128.raw");
  std::ofstream(dir / "main_job.yaml") << text;
  const Interrupted first = runThenInterrupt(
      dir, {bin.string(), "run", "main_job.yaml", "--out", "run", "--threads", "1"}, SIGTERM);
  EXPECT_EQ(first.code, 143) << first.output;
  EXPECT_NE(first.output.find("stopped by signal 15 after step"), std::string::npos) << first.output;
  EXPECT_TRUE(fs::exists(dir / "run" / "checkpoint.h5"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(first.output, m, std::regex("resume with: poresph (run [^\\n]*)")))
      << first.output;
  const std::string resume = m[1];
  EXPECT_EQ(resume, "run main_job.yaml --restart run/checkpoint.h5");
  const auto rowsBefore = lines(dir / "run" / "timeseries.csv").size();
  std::vector<std::string> args = {bin.string()};
  std::stringstream words(resume);
  for (std::string w; words >> w;) args.push_back(w);
  args.push_back("--threads");
  args.push_back("1");
  const Interrupted second = runThenInterrupt(dir, args, SIGTERM);
  EXPECT_EQ(second.code, 143) << second.output;
  EXPECT_NE(second.output.find("restarted from run/checkpoint.h5"), std::string::npos) << second.output;
  const auto rows = lines(dir / "run" / "timeseries.csv");
  EXPECT_GT(rows.size(), rowsBefore);
  double previous = -1.0;
  for (size_t r = 1; r < rows.size(); ++r) {
    const double time = numbers(rows[r])[0];
    EXPECT_GT(time, previous) << "row " << r;
    previous = time;
  }
  fs::remove_all(dir);
}
