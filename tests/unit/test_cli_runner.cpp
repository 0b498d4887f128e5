// The run loop (libcore/runner.hpp) in-process, with a probe module that applies a constant
// acceleration g (closed forms: v = g t, x = x0 + g t^2 / 2, exact for leapfrog and Verlet), that
// can blow up (NaN) after a given time, and that can raise SIGINT.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "libcore/runner.hpp"

namespace fs = std::filesystem;
using namespace poresph;

namespace {

struct ProbeControl {
  double g = 2.0;                  // m/s^2 along x
  double nanAfter = 1e30;          // acceleration becomes NaN once time exceeds this
  double interruptAfter = 1e30;    // raise(SIGINT) once time exceeds this
  double crashAfter = 1e30;        // throw (a process killed without a word) once time exceeds this
  bool raised = false;
};
ProbeControl control;

class GravityProbe : public Module {
 public:
  std::string name() const override { return "gravity_probe"; }
  std::vector<std::string> materialModels() const override { return {"gravity_body"}; }
  std::vector<PairClass> ownedPairs() const override { return {PairClass(kPhaseRigid, kPhaseRigid)}; }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override {
    for (const Material* m : materials) {
      m->parameters.real("density", Range::positive());
      m->parameters.finish();
      sim.materials[static_cast<size_t>(m->id)].phase = kPhaseRigid;  // pairs: its own class
    }
  }
  void forces(Simulation& sim) override {
    const int d = sim.dimension();
    double* a = sim.store.data(sim.acceleration);
    const double value = sim.time > control.nanAfter ? NAN : control.g;
    const Index n = sim.store.realCount();
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) a[i * d] = value;
    if (sim.time > control.crashAfter) throw std::runtime_error("simulated crash");
    if (sim.time > control.interruptAfter && !control.raised) {
      control.raised = true;
      std::raise(SIGINT);
    }
  }
  // Eq. 2.49 with the velocity: 0.25 h / |v|max is left to the core; the probe caps at 1 ms.
  double timeStepLimit(const Simulation&) const override { return 1e-3; }
};
PORESPH_REGISTER_MODULE(GravityProbe, "gravity_probe")

fs::path tmpDir() {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_cli_runner";
  fs::create_directories(d);
  return d;
}

std::string scene(const std::string& integrator, const std::string& output) {
  return R"(dimension: 2
domain: {lo: [0, 0], hi: [0.1, 0.1]}
spacing: 0.01
end_time: 0.01
integrator: )" + integrator + R"(
time_step: {dt: 5.0e-4}
output: )" + output + R"(
materials:
  - {name: body, model: gravity_body, density: 1000}
geometry:
  - {shape: box, lo: [0, 0], hi: [0.1, 0.1], material: body}
  - {shape: box, lo: [0, 0], hi: [0.1, 0.02], material: body, motion: fixed}
)";
}

Scene load(const std::string& name, const std::string& text) {
  const fs::path p = tmpDir() / name;
  std::ofstream(p) << text;
  return loadScene(p.string());
}

RunOptions options(const std::string& name) {
  RunOptions o;
  o.outDir = (tmpDir() / name).string();
  fs::remove_all(o.outDir);
  o.progress = nullptr;
  return o;
}

// Every free particle: v_x = g t (within vRel of it), x = x0 + g t^2 / 2 (x0 on the lattice);
// fixed ones at rest.
void expectFreeFall(const Simulation& sim, double t, double vRel = 1e-10) {
  const auto& st = sim.store;
  for (Index i = 0; i < st.realCount(); ++i) {
    const double vx = st.data(st.velocity())[2 * i];
    const double x = st.data(st.position())[2 * i];
    const double x0 = x - (st.data(sim.motion)[i] == kMotionFixed ? 0.0 : 0.5 * control.g * t * t);
    if (st.data(sim.motion)[i] == kMotionFixed) {
      EXPECT_EQ(vx, 0.0);
    } else {
      EXPECT_NEAR(vx, control.g * t, vRel * std::fabs(control.g * t) + 1e-15);
    }
    // x0 must be a lattice site (k + 1/2) dx
    const double k = x0 / 0.01 - 0.5;
    EXPECT_NEAR(k, std::round(k), 1e-9) << "particle " << i;
  }
}

}  // namespace

TEST(Runner, RunsToEndTimeWithExactFreeFall) {
  for (const std::string integ : {"leapfrog", "verlet"}) {
    control = ProbeControl{};
    Scene s = load("fall_" + integ + ".yaml", scene(integ, "{every_steps: 5}"));
    const RunResult r = runScene(s, options("fall_" + integ));
    EXPECT_EQ(r.status, RunStatus::Finished);
    EXPECT_EQ(r.steps, 20);
    EXPECT_NEAR(s.sim->time, 0.01, 1e-15);
    expectFreeFall(*s.sim, s.sim->time);
    EXPECT_EQ(r.snapshots, 5);  // steps 0, 5, 10, 15, 20
    EXPECT_TRUE(fs::exists(r.checkpoint));
    EXPECT_TRUE(fs::exists(fs::path(r.lastSnapshot)));
  }
}

TEST(Runner, OutputEveryTimeAndEndTimeNotAMultipleOfDt) {
  control = ProbeControl{};
  std::string text = scene("leapfrog", "{every_time: 0.003}");
  text.replace(text.find("end_time: 0.01"), 14, "end_time: 0.0102");
  Scene s = load("every_time.yaml", text);
  const RunResult r = runScene(s, options("every_time"));
  EXPECT_EQ(r.status, RunStatus::Finished);
  // 20 steps of 5e-4 then a last one of 2e-4 landing on end_time.
  EXPECT_EQ(r.steps, 21);
  EXPECT_NEAR(s.sim->time, 0.0102, 1e-15);
  EXPECT_NEAR(s.sim->dt, 2e-4, 1e-15);
  expectFreeFall(*s.sim, s.sim->time);
  // t = 0, 0.003, 0.006, 0.009 and the final state at 0.0102.
  EXPECT_EQ(r.snapshots, 5);
}

TEST(Runner, NumericalFailureRestoresAndWritesTheLastGoodState) {
  control = ProbeControl{};
  control.nanAfter = 0.0031;  // the step that starts at t > 3.1 ms fails
  Scene s = load("blowup.yaml", scene("leapfrog", "{every_steps: 100}"));
  const RunResult r = runScene(s, options("blowup"));
  EXPECT_EQ(r.status, RunStatus::Failed);
  EXPECT_NE(r.message.find("not finite"), std::string::npos) << r.message;
  // Last good state: the step started at 3.5 ms (> 3.1 ms) failed, so t = 3.5 ms, 7 steps.
  EXPECT_EQ(s.sim->step, 7);
  EXPECT_NEAR(s.sim->time, 0.0035, 1e-15);
  EXPECT_NO_THROW(s.sim->checkFinite());
  // The state restored from the health monitor's copy: velocities were kept in single precision
  // there (libcore/health.hpp, the rollback copy in mixed precision), so v_x = g t to float
  // rounding (2^-24 relative; measured 3.1e-8).
  expectFreeFall(*s.sim, s.sim->time, 1.2e-7);
  EXPECT_TRUE(fs::exists(r.checkpoint));
  EXPECT_NE(r.lastSnapshot.find("step_00000007.vtu"), std::string::npos) << r.lastSnapshot;
  EXPECT_TRUE(fs::exists(fs::path(r.lastSnapshot)));
}

TEST(Runner, SigintFinishesTheStepAndWritesACheckpoint) {
  control = ProbeControl{};
  control.interruptAfter = 0.002;
  Scene s = load("interrupt.yaml", scene("leapfrog", "{every_steps: 100}"));
  const RunResult r = runScene(s, options("interrupt"));
  EXPECT_TRUE(control.raised);
  EXPECT_EQ(r.status, RunStatus::Interrupted);
  EXPECT_EQ(r.signal, SIGINT);
  EXPECT_LT(r.steps, 20);
  EXPECT_GE(r.steps, 5);
  EXPECT_TRUE(fs::exists(r.checkpoint));
  expectFreeFall(*s.sim, s.sim->time);
  // The handler was removed again: SIGINT has its previous disposition.
  struct sigaction current;
  sigaction(SIGINT, nullptr, &current);
  EXPECT_EQ(current.sa_handler, SIG_DFL);

  // Restart from the checkpoint and finish: the same closed form at end_time.
  control.interruptAfter = 1e30;
  Scene again = load("interrupt.yaml", scene("leapfrog", "{every_steps: 100}"));
  RunOptions o = options("interrupt_resumed");
  o.restartFrom = r.checkpoint;
  const RunResult r2 = runScene(again, o);
  EXPECT_EQ(r2.status, RunStatus::Finished);
  EXPECT_EQ(r.steps + r2.steps, 20);
  EXPECT_NEAR(again.sim->time, 0.01, 1e-15);
  expectFreeFall(*again.sim, again.sim->time);
}

// output.checkpoint_every_steps: a run that dies without a signal or a numerical failure (here an
// exception out of a module, as SIGKILL or a lost machine would leave it) keeps the last periodic
// checkpoint, complete (no half-written file left), and the restart from it finishes the run on
// the closed form.
TEST(Runner, PeriodicCheckpointOutlivesACrash) {
  control = ProbeControl{};
  control.crashAfter = 0.0051;  // the first evaluation at t = 5.5 ms (step 11 or 12) throws
  const std::string out = "{every_steps: 100, checkpoint_every_steps: 4}";
  Scene s = load("crash.yaml", scene("leapfrog", out));
  const RunOptions o = options("crash");
  EXPECT_THROW(runScene(s, o), std::runtime_error);
  const fs::path cp = fs::path(o.outDir) / "checkpoint.h5";
  ASSERT_TRUE(fs::exists(cp)) << "no periodic checkpoint was written";
  EXPECT_FALSE(fs::exists(cp.string() + ".part"));

  control.crashAfter = 1e30;
  Scene again = load("crash.yaml", scene("leapfrog", out));
  RunOptions o2 = options("crash_resumed");
  o2.restartFrom = cp.string();
  const RunResult r2 = runScene(again, o2);
  EXPECT_EQ(r2.status, RunStatus::Finished);
  EXPECT_EQ(r2.steps, 20 - 8) << "the last periodic checkpoint before the crash is step 8";
  EXPECT_NEAR(again.sim->time, 0.01, 1e-15);
  expectFreeFall(*again.sim, again.sim->time);
}

TEST(Runner, ProgressLinesNameStepTimeDtWallAndTimeLeft) {
  control = ProbeControl{};
  Scene s = load("progress.yaml", scene("verlet", "{every_steps: 100}"));
  std::ostringstream log;
  RunOptions o = options("progress");
  o.progress = &log;
  o.progressInterval = 0.0;  // a line after every step
  const RunResult r = runScene(s, o);
  EXPECT_EQ(r.status, RunStatus::Finished);
  const std::string text = log.str();
  long lines = 0;
  for (char c : text) lines += c == '\n';
  EXPECT_EQ(lines, 20) << text;
  EXPECT_NE(text.find("step 20  t = 0.01 s  dt = 0.0005 s  wall "), std::string::npos) << text;
  EXPECT_NE(text.find("left ~"), std::string::npos) << text;
}
