#pragma once
// The state of one run and the scheduler of a step (see libcore/module.hpp for the stage order).
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "libcore/domain.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/halo.hpp"
#include "libcore/kernel.hpp"
#include "libcore/module.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/particle_store.hpp"

namespace poresph {

/// How a particle moves. Stored in the core int field "motion".
enum Motion : std::int32_t {
  kMotionFree = 0,        ///< integrated from its acceleration
  kMotionFixed = 1,       ///< never moves (walls, clamped layers)
  kMotionPrescribed = 2,  ///< velocity imposed by a constraint; position follows it
};

/// A per-particle quantity advanced by the integrator: d(value)/dt = rate. Positions and
/// velocities are always integrated; modules add their own (density, displacement, energy...).
struct IntegratedField {
  RealField value;
  RealField rate;
  bool freeOnly = true;  ///< advance only particles with motion == kMotionFree
};

class Simulation {
 public:
  explicit Simulation(int dimension);

  int dimension() const { return store.dimension(); }

  // ---- state ----
  ParticleStore store;
  Domain domain;
  Kernel kernel;
  double spacing = 0.0;           ///< initial particle spacing dx
  double time = 0.0;
  double dt = 0.0;
  Index step = 0;
  RealField acceleration;         ///< dv/dt of each particle, summed by the modules' stages
  IntField motion;                ///< Motion of each particle
  std::vector<IntegratedField> integrated;
  std::vector<std::unique_ptr<Module>> modules;
  std::vector<Material> materials;
  /// How fluid pairs are evaluated (pressure form, viscosity mean, artificial viscosity): set by
  /// the fluid module, read by every module that applies fluid pair terms (coupling).
  FluidPairSettings fluidPairSettings;
  /// Physical parameters one module reads and another needs, published at configure (the
  /// modules meet only here): the fluid module's interface tension and gravity, read by the
  /// drainage module for the dimensionless numbers of Eqs. 5.11-5.14.
  struct PublishedPhysics {
    double surfaceTension = 0.0;                 ///< gamma of the fluid-fluid interface [N/m]
    std::array<double, 3> fluidGravity{0, 0, 0};  ///< gravity acting on the fluids [m/s^2]
    /// The coupling module's fluid-solid boundary model (set when it runs): the rigid module's
    /// plates and grains take it where the fluid also meets elastic solids (one model per
    /// fluid particle, docs/coupling.md "Pores opening onto a plate").
    std::optional<BoundaryModel> fluidSolidModel;
  } published;
  /// Appends a material (id = its index) whose parameters are a YAML mapping given as text, for
  /// scenes built in code (tests, benchmarks); errors name `origin` and materials[id].
  const Material& addMaterial(const std::string& name, const std::string& model,
                              const std::string& yamlMapping, const std::string& origin = "<code>");

  // ---- neighbours ----
  NeighbourList neighbours;  ///< of the real particles, over real and ghost particles
  NeighbourSearch search;
  PeriodicHalo halo;
  int reorderEvery = 50;     ///< cell-reorder the store every N neighbour builds (0: never)
  /// Verlet skin (metres, scene key `neighbour_skin` in units of dx; 0: a fresh search every
  /// step). With a skin and no periodic axis the search runs with radius support + skin only
  /// when a particle has moved by skin/2 since the last search; every other step the exact
  /// list is filtered from those candidates (docs/performance.md).
  double neighbourSkin = 0.0;
  VerletNeighbours verlet;
  /// Scene key `neighbour_list`: `full` (every pair in both rows), `half` (each pair of real
  /// particles once, NeighbourList::half, for the modules' symmetric pair loops; refused when a
  /// module needs the full list), `auto` (half when every module supports it) or `cells` (no
  /// stored list: the symmetric loops find the half list's pairs in the search's cells,
  /// libcore/cell_walk.hpp; same modules as half, no Verlet skin).
  enum class NeighbourListChoice { Full, Half, Auto, Cells };
  NeighbourListChoice neighbourListChoice = NeighbourListChoice::Full;
  /// True when `neighbours` (and the Verlet candidates) are half lists; set by
  /// chooseNeighbourList() from the choice and the modules (Module::supportsHalfNeighbourList).
  bool halfNeighbourList = false;
  /// True with the choice `cells` (then halfNeighbourList too): updateNeighbours only sorts the
  /// particles into cells (search.grid()), `neighbours` stays an empty half list, and the
  /// symmetric loops walk the cells (libcore/cell_walk.hpp).
  bool cellWalk = false;
  /// Sets halfNeighbourList. With the choice `half`, throws InputError naming the first module
  /// that needs the full list (as configured).
  void chooseNeighbourList();
  /// Pair classes read outside the modules' loops (a test or a tool reading sim.neighbours),
  /// added to the modules' in neighbourPairMask(); kAllPairClasses keeps every pair.
  PairMask extraNeighbourPairs = 0;
  /// The pair classes (libcore/phases.hpp) the neighbour lists keep: the union of the modules'
  /// Module::neighbourPairsRead() and extraNeighbourPairs, every class when there is no module.
  /// The search leaves the pairs of the other classes out (the Verlet candidates too), so the
  /// loops do not sweep pairs that none of them reads (issue 17, docs/performance.md "Pair
  /// classes no loop reads"); every real particle keeps its row (empty when its phase reads no
  /// class). Asked at every updateNeighbours: a module added later is taken at once (the
  /// candidates of another mask are searched again).
  PairMask neighbourPairMask() const;
  /// The candidates of the last search: the Verlet candidates (radius support + skin) when the
  /// skin is active, the exact list otherwise. A superset of every neighbour list until
  /// neighbourBuilds() changes (then the store may also have been reordered).
  const NeighbourList& neighbourCandidates() const {
    return verletActive_ ? verlet.candidates() : neighbours;
  }
  /// Number of neighbour searches so far (rebuilds of the candidates).
  Index neighbourBuilds() const { return neighbourBuilds_; }

  // ---- scheduling ----
  void addModule(std::unique_ptr<Module> module);
  Module* module(const std::string& name) const;
  /// Registers d(value)/dt = rate with the integrator (both fields must exist). A field has one
  /// rate, advanced for one set of particles: a second rate, or the same rate with another
  /// freeOnly, is refused (std::logic_error) instead of being dropped.
  void addIntegrated(RealField value, RealField rate, bool freeOnly = true);
  /// Phases present among the real particles: count per phase (kPhaseCount entries).
  std::vector<Index> phaseCounts() const;
  /// The pair classes of the phases present (wall-wall excluded: walls never move) must each
  /// have exactly one owner among the modules (Module::ownedPairs); throws InputError naming the
  /// class and the modules otherwise, and for particles of an unset phase.
  void checkPairOwners() const;
  /// The acceleration of the previous rate evaluation (moving boundaries, Adami et al. 2012:
  /// the wall pressure needs the wall's acceleration). Registered on first request; zero
  /// before the first evaluation.
  RealField previousAcceleration();
  /// The position correction (XSPH, Eq. 2.66; particle shifting): one core field, integrated as
  /// the second rate of the positions of free particles, that every module adds into (the
  /// modules' corrections of their own particles never collide). Registered on first request.
  RealField positionCorrection();
  /// Stage 1: wrap periodic particles, (re)build halos and neighbour lists; reorder the store
  /// along the cells every reorderEvery calls.
  void updateNeighbours();
  /// Stages 1-6: updateNeighbours, then evaluateRatesOnTheList.
  void evaluateRates();
  /// Stages 2-6 on the neighbour lists as they stand: zero accelerations and rates, then every
  /// module's kinematics, constitutive, forces, interfaces and constraints, in module order
  /// within a stage (a test may edit the lists between the two).
  void evaluateRatesOnTheList();
  /// Minimum over the modules' limits (and +inf when no module limits the step).
  double stableTimeStep() const;
  /// Columns for timeseries.csv: time, step, dt, kinetic energy, then each module's.
  std::vector<std::pair<std::string, double>> diagnostics() const;
  /// Throws NumericalError naming the first particle and field that is NaN or Inf.
  void checkFinite() const;
  /// Kinetic energy of the real, non-fixed particles: sum 1/2 m v^2.
  double kineticEnergy() const;

 private:
  RealField previousAcceleration_, positionCorrection_;
  Index neighbourBuilds_ = 0;
  bool verletActive_ = false;
  std::vector<Index> order_;
};

}  // namespace poresph
