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

namespace {

const char* const kClockKeys[] = {"end_time", "max_steps", "time_step", "output", "health"};
// Keys inside a module's section that say only when the run ends (a run may be continued with
// another value, as with end_time).
const char* const kClockSectionKeys[] = {"drainage.stop_after_percolation"};

std::vector<std::string> splitKey(const std::string& key) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(key);
  while (std::getline(in, part, '.')) parts.push_back(part);
  return parts;
}

/// The node a setting key names in the resolved scene (ModuleSetting::key: "<section>.<key>",
/// "materials.<name>.<key>[.<key>]"; a list is entered by its entry's `name`), or an invalid node.
YAML::Node findKey(const YAML::Node& root, const std::vector<std::string>& parts) {
  // Handles are rebound with reset(): assigning a YAML::Node would overwrite the node it holds.
  YAML::Node node;
  node.reset(root);
  for (const std::string& part : parts) {
    YAML::Node next;
    bool found = false;
    if (node.IsSequence()) {
      for (const YAML::Node& item : node)
        if (item.IsMap() && item["name"] && item["name"].IsScalar() &&
            item["name"].Scalar() == part) {
          next.reset(item);
          found = true;
          break;
        }
    } else if (node.IsMap()) {
      for (const auto& kv : node)
        if (kv.first.IsScalar() && kv.first.Scalar() == part) {
          next.reset(kv.second);
          found = true;
          break;
        }
    }
    if (!found) return YAML::Node(YAML::NodeType::Undefined);
    node.reset(next);
  }
  return node;
}

bool sceneSetsKey(const Scene& scene, const std::string& key) {
  const YAML::Node n = findKey(scene.resolved, splitKey(key));
  return n.IsDefined() && !n.IsNull();
}

/// Removes the key (a ModuleSetting::key) from `root`, and the maps this leaves empty.
void eraseKey(YAML::Node root, const std::vector<std::string>& parts) {
  if (parts.empty()) return;
  std::vector<std::string> parent(parts.begin(), parts.end() - 1);
  YAML::Node owner = parent.empty() ? root : findKey(root, parent);
  if (!owner.IsDefined() || !owner.IsMap()) return;
  owner.remove(parts.back());
  if (owner.size() == 0 && !parent.empty()) eraseKey(root, parent);
}

std::string signatureWithout(const Scene& scene, const std::vector<std::string>& keys) {
  YAML::Node physics = YAML::Clone(scene.resolved);
  for (const char* key : kClockKeys) physics.remove(key);
  for (const char* key : kClockSectionKeys) eraseKey(physics, splitKey(key));
  for (const std::string& key : keys) eraseKey(physics, splitKey(key));
  YAML::Emitter e;
  e << physics;
  return fnv1a(e.c_str());
}

/// "section 'fluid'" / "material 'clay'" and the key inside it, for the hints of the messages.
std::pair<std::string, std::string> whereToSet(const std::string& key) {
  const std::vector<std::string> p = splitKey(key);
  if (p.size() >= 3 && p[0] == "materials") {
    std::string inner = p[2];
    for (size_t k = 3; k < p.size(); ++k) inner += "." + p[k];
    return {"material '" + p[1] + "'", inner};
  }
  if (p.size() >= 2) {
    std::string inner = p[1];
    for (size_t k = 2; k < p.size(); ++k) inner += "." + p[k];
    return {p[0] + " section", inner};
  }
  return {"top level", key};
}

}  // namespace

ModuleSettings sceneSettings(const Scene& scene) {
  ModuleSettings out;
  // Scene-wide choices that shape every kernel sum (resolved by scene.cpp, defaults filled in).
  for (const char* key : {"kernel", "h_over_dx", "integrator"}) {
    const YAML::Node n = scene.resolved[key];
    if (n && n.IsScalar()) out.push_back({key, n.Scalar()});  // always in the text: no former default
  }
  for (const auto& m : scene.sim->modules)
    for (ModuleSetting& st : m->settings()) out.push_back(std::move(st));
  return out;
}

std::string sceneSignature(const Scene& scene) {
  // What must not change between a run and its restart: the physics and the geometry. The
  // clock (end_time, max_steps, time_step), the output cadence and the health limits may.
  // The recorded settings are compared by their resolved values (restoreCheckpoint).
  std::vector<std::string> keys;
  for (const ModuleSetting& st : sceneSettings(scene)) keys.push_back(st.key);
  return signatureWithout(scene, keys);
}

std::string legacySceneSignature(const Scene& scene) { return signatureWithout(scene, {}); }

void restoreCheckpoint(Scene& scene, const std::string& path, ModuleState* integratorState,
                       bool printWarnings) {
  Simulation& sim = *scene.sim;
  const CheckpointRecord record = readCheckpointRecord(path);
  const ModuleSettings settings = sceneSettings(scene);
  std::vector<std::string> warnings;
  std::string expected;
  if (record.hasSettings) {
    // Every recorded setting against the one the scene resolves to, by name: a typed change and
    // a default that changed between the binaries are refused alike.
    std::ostringstream diff;
    int differences = 0;
    std::vector<std::string> recordedKeys;
    for (const auto& [key, value] : record.settings) {
      recordedKeys.push_back(key);
      const auto it = std::find_if(settings.begin(), settings.end(),
                                   [&](const ModuleSetting& st) { return st.key == key; });
      if (it != settings.end() && it->value == value) continue;
      diff << (differences++ ? "; " : "") << key << ": checkpoint " << value << ", scene ";
      if (it == settings.end()) {
        diff << "(not a setting of this scene)";
        continue;
      }
      diff << it->value;
      if (!sceneSetsKey(scene, key)) {
        const auto [where, inner] = whereToSet(key);
        diff << " (the default; the scene has no key: add '" << inner << ": " << value
             << "' to its " << where << " to continue the run as it ran)";
      }
    }
    if (differences > 0)
      throw InputError("checkpoint '" + path + "': " + std::to_string(differences) +
                       (differences == 1 ? " setting differs" : " settings differ") +
                       " from the run that wrote it: " + diff.str() +
                       ". A restart keeps the settings it ran with (docs/output.md \"Restart "
                       "and changed defaults\")");
    for (const ModuleSetting& st : settings)
      if (std::find(recordedKeys.begin(), recordedKeys.end(), st.key) == recordedKeys.end())
        warnings.push_back("warning: restart: checkpoint '" + path + "' does not record the setting " +
                           st.key + " (written by an older binary); this run uses " + st.value + "\n");
    expected = signatureWithout(scene, recordedKeys);
  } else {
    // Written before settings were recorded (2026-11-28): compared by the whole scene text, as
    // then written. A key the scene sets to the default that a scene without it then ran with
    // (ModuleSetting::formerDefault) is the same physics: the signature without those keys is
    // accepted too. A key left to a default that has changed since cannot be checked: warned.
    expected = legacySceneSignature(scene);
    std::vector<std::string> pinned;
    for (const ModuleSetting& st : settings) {
      if (st.formerDefault.empty()) continue;
      const bool set = sceneSetsKey(scene, st.key);
      if (set && st.value == st.formerDefault) pinned.push_back(st.key);
      if (!set && st.value != st.formerDefault) {
        const auto [where, inner] = whereToSet(st.key);
        const std::vector<std::string> p = splitKey(st.key);
        const std::string owner = p.size() >= 2 && p[0] != "materials" ? "the " + p[0] + "'s " : "";
        warnings.push_back(
            "warning: restart: the checkpoint '" + path + "' does not record " + owner + inner +
            " (it was written before the settings were recorded, 2026-11-28); this run "
            "continues with the default " + st.value + ". A scene without the key ran with " +
            st.formerDefault + (st.formerDefaultNote.empty() ? "" : " " + st.formerDefaultNote) +
            ": for a run started then, add '" + inner + ": " + st.formerDefault +
            "' to the scene's " + where + " to continue it as it ran (docs/output.md "
            "\"Restart and changed defaults\")\n");
      }
    }
    if (!record.signature.empty() && record.signature != expected && !pinned.empty()) {
      const std::string withoutPinned = signatureWithout(scene, pinned);
      if (withoutPinned == record.signature) expected = withoutPinned;
    }
  }
  readCheckpoint(sim, path, expected, integratorState);
  if (printWarnings)
    for (const std::string& w : warnings) std::fputs(w.c_str(), stderr);
  if (const std::string reason = scene.endConditionMet(); !reason.empty())
    throw InputError(path + ": the checkpoint at time " + std::to_string(sim.time) +
                     " s already meets the run's end condition (" + reason + "): change it in " +
                     scene.file + " to continue the run");
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
  const ModuleSettings settings = sceneSettings(scene);  // recorded in every checkpoint
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
      writeCheckpoint(sim, checkpointPath, signature, nullptr, &settings);
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
      writeCheckpoint(sim, checkpointPath, signature, &integratorState, &settings);
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
    writeCheckpoint(sim, checkpointPath, signature, &integratorState, &settings);
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
