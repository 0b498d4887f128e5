#pragma once
// A physics module (fluid, solid, damage, rigid, coupling): a small object that registers the
// fields it needs, checks the materials it owns, contributes to the stages of a step, limits the
// time step and adds columns to timeseries.csv. A module never includes another module's
// headers; what modules share goes through the particle store and libcore.
//
// Stage order of one rate evaluation (Simulation::evaluateRates):
//   1. halos and neighbour lists (core)
//   2. kinematics(): densities, colour, strains and strain rates, correction matrices
//   3. constitutive(): pressure (EOS), stress, damage
//   4. forces(): pressure, viscous, surface tension, internal stress, artificial viscosity
//   5. interfaces(): interface conditions between phases (each pair class by one module)
//   6. constraints(): rigid-body reductions, imposed velocities, fixed particles
// Then the integrator advances positions, velocities and every (field, rate) pair registered in
// Simulation::integrated; endOfStep() of every module follows (in module order), then health
// checks, diagnostics() and output.
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "libcore/fluid_properties.hpp"
#include "libcore/health.hpp"
#include "libcore/parameters.hpp"
#include "libcore/phases.hpp"

namespace poresph {

class Simulation;

/// One material of the scene, dispatched to the module that owns its model.
struct Material {
  int id = 0;              ///< index in the scene's materials list = value of the 'material' field
  std::string name;        ///< user's name (e.g. "water")
  std::string model;       ///< model name (e.g. "fluid", "elastic", "wall")
  ParameterSet parameters; ///< the material's mapping; the owning module reads and checks it
  /// Set by the owning module in configure(); what other modules may read (libcore only):
  double density = 0.0;              ///< rho0 (key `density`, every material has one)
  std::int32_t phase = kPhaseUnset;  ///< libcore/phases.hpp; every particle of it gets this phase
  FluidProperties fluid;             ///< fluids: density, sound speed, EOS, viscosity
  double wettingCos = 0.0;           ///< boundaries (walls, solids, rigid): cos(theta), Eq. 1.10
  double waveSpeed = 0.0;            ///< solids: elastic wave speed (Eq. 2.50), for contacts
};

/// State of a module that is not per particle (rigid-body states, plate positions, the time a
/// percolation first held): named vectors of numbers, written into checkpoints under
/// /modules/<module name>/<entry name> and handed back on restart and on the health rollback.
using ModuleState = std::vector<std::pair<std::string, std::vector<double>>>;

/// One resolved setting of a module: its value after the defaults were applied (e.g. the fluid's
/// pressure gradient, a solid material's formulation or damage law). The runner records every
/// module's settings in each checkpoint (group /settings) and compares them on restart, key by
/// key: a difference, typed in the scene or a default that changed between the binary that
/// wrote the checkpoint and this one, refuses the restart naming the key and both values
/// (libcore/runner.cpp restoreCheckpoint; docs/output.md "Restart and changed defaults").
struct ModuleSetting {
  /// Where the scene sets it, dotted: "<section>.<key>" (fluid.pressure_gradient) or
  /// "materials.<material name>.<key>[.<key>]" (materials.clay.damage.law). The scene
  /// signature leaves these keys out: their resolved values are compared instead.
  std::string key;
  std::string value;  ///< the resolved value as text (a choice's name, a number with %.17g)
  /// For a checkpoint written before settings were recorded (2026-11-28): the value a scene
  /// without the key then ran with ("" if not known). Such a checkpoint is still restarted by
  /// its scene with the key added at this value; one whose scene leaves the key out while
  /// this value differs from `value` gets a warning.
  std::string formerDefault = {};
  std::string formerDefaultNote = {};  ///< when formerDefault held, e.g. "until 2026-11-27"
};
using ModuleSettings = std::vector<ModuleSetting>;
/// A number as a ModuleSetting value (%.17g: equal doubles give equal text).
std::string settingNumber(double v);

class Module {
 public:
  virtual ~Module() = default;
  virtual std::string name() const = 0;
  /// Material models this module owns (a material's 'model' key selects its module).
  virtual std::vector<std::string> materialModels() const = 0;
  /// Reads and checks the module's materials (calling finish() on their parameters) and its
  /// own scene section (may be empty), registers fields in sim.store and resolves handles.
  virtual void configure(Simulation& sim, const std::vector<const Material*>& materials,
                         const ParameterSet* section) = 0;
  /// Called once after the particles were created (initial densities, reference state).
  virtual void initialise(Simulation& sim) {}

  /// The pair classes whose pair forces this module applies, to both particles of each pair
  /// (libcore/phases.hpp). A module that only reads neighbours of another phase (e.g. the fluid
  /// extrapolating its pressure onto a solid) does not own that class.
  virtual std::vector<PairClass> ownedPairs() const { return {}; }
  /// The pair classes (libcore/phases.hpp PairMask) of every pair that some loop of this module,
  /// as configured, reads from the neighbour lists (sim.neighbours, sim.neighbourCandidates()),
  /// in either particle's row: also a class whose pairs a loop only looks at to skip them by
  /// the neighbour's phase is read when the loop's result depends on them (a sum over every
  /// neighbour). The lists keep the classes that some module reads and leave the others out at
  /// the search (issue 17: a dam break's wall-wall pairs, a third of the candidates, which no
  /// loop reads). A class is kept or left out whole, for every row of its two phases. Default:
  /// every class (nothing is left out while a module keeps the default).
  virtual PairMask neighbourPairsRead() const { return kAllPairClasses; }
  /// True when every neighbour loop of this module, as configured, works on a half list
  /// (NeighbourList::half: each pair of real particles once; scene key `neighbour_list`).
  virtual bool supportsHalfNeighbourList() const { return false; }

  virtual void kinematics(Simulation& sim) {}
  virtual void constitutive(Simulation& sim) {}
  virtual void forces(Simulation& sim) {}
  virtual void interfaces(Simulation& sim) {}
  virtual void constraints(Simulation& sim) {}

  /// Once per completed step, after the integrator advanced every field and sim.time/sim.step
  /// (Integrator::finishStep): commit history variables (damage D^{n+1} from the new strain,
  /// irreversibility), place particles of bodies whose motion the module integrates itself
  /// (rigid bodies), update controlled boundaries. Not called during the rate evaluations of a
  /// multi-stage step, so state changed here is seen by the next step's first evaluation.
  virtual void endOfStep(Simulation& sim, double dt) {}

  /// A module's own end of the run (e.g. the drainage's `stop_after_percolation`): non-empty,
  /// the reason, once it holds; the run then ends as at end_time (last row, snapshot and
  /// checkpoint written). Scene::finished() asks every module after each step.
  virtual std::string endCondition(const Simulation& sim) const { return {}; }

  /// Non-per-particle state to checkpoint (see ModuleState); empty by default. A module that
  /// returns entries here receives the same entries, same names and lengths, in restoreState()
  /// when a checkpoint is read or a failed step is rolled back.
  virtual ModuleState saveState() const { return {}; }
  virtual void restoreState(const ModuleState& state) {}
  /// The module's main numerical settings as configure() resolved them (ModuleSetting), keys
  /// the scene leaves out with their defaults; empty by default.
  virtual ModuleSettings settings() const { return {}; }

  /// Bytes per particle (averaged over all the scene's particles) of what this module allocates
  /// only in initialise(), once the particles exist (e.g. the Total-Lagrangian reference family,
  /// held for the solid particles only), for the memory estimate made before any particle is
  /// allocated (Scene::memory, `poresph info`). `neighbours`: the lattice estimate of neighbours
  /// per particle within the support; `particlesPerMaterial`: counted sites per material id.
  virtual double deferredBytesPerParticle(const Simulation& sim, double neighbours,
                                          const std::vector<Index>& particlesPerMaterial) const {
    return 0.0;
  }
  /// Bytes this module holds outside the particle store (per-body state, compressed per-particle
  /// rows such as the TL reference family), reported by `poresph info` (libcore/memory.hpp).
  virtual std::uint64_t heldBytes() const { return 0; }
  /// Largest stable time step of this module (CFL conditions, Eqs. 2.49-2.50).
  virtual double timeStepLimit(const Simulation& sim) const {
    return std::numeric_limits<double>::infinity();
  }
  /// Health checks of this module's particles (libcore/health.hpp, docs/reliability.md): appends
  /// one issue per check crossed (the worst particle), after each step. Cheap reductions only.
  virtual void checkHealth(const Simulation& sim, const HealthLimits& limits,
                           std::vector<HealthIssue>& issues) const {}
  /// Adds this module's energies (stored, work put in, dissipated, untracked scale) for the
  /// energy-growth check; kinetic energy is the core's. Returns false when the module cannot
  /// account for the energy it puts in (the default): the check is then off for the scene.
  virtual bool energyAccount(const Simulation& sim, EnergyAccount& account) const {
    return false;
  }
  /// Global quantities for timeseries.csv (name, value), e.g. energies.
  virtual void diagnostics(const Simulation& sim,
                           std::vector<std::pair<std::string, double>>& columns) const {}
  /// Lines for `poresph info` (describeScene), e.g. the rigid bodies with mass and inertia;
  /// called once the particles are built, possibly before initialise(). "" for nothing.
  virtual std::string describe(const Simulation& sim) const { return ""; }
};

/// Modules register themselves by name, one line per module:
///   PORESPH_REGISTER_MODULE(FluidModule, "fluid")
class ModuleRegistry {
 public:
  using Factory = std::function<std::unique_ptr<Module>()>;
  static bool add(const std::string& name, Factory factory);
  static std::unique_ptr<Module> create(const std::string& name);
  static std::vector<std::string> names();
  /// The module that owns a material model, or "" if none does.
  static std::string moduleForModel(const std::string& model);
};

#define PORESPH_REGISTER_MODULE(Class, name)                                   \
  namespace {                                                                  \
  const bool registered_##Class = ::poresph::ModuleRegistry::add(              \
      name, [] { return std::unique_ptr<::poresph::Module>(new Class()); });   \
  }

}  // namespace poresph
