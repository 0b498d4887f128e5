#pragma once
// Elastic solid module (issue 4): material model "elastic", module name "solid".
//
// Formulations (thesis Chapter 2.4):
//  - total_lagrangian: Saint Venant-Kirchhoff, F and dF/dt from reference-configuration mixed
//    corrected gradients (Eqs. 2.67-2.68), E_GL, S, P (2.71-2.74), momentum 2.76 and energy 2.77,
//    rho = rho0 / J (2.78-2.79).
//  - small_strain_stress: strain and strain rate from the current-configuration mixed corrected
//    gradient (2.82-2.83), isotropic law (2.84), continuity, momentum and energy (2.85-2.87).
//  - small_strain_displacement: Navier's equation (2.88) with the second-derivative operator of
//    Eq. 2.46c / 2.89 (Eq. 2.90, written for 1D, 2D and 3D).
// Plus Monaghan artificial viscosity (2.64-2.65), XSPH (2.66), viscous damping for dynamic
// relaxation, TL hourglass control (conservative penalty energy by default, or Ganzenmueller's
// pairwise spring), boundary conditions (clamped and symmetry layers with mirror
// images, imposed velocity/displacement ramps on all or some components (rollers), traction,
// pressure) and energy bookkeeping. TL reference families cross periodic faces (images at
// initialise, minimum-image separations). TL is the formulation that carries damage (issue 13,
// docs/solid.md "Which formulation carries damage"). See docs/solid.md.
//
// Fields registered (store names): reference_position, displacement, strain, stress (Cauchy),
// internal_energy (+ _rate), solid_work (3: boundary work, external work, dissipated) (+ _rate),
// solid_boundary (int, 1 + index of the boundary condition, 0 = none), solid_boundary_force,
// solid_mirror_source (int, 1 + id of a layer particle's image; with mirror layers),
// with XSPH the core field position_correction (Simulation::positionCorrection, shared with the
// fluid);
// TL: deformation_gradient, first_piola, solid_family_row (the family itself is held by the
// module), solid_hourglass_energy (conservative hourglass control only); small strain: density_rate and the
// correction state solid_correction_{matrix,shepard_sum,shepard_gradient} (libcore/corrections).
#include <array>
#include <string>
#include <vector>

#include "libcore/corrections.hpp"
#include "libcore/module.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/particle_store.hpp"
#include "libcore/types.hpp"
#include "physics/solid/constitutive_law.hpp"

namespace poresph {

class Simulation;

namespace solid {

enum class Formulation { SmallStrainStress, SmallStrainDisplacement, TotalLagrangian };
enum class Plane { Strain, Stress };

/// Parameters of one "elastic" material, after checks.
struct ElasticMaterial {
  int materialId = -1;
  std::string name;
  double density = 0.0;       ///< rho0 [kg/m^3]
  double young = 0.0;         ///< E [Pa]
  double poisson = 0.0;       ///< nu [-]
  double lambda = 0.0;        ///< Lame lambda used by the law (plane stress / 1D adjusted) [Pa]
  double mu = 0.0;            ///< shear modulus [Pa]
  double waveSpeed = 0.0;     ///< sqrt((lambda + 2 mu) / rho0) [m/s]
  double avAlpha = 0.0;       ///< Eq. 2.64 alpha
  double avBeta = 0.0;        ///< Eq. 2.64 beta
  double xsph = 0.0;          ///< Eq. 2.66 epsilon
  double damping = 0.0;       ///< viscous damping coefficient c [1/s]: a -= c v
  double hourglass = 0.0;     ///< TL hourglass control coefficient alpha (penalty alpha E) [-]
  /// Stress from strain and damage (elastic or an elasto-damage law of Chapter 4, key `damage:`
  /// of the material; physics/solid/constitutive_law.hpp, docs/damage.md).
  ConstitutiveLaw law;
};

/// Lame parameters of the law used in dimension `dim`: 3D and plane strain: the 3D ones;
/// plane stress: lambda* = 2 lambda mu / (lambda + 2 mu); 1D (uniaxial stress): lambda = 0,
/// 2 mu = E so that sigma = E eps.
void lameParameters(double E, double nu, int dim, Plane plane, double& lambda, double& mu);

enum class BoundaryType { Clamped, Velocity, Displacement, Traction, Pressure, Symmetry };

struct Boundary {
  BoundaryType type = BoundaryType::Clamped;
  std::string label;
  // selection (reference configuration): a box and/or a material
  bool hasBox = false;
  std::array<double, 3> boxMin{0, 0, 0}, boxMax{0, 0, 0};
  int material = -1;
  bool hasShell = false;  ///< selection |X - centre| in [rMin, rMax]
  std::array<double, 3> shellCentre{0, 0, 0};
  double shellMin = 0.0, shellMax = 0.0;
  std::array<double, 3> value{0, 0, 0};  ///< velocity, displacement or traction vector
  /// Velocity/displacement only: the components that are imposed (`components: [y]`); the
  /// others are free (zero traction along them: a roller, thesis Eq. 4.31). All by default.
  std::array<bool, 3> imposed{true, true, true};
  bool partial = false;  ///< some component is free (the particles stay kMotionFree)
  double pressure = 0.0;
  double rampTime = 0.0;  ///< linear ramp 0 -> value over rampTime (0: applied at once)
  double area = 0.0;      ///< traction: area per particle [m^(D-1)]; 0: spacing^(D-1)
  /// Clamped only: mirror (ghost) layer, thesis Sec. 2.6: each particle of the layer takes the
  /// displacement and velocity of its mirror image across the plane, negated (odd reflection),
  /// so that u = 0 on the plane exactly and the displacement field stays smooth across it.
  bool mirror = false;
  std::array<double, 3> mirrorPoint{0, 0, 0}, mirrorNormal{0, 0, 0};
  std::string where;  ///< "file:line: key 'solid.boundaries[k]...'": messages name the scene
};

class ElasticSolidModule : public Module {
 public:
  std::string name() const override { return "solid"; }
  std::vector<std::string> materialModels() const override { return {"elastic"}; }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override;
  void initialise(Simulation& sim) override;
  void kinematics(Simulation& sim) override;
  void constitutive(Simulation& sim) override;
  void forces(Simulation& sim) override;
  void constraints(Simulation& sim) override;
  /// Damage commit after the step (`damage_commit: step_end`, the default; damage.cpp).
  void endOfStep(Simulation& sim, double dt) override;
  /// The clipped-update counter is run state: checkpointed so a restart continues the count.
  ModuleState saveState() const override {
    return {{"damage_clipped_updates", {static_cast<double>(clippedUpdates_)}}};
  }
  void restoreState(const ModuleState& state) override {
    for (const auto& [name, v] : state)
      if (name == "damage_clipped_updates" && !v.empty()) clippedUpdates_ = static_cast<long>(v[0]);
  }
  /// Per elastic material its formulation, plane (2D) and damage law, split and (Rankine)
  /// tensile_measure; the section's hourglass_form, damage_commit and smoothing_length
  /// (Module::settings: recorded in checkpoints, compared on restart).
  ModuleSettings settings() const override;
  double timeStepLimit(const Simulation& sim) const override;
  /// The TL reference family registered in initialise(): per member an id, a slot (int32 each)
  /// and D gradient doubles, plus the member count (docs/particle-store.md "Memory").
  double deferredBytesPerParticle(const Simulation& sim, double neighbours,
                                  const std::vector<Index>& particlesPerMaterial) const override;
  /// solid-solid (the fluid-solid pairs belong to the coupling module).
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseSolid, kPhaseSolid)};
  }
  /// The small-strain formulation's rows read their solid neighbours (strain, continuity); the
  /// Total-Lagrangian one reads its own reference families, not the lists. No other class.
  PairMask neighbourPairsRead() const override { return pairClassBits(kPhaseSolid, kPhaseSolid); }
  void diagnostics(const Simulation& sim,
                   std::vector<std::pair<std::string, double>>& columns) const override;
  /// Solid speed against the wave speed (Eq. 2.50) and J = det F > 0 (TL); docs/reliability.md.
  void checkHealth(const Simulation& sim, const HealthLimits& limits,
                   std::vector<HealthIssue>& issues) const override;
  /// Elastic energy (stored), boundary and traction work (in), dissipation.
  bool energyAccount(const Simulation& sim, EnergyAccount& account) const override;

  // ---- introspection (tests, docs) ----
  Formulation formulation() const { return formulation_; }
  Plane plane() const { return plane_; }
  const std::vector<ElasticMaterial>& elasticMaterials() const { return mats_; }
  const std::vector<Boundary>& boundaries() const { return boundaries_; }
  /// Elastic (stored) energy: TL sum V0 1/2 S:E_GL; small strain sum V0 1/2 sigma:eps [J].
  double elasticEnergy(const Simulation& sim) const;
  /// Kinetic energy of the solid's non-fixed particles [J].
  double kineticEnergy(const Simulation& sim) const;
  /// Penalty energy of the conservative hourglass control, sum V0 phi_hg (0 without it) [J]:
  /// a stored energy like the elastic one (docs/solid.md "Hourglass control").
  double hourglassEnergy(const Simulation& sim) const;
  /// True when the hourglass force is the gradient of hourglassEnergy() (hourglass_form
  /// conservative, the default); false: Ganzenmueller's pair spring (pairwise), whose power is
  /// counted in the dissipated energy.
  bool hourglassConservative() const { return hourglassConservative_; }
  /// Integrated internal energy sum V0 w (Eqs. 2.77 / 2.87, w per unit reference volume) [J].
  double internalEnergy(const Simulation& sim) const;
  /// Sums of solid_work: boundary work, external (traction) work, dissipated energy [J].
  std::array<double, 3> work(const Simulation& sim) const;
  /// The elastic CFL limit h sqrt(rho / (lambda + 2 mu)) (Eq. 2.50) over the materials, or
  /// 2 / omega of the hourglass penalty's fastest mode where that is smaller (large alpha).
  double elasticTimeStepLimit(const Simulation& sim) const;
  /// Largest reference family (TL) [-].
  int familyCapacity() const { return familyCapacity_; }
  /// Members of all TL reference families, and the bytes the module holds for them (outside the
  /// store: ids, gradients, row offsets).
  std::int64_t familyMembers() const { return famOffset_.empty() ? 0 : famOffset_.back(); }
  std::uint64_t heldBytes() const override;
  // ---- damage (docs/damage.md) ----
  /// True when some material has a `damage:` law (the damage fields exist).
  bool hasDamage() const { return anyDamage_; }
  /// Energy released by damage at fixed strain, sum V0 (g(D0) - g(D)) psi+ [J]: the dissipation
  /// that closes the energy balance.
  double damageDissipation(const Simulation& sim) const;
  /// Dissipated energy of Eq. 4.26b with Yc(D): sum V0 int_0^D Yc dD [J] (GSM laws).
  double damageDissipationYc(const Simulation& sim) const;
  /// Damage updates the criterion asked to take past s_l (clipped), since the start.
  long clippedDamageUpdates() const { return clippedUpdates_; }
  /// Unit tests of the force at a frozen damage field (SolidVariational): no commit in the
  /// evaluation (damage.cpp), the stress uses the damage field as it is.
  bool freezeDamage = false;

  /// Factor applied to the elastic limit of Eq. 2.50 when a step is checked (1 = the thesis).
  double courant = 1.0;

 private:
  template <int D> void initialiseDim(Simulation& sim);
  template <int D> void kinematicsDim(Simulation& sim);
  template <int D> void constitutiveDim(Simulation& sim);
  template <int D> void forcesDim(Simulation& sim);
  template <int D> void constraintsDim(Simulation& sim);
  template <int D> double elasticEnergyDim(const Simulation& sim) const;
  template <int D> void commitDamageDim(Simulation& sim);
  void rebuildIdMap(const Simulation& sim);
  template <int D> void applyMirrors(Simulation& sim);
  /// Stiffness of the hourglass penalty of the pair (a, b): (alpha_a E_a g(D_a) + alpha_b E_b
  /// g(D_b)) / 2, the degradation g of each law applied to its particle's share like the rest of
  /// its stiffness (Eq. 4.17; g = 1 without damage). docs/damage.md "Hourglass control under
  /// damage": with the undamaged E the penalty bridged the damaged bands and widened them.
  /// A particle's share alpha E g(D); the pair stiffness is the mean of the two shares (the
  /// member loops read the shares from a per-particle array filled once per evaluation).
  static double hourglassShare(const ElasticMaterial& a, double ga) { return a.hourglass * a.young * ga; }
  static double hourglassPairStiffness(double shareA, double shareB) { return 0.5 * (shareA + shareB); }
  int slotOf(std::int32_t material) const {
    return material >= 0 && static_cast<size_t>(material) < slot_.size()
               ? slot_[static_cast<size_t>(material)] : -1;
  }

  Formulation formulation_ = Formulation::TotalLagrangian;
  Plane plane_ = Plane::Strain;
  std::vector<ElasticMaterial> mats_;
  std::vector<int> slot_;  // material id -> index in mats_ (-1: not elastic)
  std::vector<Boundary> boundaries_;
  bool initialised_ = false;
  bool hasWave_ = false;
  std::array<double, 3> waveAmplitude_{0, 0, 0}, waveVector_{0, 0, 0};

  RealField refPos_, disp_, strain_, stress_, energy_, energyRate_, work_, workRate_, bcForce_;
  RealField defGrad_, piola_;
  // hourglass control (TL): the form, its energy density field (conservative form) and the
  // per-step scratch of the conservative form (effective stress P - M/2 and the direct pair
  // force per particle; grows with the particle count, never shrinks)
  bool anyHourglass_ = false, hourglassConservative_ = true;
  bool commitAtEvaluation_ = false;  ///< `damage_commit: evaluation` (damage.cpp)
  double hourglassOmega2_ = 0.0;  ///< largest omega^2 the hourglass penalty adds (step limit)
 public:
  /// The largest omega^2 of the hourglass control (0 without it) [1/s^2] (tests, docs).
  double hourglassOmega2() const { return hourglassOmega2_; }
 private:
  RealField hgEnergy_;
  std::vector<double> hgScratch_;
  // TL per-particle factors the member loops read (docs/performance.md "The rock scene's
  // step"): the reference volume m / rho0 and the hourglass share alpha E g(D), computed once
  // per evaluation instead of once per member (the same values bit for bit)
  std::vector<double> refVolume_, hgShare_;
  void refreshReferenceVolumes(const Simulation& sim);
  // TL reference family, held by the module in compressed rows over the solid particles
  // (initialise): member ids, g_ab, and g_ba (family_storage fast) or the slot of b's own
  // entry for a (compact); a particle's row is its solid_family_row field (-1: none).
  IntField familyRow_;
  std::vector<std::int64_t> famOffset_;
  std::vector<std::int32_t> famIds_, famRevSlot_;
  std::vector<double> famG_, famGR_;
  /// family_storage fast with the conservative hourglass control: the reference-state factor
  /// W(|X_ab|) / |X_ab|^2 of each member (constant: reference positions), 8 B per member, so
  /// the hourglass pass takes no sqrt and no kernel per member (docs/performance.md).
  std::vector<double> famHgW_;
  bool compactFamily_ = false;
  /// Positions (and ids) at the last TL deformation gradient: the step_end damage commit skips
  /// recomputing F when the solid has not moved since the evaluation (the same F bit for bit).
  std::vector<double> fPositions_;
  std::vector<std::int32_t> fIds_;
  bool fValid_ = false, reuseDeformationGradient_ = false;
  std::int64_t fSkipped_ = 0;
  void recordSolidPositions(const Simulation& sim);
  bool sameSolidPositions(const Simulation& sim) const;
 public:
  /// step_end commits that found F of the evaluation still current (tests, docs).
  std::int64_t deformationGradientReuses() const { return fSkipped_; }
 private:
  RealField densityRate_, xsph_;
  CorrectionFields corrFields_;
  NeighbourList solidNeighbours_;
  std::vector<double> volume_;
  IntField bc_, mirror_;
  bool anyMirror_ = false;
  std::string formulationWhere_;  ///< "file:line: key 'materials[k].formulation'", for messages
  int familyCapacity_ = 0;
  // damage: D (output), history (Rankine/Mohr-Coulomb equivalent strains), released energy
  // density; registered only when a material has damage
  bool anyDamage_ = false;
  RealField damage_, damageHistory_, damageReleased_;
  /// degradable energy density (the coefficient of g(D): psi+ and the hourglass penalty share)
  /// at the last commit, for the step's trapezoidal release (damage.cpp); < 0: none yet
  RealField damageDegradable_;
  long clippedUpdates_ = 0;
  std::vector<Index> idToIndex_;
  /// Periods of the periodic axes (0 on the others): TL reference families that cross a
  /// periodic face use minimum-image separations.
  std::array<double, 3> period_{0, 0, 0};
  bool anyPartial_ = false;  ///< some boundary imposes only some components
  /// solid: {smoothing_length: h} (TL only): the solid's own kernel (the run's kernel type with
  /// this h) for its families, internal forces, hourglass, viscosity, XSPH and step limit; 0:
  /// the run's kernel. Pairs with other phases keep the run's h.
  double ownH_ = 0.0;
  int dim_ = 0;  ///< the run's dimension (settings(): plane in 2D)
  Kernel kernel_;
  const Kernel& solidKernel(const Simulation& sim) const;
  std::array<double, 3> gravity_{0, 0, 0};  ///< solid: {gravity: [..]} [m/s^2]
  bool hasGravity_ = false;
  void applyGravity(Simulation& sim);
};

}  // namespace solid
}  // namespace poresph
