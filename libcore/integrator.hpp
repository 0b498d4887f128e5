#pragma once
// Explicit time integrators (thesis Sec. 2.2): velocity Verlet (Eq. 2.47), leapfrog (Eq. 2.48)
// and the Predict-Evaluate-Correct leapfrog used in Chapter 3 (after Young 2018, ref. [64] of
// Chapter 3). See docs/time-integration.md.
//
// Every scheme advances, for the real particles [0, realCount()):
//   - positions with the velocities,
//   - velocities with the core `acceleration` field,
//   - every IntegratedField (value, rate) registered in Simulation::integrated.
// Motion (core int field "motion"):
//   kMotionFixed      never moves; its velocity is left alone,
//   kMotionPrescribed velocity is imposed by the modules' constraints() and never overwritten
//                     from the acceleration; the position follows that velocity,
//   kMotionFree       full update.
// An IntegratedField with freeOnly = true advances only kMotionFree particles, otherwise every
// real particle.
//
// Rates: the integrator calls sim.evaluateRates() (one call per step for every scheme, plus one
// at the first step, or whenever sim.step/time/particle count changed behind its back, e.g.
// after readCheckpoint). evaluateRates() may reorder the store, so the integrator keeps no
// per-particle array of its own: its scratch values are store fields (flags kFieldNone) named
// "integrator_*" / "<field>@integrator", registered once, so a reorder permutes them too.
// After step() returns, the store holds the state at the new time and the rates evaluated
// during the step (at t + dt for Verlet/leapfrog, at t + dt/2 for the predictor-corrector).
#include <memory>
#include <string>
#include <vector>

#include "libcore/module.hpp"
#include "libcore/particle_store.hpp"

namespace poresph {

class Simulation;

/// The real particles' fields flagged kFieldCheckpoint (checkpointed = true) or not (false),
/// real and int, as "field:<name>" entries (rows in store order) plus an "id" entry.
ModuleState packStoreFields(const ParticleStore& s, bool checkpointed);
/// Writes such entries back, row by particle id (the store may have been reordered since).
/// Throws std::invalid_argument naming the entry when it does not fit the store.
void unpackStoreFields(ParticleStore& s, const ModuleState& state);

class Integrator {
 public:
  virtual ~Integrator();
  virtual std::string name() const = 0;
  /// Advances sim by dt (> 0, finite): calls sim.evaluateRates() as many times as the scheme
  /// needs, updates sim.time (+= dt), sim.dt (= dt) and sim.step (+= 1). Respects the motion
  /// field.
  virtual void step(Simulation& sim, double dt) = 0;
  /// Number of sim.evaluateRates() calls made so far (for tests and cost reports).
  long long rateEvaluations() const { return evaluations_; }
  /// Forgets the rates held in the store: the next step() re-evaluates them first (call after
  /// changing the particles by hand; step() also detects step/time/particle-count changes).
  void invalidate() { primed_ = false; }
  /// Restart state (docs/output.md, "Checkpoints"): what the next step() takes over from the
  /// last one and a checkpoint's fields do not hold - every store field not flagged
  /// kFieldCheckpoint (the rates, evaluated at the step's prediction and not at the
  /// synchronised state a restart would re-evaluate; lagged quantities such as the previous
  /// acceleration; the scheme's scratch, e.g. leapfrog's v^{n+1/2} of Eq. 2.48) and the
  /// scheme's numbers (leapfrog: dt_n). Empty when the store does not hold the rates of the
  /// current state (not primed).
  ModuleState saveState(const Simulation& sim) const;
  /// Puts a state back into `sim` (the same particles, in any order): saveState()'s entries
  /// plus, on a restart, the checkpoint fields as read (packStoreFields(s, true) taken before
  /// the restart's evaluation, which rewrites some of them), and marks the rates current, so
  /// the next step() continues as the uninterrupted run would have, to round-off.
  /// Throws std::invalid_argument naming the entry when the state does not fit `sim`.
  void restoreState(Simulation& sim, const ModuleState& state);

 protected:
  /// Makes sure the store holds the rates of the current state (evaluates them if not).
  void prime(Simulation& sim);
  /// Calls sim.evaluateRates() and counts it.
  void evaluate(Simulation& sim);
  /// Records the state after a step so that the next step can trust the stored rates.
  void finishStep(Simulation& sim, double dt);
  /// Registers (once per simulation and integrated-field list) the scratch fields.
  void bindScratch(Simulation& sim);
  /// The scheme's own cross-step numbers (saveState/restoreState; its fields are store fields).
  virtual std::vector<double> schemeNumbers() const { return {}; }
  virtual void setSchemeNumbers(const std::vector<double>&) {}

  long long evaluations_ = 0;
  bool primed_ = false;
  const Simulation* bound_ = nullptr;
  Index lastStep_ = -1;
  double lastTime_ = 0.0;
  Index lastCount_ = -1;
  // scratch store fields (kFieldNone): velocity/position copies and one per IntegratedField
  RealField scratchV_, scratchR_;
  std::vector<RealField> scratchF_;
  std::vector<int> boundIntegrated_;  // value field ids the scratch was made for
};

/// "leapfrog" (Eq. 2.48), "verlet" (Eq. 2.47) or "predictor_corrector"; throws InputError
/// listing the valid names otherwise.
std::unique_ptr<Integrator> makeIntegrator(const std::string& name);
std::vector<std::string> integratorNames();

/// The CFL limits of Eq. 2.49 over the real, non-fixed particles:
/// min(0.25 h / max|v|, 0.25 sqrt(h / max|a|)) (+inf when every |v| and |a| are zero).
/// Modules add their own limits (Eq. 2.50, sound speed) through Module::timeStepLimit().
double cflTimeStep(const Simulation& sim, double h);

}  // namespace poresph
