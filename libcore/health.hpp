#pragma once
// Health checks of a run (docs/reliability.md): cheap per-step tests that stop a run whose state
// is no longer physical although every number is still finite (a blow-up that stays finite, a
// time step that collapses, particles flying off), before it becomes a result.
//
// The checks, each with its scene key under `health:` and its default:
//   density_variation  0.1    |rho - rho0| / rho0 of a fluid particle (weakly compressible
//                             assumption, thesis Sec. 1.3.1: c0 is chosen for ~1 %); and any
//                             density <= 0 (every phase)
//   max_mach           0.5    |v| / c of a particle, c the sound speed of its fluid or the
//                             elastic wave speed of its solid (Eq. 2.50)
//   dt_floor           1e-3   adaptive dt / the stable dt of the initial state
//   energy_growth      1.0    growth of the accounted energy (kinetic + stored + dissipated -
//                             work put in) over its start value, in units of the energy scale
//                             of the scene (EnergyAccount, below)
//   domain_margin      0.25   a particle further outside the box of the domain and the initial
//                             particles than this fraction of the box size (non-periodic axes)
//   rollback_every     1      steps between copies of the state a failed step is rolled back
//                             to (RollbackState, below): 1 keeps the state before the failed
//                             step; k > 1 copies every k steps (the written state is then up to
//                             k - 1 steps older) for 1/k of the copying time
//   J <= 0                    (no key) an inverted solid particle (deformation gradient)
// `keep_going: true` (or `poresph run --keep-going`) turns the stops into warnings, printed once
// per check.
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

class ParameterSet;
class ParticleStore;
class Simulation;

struct HealthLimits {
  double densityVariation = 0.1;
  double maxMach = 0.5;
  double dtFloor = 1e-3;
  double energyGrowth = 1.0;
  double domainMargin = 0.25;
  Index rollbackEvery = 1;
  bool keepGoing = false;
};

/// Reads the `health:` section (nullptr: every default); unknown keys are errors.
HealthLimits readHealthLimits(const ParameterSet* section);

/// One check crossed: what, where, by how much.
struct HealthIssue {
  std::string check;     ///< the scene key of the check (e.g. "max_mach"), or "jacobian"
  std::string field;     ///< the field that crossed it (e.g. "velocity")
  Index particle = -1;   ///< index in the store (-1: a global check)
  double value = 0.0;    ///< measured value
  double limit = 0.0;    ///< the bound it crossed
  std::string detail;    ///< one sentence: what the value is and what to do
};

/// Energy bookkeeping a module contributes to the check `energy_growth`. Kinetic energy is the
/// core's. `untrackedScale` is the size of the energy the module does not account for
/// (compression of a weakly compressible fluid, surface energy, work of body forces), below
/// which a growth is not a fault.
struct EnergyAccount {
  double stored = 0.0;          ///< elastic energy, gravity potential (J)
  double workIn = 0.0;          ///< work done on the particles by imposed boundaries and loads (J)
  double dissipated = 0.0;      ///< energy dissipated and accounted for (J)
  double untrackedScale = 0.0;  ///< J
  double storedRange = 0.0;     ///< largest change the stored energy can have (e.g. m g H) (J)
  bool complete = true;         ///< every module accounted for its energy (else: no check)
};

/// Largest particle value of a per-particle measure, with its index (reduction helper for the
/// modules' checks): the first particle of the largest value.
struct MaxAt {
  double value = -std::numeric_limits<double>::infinity();
  Index particle = -1;
};
#pragma omp declare reduction(maxAt : MaxAt : omp_out = (omp_in.value > omp_out.value || (omp_in.value == omp_out.value && omp_in.particle < omp_out.particle)) ? omp_in : omp_out)

/// The per-step monitor the run loop calls: the core checks (density <= 0, dt floor, domain,
/// energy) and every module's Module::checkHealth.
class HealthMonitor {
 public:
  HealthMonitor() = default;
  HealthMonitor(const HealthLimits& limits) : limits_(limits) {}
  /// Takes the reference state (initial stable step, domain box, energy at the start).
  void start(const Simulation& sim, double initialStableTimeStep);
  /// All checks on the current state; the issues found (empty when healthy).
  std::vector<HealthIssue> check(const Simulation& sim);
  const HealthLimits& limits() const { return limits_; }
  /// "check 'max_mach' (velocity): particle 12 (id 40, material 0) ... at step s, time t s".
  static std::string describe(const Simulation& sim, const HealthIssue& issue);

 private:
  double energyBalance(const Simulation& sim, EnergyAccount& total) const;
  HealthLimits limits_;
  double initialStable_ = 0.0;
  double energy0_ = 0.0, kinetic0_ = 0.0, stored0_ = 0.0;
  double energyScale0_ = 0.0, workIn0_ = 0.0;
  std::array<double, 3> boxLo_{}, boxHi_{};
  bool started_ = false;
  bool energyChecked_ = false;
};

/// The state a failed step is rolled back to by the run loop (libcore/runner.cpp), so that the
/// run ends by writing a state that passed every check. It copies, for the real particles, only
/// the fields that the written files hold: those flagged kFieldCheckpoint (the state a restart
/// needs) or kFieldOutput (the snapshot), and every module's saveState(). Scratch fields, rates,
/// the integrator's copies and the neighbour data are not copied: after a rollback the run only
/// writes the checkpoint and the snapshot and stops. Buffers are reused (no allocation in the
/// time loop once the particle count is steady). docs/particle-store.md has the measured costs.
///
/// Mixed precision (docs/performance.md "Memory levers"): a field flagged kFieldRollbackSingle
/// (velocity, density, acceleration, the fluid's pressure, and the positions while the store
/// holds no solid or rigid particle) is copied in single precision, as a float offset from the
/// middle of each component's range when the range excludes 0 (positions: the box of the
/// particles; density: around rho0), else as a float; a restore puts back the value rounded to
/// 2^-24 of that span (a restored run then follows the uninterrupted one within the tolerance
/// tests/unit/test_health_rollback.cpp measures). Every other field (mass, the solid's fields,
/// the positions of a store with solid or rigid particles) is copied exactly: as doubles, or,
/// when its values are at most kPaletteSize distinct bit patterns at the capture (mass, phase,
/// material, motion of most scenes), as one byte per value indexing those values (lossless).
class RollbackState {
 public:
  /// `everyField`: copy every field (the run loop's copy before this class; kept to measure it),
  /// all exactly (no single precision).
  explicit RollbackState(Index every = 1, bool everyField = false)
      : every_(every < 1 ? 1 : every), everyField_(everyField) {}
  /// Copies the state when due: the first call, then every `every` steps (by sim.step). Returns
  /// whether it copied.
  bool capture(const Simulation& sim);
  /// Puts the copied fields, clock and module states back (ghosts removed). False when nothing
  /// was captured or the particle count changed since.
  bool restore(Simulation& sim) const;
  bool valid() const { return valid_; }
  Index capturedStep() const { return step_; }
  /// Whether field `spec` is copied (checkpoint or output flag).
  static bool copies(unsigned flags);
  /// Bytes per real particle of one copy of this store's current values (a palette field counts
  /// one byte per component; its few values are not counted).
  static std::size_t bytesPerParticle(const ParticleStore& store);
  /// Bytes held now (capacity of the buffers).
  std::size_t bytes() const;

  static constexpr int kPaletteSize = 16;
  /// How a field is held in the copy.
  enum class Storage : std::uint8_t { None, Double, Single, Int, Palette };
  /// The storage a capture of field `f` of `store` picks now.
  static Storage storageOf(const ParticleStore& store, int f, bool everyField = false);

 private:
  struct Column {
    Storage storage = Storage::None;
    std::vector<double> real;        // Double
    std::vector<float> single;       // Single: value - offset[component]
    std::vector<double> offset;      // Single: per component
    std::vector<std::int32_t> ints;  // Int
    std::vector<std::uint8_t> code;  // Palette: index into `palette` per value
    std::vector<std::uint64_t> palette;  // Palette: the values' bit patterns (double or int32)
    void releaseAllBut(Storage keep);
    std::size_t bytes() const;
  };
  Index every_;
  bool everyField_;
  std::vector<Column> columns_;
  // Module::saveState() of each module (ModuleState, spelled out: module.hpp includes this file)
  std::vector<std::vector<std::pair<std::string, std::vector<double>>>> modules_;
  Index n_ = 0;
  double time_ = 0.0, dt_ = 0.0;
  Index step_ = -1;
  bool valid_ = false;
};

}  // namespace poresph
