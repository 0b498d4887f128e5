#pragma once
// Phase of a particle (core int field "phase"): decides the pair class of an interaction
// (fluid-fluid, fluid-solid, ...). The module that owns a material declares its phase in
// configure() (Material::phase); the scene gives each particle the phase of its material before
// any module is initialised, so no particle is ever of an unset phase.
//
// Pair classes: every pair of phases present in a scene is an interaction that exactly one
// module owns (Module::ownedPairs): that module applies the pair force to both particles of the
// pair (action = reaction). Simulation::checkPairOwners refuses a scene where two modules claim
// one class or a class whose phases are both present has no owner.
#include <cstdint>
#include <string>

namespace poresph {

enum Phase : std::int32_t {
  kPhaseUnset = -1,  ///< a material whose module declared no phase (refused by the scene)
  kPhaseFluid = 0,  ///< water or gas (physics/fluid)
  kPhaseWall = 1,   ///< fixed boundary particles (take part in fluid sums, never move)
  kPhaseSolid = 2,  ///< deformable solid: clay matrix (physics/solid, physics/damage)
  kPhaseRigid = 3,  ///< rigid inclusions (physics/rigid)
};
constexpr int kPhaseCount = 4;

inline const char* phaseName(std::int32_t p) {
  switch (p) {
    case kPhaseFluid: return "fluid";
    case kPhaseWall: return "wall";
    case kPhaseSolid: return "solid";
    case kPhaseRigid: return "rigid";
    default: return "unset";
  }
}

/// An unordered pair of phases (a <= b).
struct PairClass {
  std::int32_t a = kPhaseFluid, b = kPhaseFluid;
  PairClass() = default;
  PairClass(std::int32_t p, std::int32_t q) : a(p < q ? p : q), b(p < q ? q : p) {}
  bool operator==(const PairClass& o) const { return a == o.a && b == o.b; }
  std::string name() const { return std::string(phaseName(a)) + "-" + phaseName(b); }
};

/// A set of pair classes as the rows of a neighbour list see them: bit a * kPhaseCount + b set
/// when the rows of phase-a particles hold their phase-b neighbours. A class sets both of its
/// bits (a loop may read a pair in either particle's row, and a half list stores it in one row
/// only). Module::neighbourPairsRead, Simulation::neighbourPairMask (docs/performance.md "Pair
/// classes no loop reads").
using PairMask = std::uint32_t;
constexpr PairMask kAllPairClasses = (PairMask(1) << (kPhaseCount * kPhaseCount)) - 1;
/// The class of phases p and q (both bits).
constexpr PairMask pairClassBits(std::int32_t p, std::int32_t q) {
  return (PairMask(1) << (p * kPhaseCount + q)) | (PairMask(1) << (q * kPhaseCount + p));
}
/// Every class with phase p on one side (p-fluid, p-wall, p-solid, p-rigid).
constexpr PairMask pairClassesWith(std::int32_t p) {
  PairMask m = 0;
  for (std::int32_t q = 0; q < kPhaseCount; ++q) m |= pairClassBits(p, q);
  return m;
}

}  // namespace poresph
