#pragma once
// HDF5 checkpoints (docs/output.md): every field flagged kFieldCheckpoint of the real particles
// (dataset /fields/<name>, shape [n, components], double or int32), plus attributes time, step,
// dt, dimension, particle count, and the domain (lo, hi, periodic).
#include <string>

#include "libcore/module.hpp"

namespace poresph {

class Simulation;

/// Writes sim's restart state to `path` (HDF5, overwritten). Throws InputError if the file
/// cannot be created.
/// `signature` (optional) identifies the scene (runner.cpp: sceneSignature) and is compared by
/// readCheckpoint.
/// `integratorState` (optional, Integrator::saveState) is written under /integrator/<entry>: a
/// restart that puts it back continues the run to round-off instead of re-priming the scheme.
void writeCheckpoint(const Simulation& sim, const std::string& path,
                     const std::string& signature = "",
                     const ModuleState* integratorState = nullptr);

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
