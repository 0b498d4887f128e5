#pragma once
// The time loop of a run (what `poresph run` calls).
//
// Each step: dt (fixed, or cfl x the stable limit, never past end_time: Scene::nextTimeStep),
// one integrator step (libcore/integrator.hpp), sim.checkFinite(), the health checks
// (libcore/health.hpp: density, Mach, dt floor, domain, energy, J), output at the scene's cadence
// (snapshot + timeseries row), a progress line at most every `progressInterval` seconds.
// Stops at end_time (or max_steps), on a NumericalError or a health check crossed (the state
// before the failed step, the last one that passed every check, is restored, then written as a
// checkpoint and a snapshot), or when SIGINT/SIGTERM arrive (the
// step in progress is finished, then a checkpoint is written). A second signal kills at once.
//
// The loop does not allocate beyond what the store and neighbour lists need: the copy of the
// last good state (for the failure snapshot) reuses its buffers, and output allocates only when
// it writes.
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "libcore/scene.hpp"

namespace poresph {

struct RunOptions {
  std::string outDir;                 ///< snapshots/, results.pvd, timeseries.csv, checkpoint.h5
  std::ostream* progress = nullptr;   ///< progress and status lines (nullptr: silent)
  double progressInterval = 1.0;      ///< seconds of wall time between progress lines
  bool handleSignals = true;          ///< install SIGINT/SIGTERM handlers for the run
  std::string restartFrom;            ///< checkpoint to resume from ("" : start at t = 0)
  bool keepGoing = false;             ///< health checks warn instead of stopping the run
};

enum class RunStatus { Finished, Interrupted, Failed };

struct RunResult {
  RunStatus status = RunStatus::Finished;
  Index steps = 0;            ///< steps taken by this call
  double time = 0.0;          ///< simulated time reached (of the last good state)
  int signal = 0;             ///< the signal that interrupted the run
  std::string checkpoint;     ///< checkpoint written (final, on interrupt or on failure)
  std::string lastSnapshot;   ///< last .vtu written
  std::string message;        ///< the NumericalError's text when Failed
  double wallSeconds = 0.0;
  long long snapshots = 0;
};

/// Runs `scene` (loaded with initialise = true) to its end. Throws InputError for bad input (an
/// unknown integrator, an unwritable output directory, a checkpoint that does not match).
RunResult runScene(Scene& scene, const RunOptions& options);

/// What a run will cost, from a few timed steps (`poresph info`): each module's stable step
/// (Module::timeStepLimit) and the CFL limit, the step the scene takes now, the wall time per
/// step and the projection to end_time (or max_steps) at the present step size.
struct RunEstimate {
  std::vector<std::pair<std::string, double>> moduleLimits;  ///< module, limit (s; inf: none)
  double cflLimit = 0.0;          ///< cflTimeStep (velocity and acceleration criteria)
  double dt = 0.0;                ///< the step now (fixed, or cfl x the smallest limit)
  long stepsTimed = 0;            ///< steps timed (after one untimed first step)
  double secondsPerStep = 0.0;    ///< wall
  double stepsToEnd = 0.0;        ///< from the present time at the mean timed dt
  double secondsToEnd = 0.0;      ///< stepsToEnd x secondsPerStep
  std::string failure;            ///< the NumericalError of a timed step ("" if none)
};

/// Advances `scene` (initialised) by up to `steps` steps or `maxSeconds` of wall time, whichever
/// comes first, and projects the cost of the whole run. Writes nothing; leaves the scene advanced.
RunEstimate estimateRun(Scene& scene, long steps, double maxSeconds);
/// Lines for `poresph info`: "stable steps: ...", "estimate: ...".
std::string describeEstimate(const Scene& scene, const RunEstimate& e);

/// The run's resolved settings, recorded in every checkpoint and compared on restart key by key:
/// the scene's kernel, h_over_dx and integrator, then every module's Module::settings().
ModuleSettings sceneSettings(const Scene& scene);

/// A hash of the scene's physics and geometry: the resolved scene without end_time, max_steps,
/// time_step, output, health and without the keys of sceneSettings() (compared by value
/// instead), written into checkpoints and compared on restart.
std::string sceneSignature(const Scene& scene);
/// The signature as checkpoints written before 2026-11-28 hold it: the whole resolved scene
/// (module sections as written) without end_time, max_steps, time_step, output and health.
std::string legacySceneSignature(const Scene& scene);

/// Reads a checkpoint into the scene's simulation, refusing (InputError naming the file) one of
/// another scene (particle count, scene signature), one whose recorded settings differ from the
/// scene's (each differing key named with the checkpoint's and the scene's value), a missing or
/// unreadable file, and one whose time is not before the scene's end. A checkpoint without
/// recorded settings (written before 2026-11-28) is compared by legacySceneSignature(), a key
/// set explicitly to its ModuleSetting::formerDefault left out, and warns for each setting the
/// scene leaves to a default that differs from the former one. runScene() calls it; `poresph run --restart` calls it
/// before it touches the output directory, with `printWarnings` false (the run's own call prints
/// them, once).
void restoreCheckpoint(Scene& scene, const std::string& path,
                       ModuleState* integratorState = nullptr, bool printWarnings = true);

/// Throws InputError (naming `origin`, the check, the particle) when the scene's current state
/// already fails a health check: a run from it would stop at its first step. runScene() calls
/// it (unless keep_going); `poresph run` calls it before it creates the output directory.
void checkInitialHealth(const Scene& scene, const std::string& origin);

/// Asks a running runScene() to stop after the step in progress (what the signal handlers do;
/// also usable from tests). `signal` is reported in RunResult::signal.
void requestStop(int signal);

}  // namespace poresph
