#pragma once
// Drainage driver and monitor (module "drainage", scene section `drainage:`; docs/drainage.md).
//
// The set-up of the thesis' drainage runs (Sec. 5.2, Fig. 5.3): a sample slab between two
// reservoirs of the invading fluid (gas) along a periodic flow axis; the pressure drop between
// the reservoirs is imposed "by means of a body force F_z applied to every gas material point in
// reservoirs": with the reservoirs of total length L_r along the axis and the gas density rho_g,
//   f = dP / (rho_g L_r)                                     (per unit mass, along `push`)
// so that a gas column at rest in the reservoirs carries the pressure difference dP
// (dp/ds = rho_g f) that the sample then sees between its two faces. `ramp_time` raises f
// linearly from 0 (f min(1, t / ramp_time)), as the solid ramps its loads.
//
// What it measures (timeseries.csv columns, all counted in the sample slab, volumes V = m/rho of
// the current density, so the porosity follows the deformed solid):
//   drainage_porosity          V_fluid / (V_fluid + V_solid)       (solid particles and rigid
//                              bodies listed in `inclusions`; other rigid bodies are plates)
//   drainage_gas_saturation    V_invading / V_fluid, drainage_water_saturation V_defending / V_fluid
//   drainage_percolated        1 once a cluster of invading particles (links shorter than
//                              `link_distance` x dx, periodic images not used) reaches within
//                              dx of both faces of the slab (gas breakthrough), else 0;
//                              drainage_percolation_time (-1 before)
//   drainage_flow_path         1 once the pore space plus the damaged solid (D > 0.5) spans the
//                              slab the same way (fluid of either phase or damaged solid
//                              particles, same links and faces): a path that damage opened
//                              between pores that were isolated (Sec. 5.5); 1 from the start
//                              when the pores already percolate; drainage_flow_path_time
//   drainage_damaged_fraction  solid volume with D > 0.5 / solid volume, drainage_max_damage
//                              (only when a `damage` field exists)
//   drainage_solid_mean_stress mean of tr(sigma)/D over the solid (volume weighted) and
//   drainage_solid_max_principal_stress (only when a `stress` field exists)
//   drainage_gas_velocity      volume-weighted mean velocity of the invading fluid in the slab
//                              along the push direction (v_g of Eqs. 5.12a, 5.14a)
//   drainage_capillary_number  mu_g v_g / gamma (5.12a; only with a surface tension) and
//   drainage_reynolds_number   rho_g v_g L / mu_g (5.14a; only with a gas viscosity), L the
//                              pore size (`pore_size`, or the hydraulic diameter measured at
//                              initialise: 4 V_pore / S_wall of the slab, S_wall from the
//                              fluid-solid face neighbours of the lattice)
// The percolation and flow-path times are module state (checkpointed, Module::saveState).
#include <string>
#include <vector>

#include "libcore/module.hpp"

namespace poresph {

class DrainageModule : public Module {
 public:
  std::string name() const override { return "drainage"; }
  std::vector<std::string> materialModels() const override { return {}; }
  /// The pore size reads the fluid rows' boundary neighbours of every phase; the percolation
  /// test links fluid particles, and the flow-path test also damaged solid ones (fluid-fluid,
  /// fluid-solid, solid-solid).
  PairMask neighbourPairsRead() const override {
    return pairClassesWith(kPhaseFluid) | pairClassBits(kPhaseSolid, kPhaseSolid);
  }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override;
  void initialise(Simulation& sim) override;
  void forces(Simulation& sim) override;
  void endOfStep(Simulation& sim, double dt) override;
  ModuleState saveState() const override;
  void restoreState(const ModuleState& state) override;
  /// axis and push direction, recorded in checkpoints (Module::settings).
  ModuleSettings settings() const override {
    const std::string axis(1, "xyz"[axis_]);
    return {{"drainage.axis", axis, axisDefault_}, {"drainage.push", push_, "negative"}};
  }
  void diagnostics(const Simulation& sim,
                   std::vector<std::pair<std::string, double>>& columns) const override;
  /// `poresph info`: the set-up, the body force and the fluids' ratios (Eqs. 5.13, density).
  std::string describe(const Simulation& sim) const override;

  /// Body force per unit mass on the invading fluid in the reservoirs (signed along the axis).
  double bodyForce() const { return force_; }
  /// True when a cluster of invading particles spans the slab face to face (evaluated now).
  bool percolates(const Simulation& sim) const;
  /// Pore space plus damaged solid spans the slab (drainage_flow_path).
  bool flowPathSpans(const Simulation& sim) const;
  double percolationTime() const { return percolationTime_; }
  /// `stop_after_percolation: t`: the run ends t seconds after the percolation time.
  std::string endCondition(const Simulation& sim) const override;
  /// Characteristic pore size L of Eqs. 5.11a/5.14a: `pore_size` or the measured hydraulic
  /// diameter (0 before initialise without the key).
  double poreSize() const { return poreSize_; }
  /// Hydraulic diameter 4 V / S of the pore space of the slab on the particle lattice: V the
  /// fluid particles' volume, S one dx^(D-1) face per fluid-nonfluid pair at distance dx
  /// (neighbour lists must exist); 0 when the slab has no pore wall.
  double measurePoreSize(const Simulation& sim) const;

 private:
  int axis_ = 0;
  std::string axisDefault_ = "z", push_ = "negative";  // for settings()
  double sampleLo_ = 0.0, sampleHi_ = 0.0;
  double pressureDrop_ = 0.0, force_ = 0.0, rampTime_ = 0.0, linkDistance_ = 1.5;
  int invading_ = -1, defending_ = -1;  // material ids
  std::vector<char> inclusion_;           // by material id: a rigid inclusion of the sample
  long checkEvery_ = 10;
  double stopAfterPercolation_ = -1.0;  // stop_after_percolation (s); < 0: not set
  mutable double percolationTime_ = -1.0;  // first time seen (endOfStep or an output row)
  mutable double flowPathTime_ = -1.0;     // likewise for drainage_flow_path
  /// One cluster of `member` particles (short real links) within dx of both slab faces.
  template <class Member>
  bool spans(const Simulation& sim, Member member) const;
  std::string where_;
  double poreSize_ = 0.0;
  bool poreSizeGiven_ = false;
  /// The parameters the dimensionless numbers of Eqs. 5.11-5.14 need: the simulated ones, and
  /// those of the real system given in the `physical:` section (NaN: not given).
  struct Parameters {
    double invadingDensity, defendingDensity, invadingViscosity, defendingViscosity,
        surfaceTension, poreSize, velocity, gravity;
  };
  Parameters physical_{};
  bool hasPhysical_ = false;
  mutable std::vector<std::int64_t> parent_;  // union-find scratch (sized at initialise)
};

}  // namespace poresph
