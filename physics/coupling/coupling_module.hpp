#pragma once
// Two-way fluid-solid coupling (module "coupling"): the owner of the fluid-solid pair class.
//
// Interface conditions of the thesis, Eqs. 1.37-1.38 (velocity continuity, normal stress
// continuity), by extended summation over the interacting particles (Sec. 5.1, after Antoci et
// al. 2007): a solid particle takes part in the fluid sums of its fluid neighbours as a moving
// boundary whose pressure and no-slip velocity the fluid module extrapolates from the fluid
// (Adami et al. 2012, with the -a_w term of a moving wall), and each fluid-solid pair force
// (pressure 5.2b, viscosity 5.4, artificial viscosity 2.64, written once in
// libcore/fluid_pair_terms.hpp) is applied to both particles: +F on the fluid particle, -F on
// the solid one. Action = reaction holds pair by pair, so the total momentum of fluid and solid
// is conserved; the solid feels the water and gas pressure as a traction through the same
// forces that keep the fluid out of it. The fluid's continuity sum over its solid neighbours
// (5.1a, with the solid's velocity) is applied here as well.
//
// Why the solid's own Cauchy stress is not put into the fluid's momentum sum: near a loaded
// solid its in-plane stresses (bending, confinement) are orders of magnitude above the fluid
// pressure, and with a kernel truncated at the interface they would push the fluid sideways;
// the traction the fluid must see is sigma . n = -p n, which the extrapolated pressure gives.
// (docs/coupling.md)
//
// Added automatically to a scene that has fluid and solid particles (no section needed). It
// reads from the store only: pressure and wall_velocity (fluid, constitutive stage),
// viscous_factor and density_rate (fluid), and the material table (Material::fluid).
//
// Columns: fluid_solid_force_{x,y,z}: the total force of the fluid on the solid (N, per unit
// length in 2D).
#include <array>
#include <string>
#include <vector>

#include "libcore/fluid_pair_terms.hpp"
#include "libcore/module.hpp"
#include "libcore/particle_store.hpp"

namespace poresph {

class CouplingModule : public Module {
 public:
  std::string name() const override { return "coupling"; }
  std::vector<std::string> materialModels() const override { return {}; }
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseFluid, kPhaseSolid)};
  }
  /// The fluid rows' solid neighbours and the solid rows' fluid neighbours only.
  PairMask neighbourPairsRead() const override { return pairClassBits(kPhaseFluid, kPhaseSolid); }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override;
  void initialise(Simulation& sim) override;
  void interfaces(Simulation& sim) override;
  void diagnostics(const Simulation& sim,
                   std::vector<std::pair<std::string, double>>& columns) const override;
  /// The fluid-solid pairs store no energy of their own: with the mirror model the work they do
  /// is exactly what the fluid's compression energy and the solid take up, so the energy check
  /// stays on; with the extrapolated model it does not close (returns false: check off).
  /// fluid_solid (mirror / extrapolated), recorded in checkpoints (Module::settings).
  ModuleSettings settings() const override {
    return {{"coupling.fluid_solid", model_ == BoundaryModel::Extrapolated ? "extrapolated" : "mirror",
             "mirror"}};
  }
  bool energyAccount(const Simulation& sim, EnergyAccount& account) const override {
    return model_ == BoundaryModel::Mirror;
  }

  /// Total force of the fluid on the solid at the last evaluation (N; N/m in 2D).
  const std::array<double, 3>& forceOnSolid() const { return forceOnSolid_; }

 private:
  template <int D> void interfacesD(Simulation& sim);
  RealField pressure_, wallVelocity_, viscousFactor_, densityRate_;
  std::array<double, 3> forceOnSolid_{0, 0, 0};
  BoundaryModel model_ = BoundaryModel::Mirror;  // section key fluid_solid
};

}  // namespace poresph
