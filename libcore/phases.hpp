#pragma once
// Phase of a particle (core int field "phase"): decides the pair class of an interaction
// (fluid-fluid, fluid-solid, ...). Each module sets the phase of the particles of its
// materials in Module::initialise(); interface conditions dispatch on it.
#include <cstdint>

namespace poresph {

enum Phase : std::int32_t {
  kPhaseFluid = 0,  ///< water or gas (physics/fluid)
  kPhaseWall = 1,   ///< fixed boundary particles (take part in fluid sums, never move)
  kPhaseSolid = 2,  ///< deformable solid: clay matrix (physics/solid, physics/damage)
  kPhaseRigid = 3,  ///< rigid inclusions (physics/rigid)
};

}  // namespace poresph
