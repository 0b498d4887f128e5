#pragma once
// HDF5 checkpoints (docs/output.md): every field flagged kFieldCheckpoint of the real particles
// (dataset /fields/<name>, shape [n, components], double or int32), plus attributes time, step,
// dt, dimension, particle count, and the domain (lo, hi, periodic).
#include <string>

namespace poresph {

class Simulation;

/// Writes sim's restart state to `path` (HDF5, overwritten). Throws InputError if the file
/// cannot be created.
/// `signature` (optional) identifies the scene (runner.cpp: sceneSignature) and is compared by
/// readCheckpoint.
void writeCheckpoint(const Simulation& sim, const std::string& path,
                     const std::string& signature = "");

/// Restores a checkpoint into `sim`, whose modules were configured as for the run that wrote it
/// (the same checkpoint fields registered). Replaces the particles (ghosts cleared), time, step,
/// dt and domain. Throws InputError naming the file and the field when a field is missing on
/// either side, or its type or number of components differs, or the dimension differs.
/// With `expectedSignature` (what a run passes: the simulation was just built from its scene)
/// it also refuses a checkpoint whose particle count differs from the simulation's or whose
/// scene signature differs.
void readCheckpoint(Simulation& sim, const std::string& path,
                    const std::string& expectedSignature = "");

}  // namespace poresph
