#pragma once
// Scene files (YAML) -> a ready Simulation.
//
// loadScene() reads a scene (docs/scene-format.md lists every key), checks every value (unknown
// keys, wrong types, ranges; every error is an InputError naming file:line, key and value),
// dispatches each material to the module that owns its model (ModuleRegistry::moduleForModel,
// Module::configure) together with the module's own section, fills the geometry regions with a
// lattice of spacing dx (libcore/geometry.hpp), sets masses m = rho0 dx^D from each material's
// `density`, initialises the modules and checks a fixed time step against the modules' stable
// limit (Eqs. 2.49-2.50).
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "libcore/geometry.hpp"
#include "libcore/health.hpp"
#include "libcore/reference.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

struct TimeStepSettings {
  bool adaptive = false;  ///< dt = min(cfl * stable limit, dt cap, remaining time) each step
  double dt = 0.0;        ///< fixed step (s); with adaptive, an upper bound (0: none)
  double cfl = 1.0;       ///< factor on the modules' stable limit when adaptive, in (0, 1]
};

struct OutputSettings {
  long everySteps = 0;    ///< snapshot + timeseries every N steps (0: off)
  double everyTime = 0.0; ///< ... or every T seconds of simulated time (0: off)
};

struct SceneOptions {
  /// Build neighbour lists, call every module's initialise(), evaluate the rates once and check
  /// the time step. `poresph info` loads without it.
  bool initialise = true;
  /// Fill the geometry with particles. false: stop after the modules' configure(), the counting
  /// pass and the memory estimate (Scene::memory), allocating no particle; buildParticles() does
  /// the rest (`poresph info` prints the estimate first). Implies no initialise.
  bool buildParticles = true;
  /// Refuse (InputError naming `spacing`) a scene whose memory estimate exceeds the available
  /// memory, before any particle is allocated (`poresph run --force` turns it off).
  bool checkMemory = true;
  /// The available memory to compare with, in bytes; 0: availableMemoryBytes() (MemAvailable).
  std::uint64_t availableMemory = 0;
};

/// What a run of the scene needs in memory, estimated before any particle is allocated: the
/// particle count of the counting pass (countLattice) times the bytes per particle of the fields
/// the modules registered in configure() and will register in initialise(), the integrator's
/// scratch, the run loop's rollback copy (libcore/health.hpp RollbackState), plus the neighbour
/// lists (lattice estimate latticeNeighbourCount x 4 bytes + an 8-byte offset) and the search's
/// per-particle arrays (16 + 8 D bytes): memoryReport() of libcore/memory.hpp. Periodic ghosts
/// are counted in the fields (support / periodic length of every field); the transient arrays of
/// the geometry fill and of initialise() are not.
struct MemoryEstimate {
  std::uint64_t particles = 0;
  /// Registered fields, the integrator's scratch and the fields modules register in
  /// initialise() (Module::deferredBytesPerParticle)
  std::uint64_t fieldBytesPerParticle = 0;
  std::uint64_t rollbackBytesPerParticle = 0;   ///< RollbackState (checkpoint + output fields)
  std::uint64_t neighbourBytesPerParticle = 0;  ///< lists + search
  std::uint64_t bytesPerParticle = 0;           ///< fields + rollback + neighbours
  std::uint64_t totalBytes = 0;                 ///< particles x bytesPerParticle (saturated)
  std::uint64_t availableBytes = 0;             ///< MemAvailable (0: unknown)
  bool fits() const { return availableBytes == 0 || totalBytes <= availableBytes; }
  /// One line: "about 1.2 GiB for 5000000 particles x 256 bytes/particle (...); 20 GiB available".
  std::string describe() const;
};

struct Scene {
  std::string file;                 ///< path of the scene file as given
  std::unique_ptr<Simulation> sim;  ///< state, modules, materials, particles

  // ---- resolved settings (defaults filled in) ----
  double hOverDx = 1.3;
  std::string kernelName = "cubic_spline";
  std::string integrator = "leapfrog";
  double endTime = 0.0;
  long maxSteps = 0;  ///< 0: no limit
  TimeStepSettings timeStep;
  OutputSettings output;
  HealthLimits health;      ///< the `health:` section (libcore/health.hpp)
  ReferenceSpec reference;  ///< the `reference:` section (libcore/reference.hpp)
  std::vector<Region> regions;
  std::vector<Index> particlesPerMaterial;  ///< by material id (counted before the fill)
  std::vector<double> referenceDensity;     ///< rho0 by material id
  MemoryEstimate memory;                    ///< estimated before the particles are allocated
  bool particlesBuilt = false;              ///< false after loadScene with buildParticles = false
  std::string spacingWhere;                 ///< "file:line: key 'spacing' = '...'" for messages
  std::string geometryWhere;                ///< "file:line: key 'geometry'" for messages
  std::vector<std::string> moduleSections;  ///< modules that got a scene section
  double initialStableTimeStep = std::numeric_limits<double>::infinity();
  std::string stableLimitModule;            ///< module with the smallest limit ("" if none)

  // ---- echo ----
  YAML::Node source;      ///< the scene as read
  YAML::Node resolved;    ///< every scene-level value used (defaults included)

  /// The step to take from sim->time: fixed dt or cfl * stable limit (capped by dt), never past
  /// end_time. Throws NumericalError when the adaptive step is not positive and finite.
  double nextTimeStep() const;
  /// True once end_time (or max_steps) is reached.
  bool finished() const;
  /// The first module end condition that holds (Module::endCondition), "" if none: the reason
  /// a run ended before end_time and max_steps.
  std::string endConditionMet() const;
};

/// Reads and builds a scene. Throws InputError (file, line, key, value in the message).
Scene loadScene(const std::string& path, const SceneOptions& options = {});
/// Same from text; `fileName` is used in messages and relative paths.
Scene loadSceneText(const std::string& text, const std::string& fileName,
                    const SceneOptions& options = {});
/// Module initialisation and the time-step check (what loadScene does with initialise = true).
void initialiseScene(Scene& scene);
/// Second phase of a scene loaded with buildParticles = false: fills the geometry with particles
/// (masses, densities, materials, motions, velocities). Does not initialise.
void buildParticles(Scene& scene);

/// The resolved scene (every value used, defaults included, materials and module sections as
/// given, modules in stage order) as YAML: what `poresph run` writes to run.yaml.
std::string resolvedSceneYaml(const Scene& scene);

/// A human-readable summary: dimension, domain, particles per material, modules, fields with
/// components and owner, bytes per particle, neighbour counts (estimate; measured when the
/// neighbour lists were built), time step. What `poresph info` prints.
std::string describeScene(const Scene& scene);

/// Expected neighbour count of an interior particle on a full lattice: lattice sites strictly
/// within the kernel support (self excluded), counted exactly on the lattice.
Index latticeNeighbourCount(int dimension, double supportOverDx);

}  // namespace poresph
