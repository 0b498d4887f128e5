#pragma once
// Halo (ghost) particles. Periodic images now; an MPI decomposition later adds a second
// exchanger that fills the same ghost range of the store with particles of neighbour ranks.
#include <vector>

#include "libcore/domain.hpp"
#include "libcore/particle_store.hpp"

namespace poresph {

class PeriodicHalo {
 public:
  /// Wraps real particles back into the box along periodic axes (positions only).
  void wrap(ParticleStore& store, const Domain& domain) const;
  /// Removes old ghosts, then adds an image of every real particle that lies within `width` of a
  /// periodic face (edges and corners included). Throws InputError if a periodic length is
  /// shorter than `width` (images of images would be needed).
  void build(ParticleStore& store, const Domain& domain, double width);
  /// Moves the ghosts of the last build with their sources (every ghost field copied again,
  /// positions shifted as built), without wrapping or choosing ghosts again: between two Verlet
  /// searches, when no real particle has moved by more than the skin / 2 the build's width
  /// included (Simulation::updateNeighbours).
  void refresh(ParticleStore& store) const;

 private:
  std::vector<Index> sources_;
  std::vector<double> shifts_;
};

}  // namespace poresph
