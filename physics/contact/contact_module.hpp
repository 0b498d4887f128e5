#pragma once
// Contact between a deformable solid and fixed walls (module "contact"): the owner of the
// solid-wall pair class (libcore/phases.hpp), added automatically to a scene that has solid and
// wall particles (e.g. an elastic plate under water held by fluid wall particles, a clay sample
// confined by fixed walls).
//
// The pairwise repulsion of thesis Eq. A.18, F_a = -m_b / (m_a + m_b) B(r_ab) n_a, with the
// strength B of a stiff contact pressure (A.17: the solid's bulk modulus k_s = rho c_s^2):
//   B(r) = 2 k_s dx^(D-1) (1 - r / dx)   for r < dx (the lattice spacing), 0 beyond,
// n_a the unit vector from the wall particle to the solid one. Its stiffness per pair,
// k_s dx^(D-2), gives the contact the solid's own wave speed, so the solid's CFL limit (2.50)
// covers it. Walls are fixed: the reaction on them is not integrated. No friction.
#include <string>
#include <vector>

#include "libcore/module.hpp"

namespace poresph {

class ContactModule : public Module {
 public:
  std::string name() const override { return "contact"; }
  std::vector<std::string> materialModels() const override { return {}; }
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseSolid, kPhaseWall)};
  }
  /// The solid rows' wall neighbours only.
  PairMask neighbourPairsRead() const override { return pairClassBits(kPhaseSolid, kPhaseWall); }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override;
  void initialise(Simulation& sim) override;
  void interfaces(Simulation& sim) override;

 private:
  template <int D> void interfacesD(Simulation& sim);
  std::vector<double> bulkModulus_;  // by material id: rho0 c^2 of each elastic material
};

}  // namespace poresph
