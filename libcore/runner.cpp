#include "libcore/runner.hpp"

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <csignal>
#include <cstring>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "libcore/checkpoint.hpp"
#include "libcore/health.hpp"
#include "libcore/integrator.hpp"
#include "libcore/output.hpp"

namespace poresph {

namespace {

volatile std::sig_atomic_t g_stopSignal = 0;

extern "C" void onStopSignal(int sig) { g_stopSignal = sig; }

/// Installs the SIGINT/SIGTERM handlers for the lifetime of the object. SA_RESETHAND: the
/// first signal asks for a clean stop, a second one gets the default action (terminates).
class SignalGuard {
 public:
  explicit SignalGuard(bool active) : active_(active) {
    g_stopSignal = 0;
    if (!active_) return;
    struct sigaction sa;
    std::memset(&sa, 0, sizeof(sa));
    sa.sa_handler = onStopSignal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &oldInt_);
    sigaction(SIGTERM, &sa, &oldTerm_);
  }
  ~SignalGuard() {
    if (!active_) return;
    sigaction(SIGINT, &oldInt_, nullptr);
    sigaction(SIGTERM, &oldTerm_, nullptr);
  }
  SignalGuard(const SignalGuard&) = delete;
  SignalGuard& operator=(const SignalGuard&) = delete;

 private:
  bool active_;
  struct sigaction oldInt_ {};
  struct sigaction oldTerm_ {};
};

std::string duration(double s) {
  std::ostringstream o;
  if (!std::isfinite(s)) return "?";
  if (s < 60.0) {
    o << std::fixed << std::setprecision(1) << s << " s";
  } else if (s < 3600.0) {
    o << static_cast<long>(s) / 60 << " min " << static_cast<long>(s) % 60 << " s";
  } else {
    o << static_cast<long>(s) / 3600 << " h " << (static_cast<long>(s) % 3600) / 60 << " min";
  }
  return o.str();
}

/// FNV-1a 64 of the text, as 16 hex digits (stable across builds and machines).
std::string fnv1a(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
  return buf;
}

}  // namespace

std::string sceneSignature(const Scene& scene) {
  // What must not change between a run and its restart: the physics and the geometry. The
  // clock (end_time, max_steps, time_step), the output cadence and the health limits may.
  YAML::Node physics = YAML::Clone(scene.resolved);
  for (const char* key : {"end_time", "max_steps", "time_step", "output", "health"})
    physics.remove(key);
  YAML::Emitter e;
  e << physics;
  return fnv1a(e.c_str());
}

namespace {
/// The signatures of `scene` as written before its explicit `fluid: {pressure_gradient:
/// symmetric}` key was added: the key removed, and the section too if that empties it. A run
/// started before 2026-11-27 without the key ran with Eq. 5.2b, the default then; its
/// checkpoint does not record the form (the fluid's `setting_pressure_gradient` came later), so
/// the restart's warning asks for the key, and the key must not make the scene another one.
/// The fluid module refuses the key against a checkpoint that records another form.
std::vector<std::string> legacySymmetricSignatures(const Scene& scene) {
  const YAML::Node fluid = scene.resolved["fluid"];
  if (!fluid || !fluid.IsMap() || !fluid["pressure_gradient"] ||
      !fluid["pressure_gradient"].IsScalar() ||
      fluid["pressure_gradient"].Scalar() != "symmetric")
    return {};
  std::vector<std::string> out;
  for (bool dropEmpty : {false, true}) {
    YAML::Node physics = YAML::Clone(scene.resolved);
    physics["fluid"].remove("pressure_gradient");
    if (dropEmpty) {
      if (physics["fluid"].size() != 0) continue;
      physics.remove("fluid");
    }
    for (const char* key : {"end_time", "max_steps", "time_step", "output", "health"})
      physics.remove(key);
    YAML::Emitter e;
    e << physics;
    out.push_back(fnv1a(e.c_str()));
  }
  return out;
}
}  // namespace

void restoreCheckpoint(Scene& scene, const std::string& path, ModuleState* integratorState) {
  Simulation& sim = *scene.sim;
  try {
    readCheckpoint(sim, path, sceneSignature(scene), integratorState);
  } catch (const InputError& e) {
    // Only the signature check (made before anything is read into the simulation) is retried.
    if (std::string(e.what()).find("scene signature") == std::string::npos) throw;
    bool restored = false;
    for (const std::string& legacy : legacySymmetricSignatures(scene)) {
      try {
        readCheckpoint(sim, path, legacy, integratorState);
        restored = true;
        break;
      } catch (const InputError& again) {
        if (std::string(again.what()).find("scene signature") == std::string::npos) throw;
      }
    }
    if (!restored) throw;
  }
  if (scene.finished())
    throw InputError(path + ": the checkpoint is at time " + std::to_string(sim.time) +
                     " s, step " + std::to_string(sim.step) + ", which is not before the end of " +
                     scene.file + " (end_time " + std::to_string(scene.endTime) +
                     " s, max_steps " + std::to_string(scene.maxSteps) +
                     "): raise end_time (or max_steps) in the scene to continue the run");
}

void checkInitialHealth(const Scene& scene, const std::string& origin) {
  const Simulation& sim = *scene.sim;
  HealthMonitor health(scene.health);
  health.start(sim, scene.timeStep.adaptive ? scene.initialStableTimeStep : 0.0);
  const auto issues = health.check(sim);
  if (!issues.empty())
    throw InputError(origin + ": the initial state fails a " +
                     HealthMonitor::describe(sim, issues[0]) + " (the scene key health." +
                     issues[0].check + " sets the bound; docs/reliability.md)");
}

RunEstimate estimateRun(Scene& scene, long steps, double maxSeconds) {
  using Clock = std::chrono::steady_clock;
  Simulation& sim = *scene.sim;
  RunEstimate e;
  for (const auto& m : sim.modules) e.moduleLimits.emplace_back(m->name(), m->timeStepLimit(sim));
  e.cflLimit = cflTimeStep(sim, sim.kernel.h());
  std::unique_ptr<Integrator> integrator = makeIntegrator(scene.integrator);
  const double t0 = sim.time;
  try {
    e.dt = scene.nextTimeStep();
    if (scene.finished() || steps <= 0) return e;
    integrator->step(sim, scene.nextTimeStep());  // untimed: it also primes the rates
    const auto start = Clock::now();
    const double tStart = sim.time;
    double wall = 0.0;
    while (e.stepsTimed < steps && wall < maxSeconds && !scene.finished()) {
      integrator->step(sim, scene.nextTimeStep());
      sim.checkFinite();
      ++e.stepsTimed;
      wall = std::chrono::duration<double>(Clock::now() - start).count();
    }
    if (e.stepsTimed > 0) {
      e.secondsPerStep = wall / static_cast<double>(e.stepsTimed);
      const double meanDt = (sim.time - tStart) / static_cast<double>(e.stepsTimed);
      e.stepsToEnd = meanDt > 0.0 ? (scene.endTime - t0) / meanDt : 0.0;
      if (scene.maxSteps > 0) e.stepsToEnd = std::min(e.stepsToEnd, static_cast<double>(scene.maxSteps));
      e.secondsToEnd = e.stepsToEnd * e.secondsPerStep;
    }
  } catch (const NumericalError& err) {
    e.failure = err.what();
  }
  return e;
}

std::string describeEstimate(const Scene& scene, const RunEstimate& e) {
  std::ostringstream o;
  o << std::setprecision(4);
  o << "stable steps: ";
  bool first = true;
  for (const auto& [name, limit] : e.moduleLimits) {
    if (!std::isfinite(limit)) continue;
    o << (first ? "" : ", ") << name << " " << limit << " s";
    first = false;
  }
  o << (first ? "" : ", ") << "velocity/acceleration CFL " << e.cflLimit << " s\n";
  o << "step now:     " << e.dt << " s";
  if (scene.timeStep.adaptive) o << " (cfl " << scene.timeStep.cfl << " x the smallest)";
  o << "\n";
  if (!e.failure.empty()) {
    o << "estimate:     a timed step failed: " << e.failure << "\n";
    return o.str();
  }
  if (e.stepsTimed == 0) return o.str();
  o << "run time:     ~" << duration(e.secondsToEnd) << " for ~" << std::llround(e.stepsToEnd)
    << " steps at " << e.secondsPerStep << " s per step (" << e.stepsTimed << " steps timed, "
    << omp_get_max_threads()
    << " threads; at today's step size: an adaptive step that shrinks later costs more)\n";
  return o.str();
}

void requestStop(int signal) { g_stopSignal = signal == 0 ? SIGTERM : signal; }

RunResult runScene(Scene& scene, const RunOptions& options) {
  using Clock = std::chrono::steady_clock;
  Simulation& sim = *scene.sim;
  RunResult result;
  std::ostream* log = options.progress;

  std::unique_ptr<Integrator> integrator = makeIntegrator(scene.integrator);
  const std::string signature = sceneSignature(scene);  // written into every checkpoint
  if (!options.restartFrom.empty()) {
    ModuleState integratorState;
    restoreCheckpoint(scene, options.restartFrom, &integratorState);
    // The evaluation builds the neighbour lists and ghosts and, for a checkpoint without an
    // integrator state (written after a health rollback), the derived fields (pressure, stress,
    // colour...) and rates; the next step then re-primes the scheme. With the state, every
    // field is put back as the interrupted run left it (the rates it evaluated at its last
    // step's prediction, lagged fields, leapfrog's v^{n+1/2}, and the checkpoint fields the
    // evaluation rewrites), so the run continues to round-off.
    ModuleState asRead;
    if (!integratorState.empty()) asRead = packStoreFields(sim.store, true);
    sim.evaluateRates();
    if (integratorState.empty()) {
      integrator->invalidate();
    } else {
      integratorState.insert(integratorState.end(), asRead.begin() + 1, asRead.end());  // no 2nd id
      try {
        integrator->restoreState(sim, integratorState);
      } catch (const std::invalid_argument& e) {
        throw InputError(options.restartFrom + ": " + e.what() +
                         " (a checkpoint of another scene or version?)");
      }
    }
    if (log)
      *log << "poresph: restarted from " << options.restartFrom << " at step " << sim.step
           << ", time " << sim.time << " s\n";
  }
  HealthLimits limits = scene.health;
  if (options.keepGoing) limits.keepGoing = true;
  HealthMonitor health(limits);
  health.start(sim, scene.timeStep.adaptive ? scene.initialStableTimeStep : 0.0);
  if (!limits.keepGoing)
    checkInitialHealth(scene, options.restartFrom.empty() ? scene.file : options.restartFrom);
  std::vector<std::string> warned;  // checks already reported with keep_going
  OutputWriter writer(options.outDir);
  const std::string checkpointPath = options.outDir + "/checkpoint.h5";

  const OutputSettings& out = scene.output;
  Index lastOutputStep = -1;
  double nextOutputTime = 0.0;
  auto scheduleNext = [&] {
    if (out.everyTime > 0.0)
      nextOutputTime =
          (std::floor(sim.time / out.everyTime + 1e-9) + 1.0) * out.everyTime;
  };
  auto writeOutput = [&] {
    result.lastSnapshot = writer.writeSnapshot(sim);
    writer.appendTimeseries(sim);
    lastOutputStep = sim.step;
    ++result.snapshots;
    scheduleNext();
  };
  auto outputDue = [&] {
    if (out.everySteps > 0) return sim.step % out.everySteps == 0;
    return sim.time >= nextOutputTime - 1e-9 * out.everyTime;
  };

  SignalGuard signals(options.handleSignals);
  const auto start = Clock::now();
  auto lastProgress = start;
  const double startTime = sim.time;
  const Index startStep = sim.step;
  auto elapsed = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };

  // Periodic checkpoints (output.checkpoint_every_steps / checkpoint_every_wall; checked by
  // scene.cpp, kept in the resolved scene).
  const YAML::Node outNode = scene.resolved["output"];
  const long checkpointEverySteps =
      outNode["checkpoint_every_steps"] ? outNode["checkpoint_every_steps"].as<long>() : 0;
  const double checkpointEveryWall =
      outNode["checkpoint_every_wall"] ? outNode["checkpoint_every_wall"].as<double>() : 0.0;
  Index lastCheckpointStep = sim.step;
  auto lastCheckpointWall = start;
  auto periodicCheckpointDue = [&] {
    if (checkpointEverySteps > 0 && sim.step - lastCheckpointStep >= checkpointEverySteps)
      return true;
    return checkpointEveryWall > 0.0 &&
           std::chrono::duration<double>(Clock::now() - lastCheckpointWall).count() >=
               checkpointEveryWall;
  };

  writeOutput();  // the initial (or restarted) state
  // The state a failed step is rolled back to (libcore/health.hpp): checkpoint and output
  // fields, copied every health.rollback_every steps.
  RollbackState lastGood(limits.rollbackEvery);

  while (!scene.finished()) {
    lastGood.capture(sim);
    try {
      const double dt = scene.nextTimeStep();
      integrator->step(sim, dt);
      sim.checkFinite();
      for (const HealthIssue& issue : health.check(sim)) {
        if (!limits.keepGoing) throw NumericalError(HealthMonitor::describe(sim, issue));
        if (std::find(warned.begin(), warned.end(), issue.check) != warned.end()) continue;
        warned.push_back(issue.check);
        if (log)
          *log << "\nwarning: " << HealthMonitor::describe(sim, issue)
               << " (keep_going: reported once per check)\n";
      }
    } catch (const NumericalError& e) {
      result.status = RunStatus::Failed;
      result.message = e.what();
      const bool restored = lastGood.restore(sim);
      if (log)
        *log << "\nporesph: numerical failure: " << e.what() << "\n"
             << (restored ? "poresph: writing the last state that passed every check (step " +
                                std::to_string(sim.step) + ", time " + std::to_string(sim.time) +
                                " s)\n"
                          : "poresph: the last good state could not be restored (particle "
                            "count changed); writing the state as it is\n");
      writeCheckpoint(sim, checkpointPath, signature);
      result.checkpoint = checkpointPath;
      if (lastOutputStep != sim.step || !restored) {
        result.lastSnapshot = writer.writeSnapshot(sim);
        ++result.snapshots;
      }
      if (log)
        *log << "poresph: checkpoint " << checkpointPath << ", last snapshot "
             << result.lastSnapshot << "\n";
      break;
    }
    if (outputDue()) writeOutput();
    if (periodicCheckpointDue()) {
      // The same state the end of the run would write (the step is complete): a run killed
      // later restarts from here to round-off (docs/output.md "Checkpoints").
      const ModuleState integratorState = integrator->saveState(sim);
      writeCheckpoint(sim, checkpointPath, signature, &integratorState);
      lastCheckpointStep = sim.step;
      lastCheckpointWall = Clock::now();
    }

    const auto now = Clock::now();
    if (log && std::chrono::duration<double>(now - lastProgress).count() >=
                   options.progressInterval) {
      lastProgress = now;
      const double wall = elapsed();
      const double done = sim.time - startTime;
      double left = done > 0.0 ? wall / done * (scene.endTime - sim.time) : NAN;
      if (scene.maxSteps > 0 && sim.step > startStep)
        left = std::min(left, wall / static_cast<double>(sim.step - startStep) *
                                  static_cast<double>(scene.maxSteps - sim.step));
      *log << "step " << sim.step << "  t = " << std::setprecision(6) << sim.time
           << " s  dt = " << std::setprecision(4) << sim.dt << " s  wall " << duration(wall)
           << "  left ~" << duration(left) << std::endl;
    }
    if (g_stopSignal != 0) {
      result.status = RunStatus::Interrupted;
      result.signal = static_cast<int>(g_stopSignal);
      break;
    }
  }

  if (result.status != RunStatus::Failed) {
    if (lastOutputStep != sim.step) writeOutput();
    const ModuleState integratorState = integrator->saveState(sim);
    writeCheckpoint(sim, checkpointPath, signature, &integratorState);
    result.checkpoint = checkpointPath;
    if (log && result.status == RunStatus::Interrupted)
      *log << "\nporesph: stopped by signal " << result.signal << " after step " << sim.step
           << " (time " << sim.time << " s); checkpoint " << checkpointPath
           << "\nporesph: resume with: poresph run " << scene.file << " --restart "
           << checkpointPath << "\n";
  }
  result.steps = sim.step - startStep;
  result.time = sim.time;
  result.wallSeconds = elapsed();
  return result;
}

}  // namespace poresph
