#pragma once
// HDF5 checkpoints (docs/output.md): every field flagged kFieldCheckpoint of the real particles
// (dataset /fields/<name>, shape [n, components], double or int32), plus attributes time, step,
// dt, dimension, particle count, and the domain (lo, hi, periodic), the scene signature and the
// resolved settings of the run (/settings).
#include <string>
#include <utility>
#include <vector>

#include "libcore/module.hpp"

namespace poresph {

class Simulation;

/// Writes sim's restart state to `path` (HDF5, overwritten). Throws InputError if the file
/// cannot be created.
/// `signature` (optional) identifies the scene (runner.cpp: sceneSignature) and is compared by
/// readCheckpoint.
/// `integratorState` (optional, Integrator::saveState) is written under /integrator/<entry>: a
/// restart that puts it back continues the run to round-off instead of re-priming the scheme.
/// `settings` (optional; default: every module's Module::settings()) are the run's resolved
/// settings, written under /settings (one string attribute per key) and compared on restart
/// (runner.cpp restoreCheckpoint).
void writeCheckpoint(const Simulation& sim, const std::string& path,
                     const std::string& signature = "",
                     const ModuleState* integratorState = nullptr,
                     const ModuleSettings* settings = nullptr);

/// What a checkpoint records of the run that wrote it, read without a simulation.
struct CheckpointRecord {
  std::string signature;     ///< the scene signature ("" when the file has none)
  bool hasSettings = false;  ///< false: written before settings were recorded (2026-11-28)
  std::vector<std::pair<std::string, std::string>> settings;  ///< (key, value), key order
};
/// Reads the record of `path`; a file that cannot be read gives an empty record (readCheckpoint
/// then says why).
CheckpointRecord readCheckpointRecord(const std::string& path);

/// Restores a checkpoint into `sim`, whose modules were configured as for the run that wrote it
/// (the same checkpoint fields registered). Replaces the particles (ghosts cleared), time, step,
/// dt and domain. Throws InputError naming the file and the field when a field is missing on
/// either side, or its type or number of components differs, or the dimension differs.
/// With `expectedSignature` (what a run passes: the simulation was just built from its scene)
/// it also refuses a checkpoint whose particle count differs from the simulation's or whose
/// scene signature differs.
/// With `integratorState` it also returns the file's integrator state (empty if it has none).
void readCheckpoint(Simulation& sim, const std::string& path,
                    const std::string& expectedSignature = "",
                    ModuleState* integratorState = nullptr);

}  // namespace poresph
