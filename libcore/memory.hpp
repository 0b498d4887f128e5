#pragma once
// Memory available to this process, so that big allocations (voxel images, scenes) can be
// refused up front with the numbers instead of failing half-way with std::bad_alloc or the
// kernel's OOM killer; and what a run holds per particle (MemoryReport, `poresph info`).
#include <cstdint>
#include <string>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

class Simulation;

/// MemAvailable from /proc/meminfo in bytes (the kernel's estimate of what can be allocated
/// without swapping); 0 when unknown (no /proc, other systems): callers then skip their check.
std::uint64_t availableMemoryBytes();

/// Human-readable size with binary units, e.g. "512 B", "3.2 GiB".
std::string formatBytes(std::uint64_t bytes);

/// One line of a MemoryReport: bytes per real particle held by one owner.
struct MemoryLine {
  std::string what;             ///< "fields: fluid", "neighbour list", "rollback copy", ...
  double bytesPerParticle = 0;  ///< per real particle (ghosts and lists averaged over them)
  /// Store fields only: the share of these bytes held for particles whose material the owner
  /// does not own (e.g. solid fields of fluid particles); 0 for core fields and the rest.
  double foreignBytesPerParticle = 0;
  std::string note;
};

/// What a run of the simulation holds per particle, by owner (docs/particle-store.md):
///  - the store's fields grouped by the module that registered them ("core", "fluid", "solid",
///    "integrator", ...); the integrator's scratch copies are added from Simulation::integrated
///    when the integrator has not registered them yet (it does at the first step);
///  - periodic ghosts (every field of each ghost), when the halo was built;
///  - the rollback copy of the run loop (RollbackState: the checkpoint fields);
///  - the neighbour list (measured when built, else the lattice estimate) and the search's
///    arrays (measured when built, else 16 + 8 D bytes).
struct MemoryReport {
  std::vector<MemoryLine> lines;
  std::uint64_t particles = 0;   ///< real particles (or the counted ones before building)
  double bytesPerParticle = 0;   ///< sum of the lines
  double foreignBytesPerParticle = 0;
  std::uint64_t totalBytes() const {
    return static_cast<std::uint64_t>(bytesPerParticle * static_cast<double>(particles) + 0.5);
  }
};

/// `particles`: the count to scale to (0: the store's real count). `neighboursPerParticle`: the
/// estimate used while no list was built (lattice count of the kernel support).
MemoryReport memoryReport(const Simulation& sim, std::uint64_t particles,
                          double neighboursPerParticle);
/// The report as lines for `poresph info` ("memory by owner:" then one line per owner).
std::string describeMemory(const MemoryReport& report);

}  // namespace poresph
