#pragma once
// Two-phase weakly compressible fluid (thesis Sec. 1.3.1 and 5.1), module name "fluid".
//
// Material models owned here:
//   "fluid": density (rho0, kg/m^3), sound_speed (m/s), viscosity (dynamic, Pa s),
//            optional eos: linear (Eq. 1.4, default) | tait, tait_gamma (7),
//            background_pressure (Pa, 0), colour (+1 liquid, -1 gas, Eq. 5.6; default +1).
//   "wall":  fixed boundary particles (phase kPhaseWall, motion fixed): density (kg/m^3),
//            contact_angle (degrees, 90), velocity (m/s, tangential wall velocity, default 0).
// Pair classes owned here: fluid-fluid and fluid-wall. Particles of other phases (solid, rigid)
// enter the fluid's kinematic sums (colour, density summation, viscous normalisation) and get
// the extrapolated boundary pressure and no-slip velocity in the constitutive stage, but their
// pair forces (and continuity terms) belong to the module that owns that class (fluid-solid:
// physics/coupling, docs/coupling.md). Their wetting colour is Material::wettingCos.
//
// Module section "fluid" (all optional): see docs/fluid.md for the full list.
//
// Fields colour, colour_gradient, curvature, interface exist only with surface_tension > 0.
// Wetting (1.10): by default ("wetting: normal") the interface normal near a boundary is turned
// to the contact angle given by the boundary's colour cos(theta), and (option wetting_ghost)
// the boundary's ghost colour - the interface continued straight into the wall at that angle -
// completes the magnitude |n| (the CSF delta) at the contact line; "wetting: colour" instead puts
// the boundary colour into the sum of 5.7.
//
// Stages: kinematics = density summation (option), colour gradient (5.7), wetting normal and
// curvature (5.8) on interface particles only; constitutive = EOS (1.4 / Tait) and wall pressure/velocity
// extrapolation (extended summation with a hydrostatic wall pressure); forces = continuity
// (5.1a, or the mass form sum m_b v_ab . grad W with `continuity_form: mass`), pressure gradient
// (5.2a, the default `pressure_gradient: volume`; 5.2b `symmetric`; Hu-Adams), harmonic-mean viscosity (5.4), body forces, CSF surface
// tension (1.9), all in gather form.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "libcore/cell_walk.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/fluid_properties.hpp"
#include "libcore/module.hpp"
#include "libcore/pair_scatter.hpp"
#include "libcore/particle_store.hpp"
#include "libcore/time_schedule.hpp"
#include "libcore/types.hpp"
#include "physics/fluid/fluid_pair.hpp"

namespace poresph {

class FluidModule : public Module {
 public:
  using Eos = FluidProperties::Eos;
  using PressureForm = FluidPressureForm;  // fluid key pressure_gradient (fluid_pair.hpp)
  /// The libcore FluidProperties (copied into Material::fluid for the other modules) plus what
  /// only this module uses.
  struct MaterialData : FluidProperties {
    bool owned = false;  ///< a material of this module
    bool fluid = false;  ///< model "fluid" (otherwise a boundary)
    double colour = 1.0;         ///< fluid colour (5.6) or wall colour cos(theta) (1.10)
    std::vector<double> wallVelocity;
  };
  struct BodyForce {
    std::vector<double> acceleration, lo, hi;
  };
  /// Magnitude of the largest body-force acceleration (0 without body forces).
  double largestBodyForce() const {
    double fMax = 0.0;
    for (const BodyForce& b : bodyForces_) {
      double f2 = 0.0;
      for (double c : b.acceleration) f2 += c * c;
      fMax = std::max(fMax, std::sqrt(f2));
    }
    return fMax;
  }
  /// Adds to `acc` the acceleration of every body force whose box holds position `x` (D values).
  template <int D, class V>
  void addBodyForces(const double* x, V& acc) const {
    for (const BodyForce& b : bodyForces_) {
      bool inside = true;
      for (int a = 0; a < D; ++a)
        inside = inside && x[a] >= b.lo[static_cast<size_t>(a)] && x[a] <= b.hi[static_cast<size_t>(a)];
      if (inside)
        for (int a = 0; a < D; ++a) acc[a] += b.acceleration[static_cast<size_t>(a)];
    }
  }

  std::string name() const override { return "fluid"; }
  std::vector<std::string> materialModels() const override { return {"fluid", "wall"}; }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override;
  void initialise(Simulation& sim) override;
  void kinematics(Simulation& sim) override;
  void constitutive(Simulation& sim) override;
  void forces(Simulation& sim) override;
  double timeStepLimit(const Simulation& sim) const override;
  void diagnostics(const Simulation& sim,
                   std::vector<std::pair<std::string, double>>& columns) const override;
  /// Density variation and Mach number of the fluid particles (docs/reliability.md).
  void checkHealth(const Simulation& sim, const HealthLimits& limits,
                   std::vector<HealthIssue>& issues) const override;
  /// Gravity potential of the moving fluid; compression and surface energy as untracked scale.
  bool energyAccount(const Simulation& sim, EnergyAccount& account) const override;
  /// `poresph info`: the gravity_schedule, when the scene has one.
  std::string describe(const Simulation& sim) const override;
  /// The resolved choices of the fluid section (density, pressure_gradient, continuity_form,
  /// continuity_interface, wall_pressure, viscosity_mean, surface tension form and weighting,
  /// wetting, wall_normal, pressure_reference, pair_precision), recorded in checkpoints and
  /// compared on restart (Module::settings; the default pressure_gradient changed from
  /// Eq. 5.2b to Eq. 5.2a on 2026-11-27, docs/output.md "Restart and changed defaults").
  ModuleSettings settings() const override;

  /// fluid-fluid and fluid-wall (the fluid-solid pairs belong to the coupling module).
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseFluid, kPhaseFluid), PairClass(kPhaseFluid, kPhaseWall)};
  }
  /// Every class with a fluid side: a fluid row's sums run over every neighbour (density
  /// summation, viscous moment, shifting, transport velocity, walls, solids and rigid particles
  /// as boundaries), a boundary row of any phase reads its fluid neighbours (the pressure and
  /// velocity extrapolation, wet flags). No pair of two boundary particles is read.
  PairMask neighbourPairsRead() const override { return pairClassesWith(kPhaseFluid); }
  /// Every loop has a symmetric form for a half list (fluid_half.cpp) except the surface
  /// tension's (colour gradient, curvature, CSF), which needs the full list.
  bool supportsHalfNeighbourList() const override {  // CSF, light_mirror, wall_background_pressure, wall_push_only, wall_overlap_pressure: full list
    return gamma_ == 0.0 && !wallMirrorLight_ && !(wallBackground_ && pressureReference_) && !wallPushOnly_ &&
           !wallOverlap_;
  }
  /// `pair_precision: float`: the fluid-fluid pairs of the symmetric force loop in single precision.
  bool floatPairs() const { return floatPairs_; }
  /// Blocks and spill buffers of the symmetric loops (their allocations, for tests).
  const PairScatter& pairScatter() const { return scatter_; }
  /// The symmetric loops' per-particle sums and spill buffers (half list only; fluid_half.cpp).
  std::uint64_t heldBytes() const override;
  double deferredBytesPerParticle(const Simulation& sim, double neighbours,
                                  const std::vector<Index>& particlesPerMaterial) const override;

  // ---- read-only access for tests and diagnostics ----
  const MaterialData& materialData(int id) const { return mat_.at(static_cast<size_t>(id)); }
  double surfaceTension() const { return gamma_; }
  /// True when the CSF surface tension (1.9) is on; only then the fields colour,
  /// colour_gradient, curvature and interface exist (handles invalid otherwise).
  bool surfaceTensionActive() const { return gamma_ > 0.0; }
  /// Largest |rho - rho0| / rho0 over the fluid particles at the last EOS evaluation.
  double maxDensityVariation() const { return maxVariation_; }
  /// Largest |rho - rho0| / rho0 over the fluid particles now, and where (from the density field).
  MaxAt largestDensityVariation(const Simulation& sim) const;
  /// Number of EOS evaluations at which the density bound was exceeded.
  long long densityBoundExceeded() const { return boundExceeded_; }
  double densityBound() const { return densityBound_; }
  /// The key `gravity` (D components; unscaled).
  const std::vector<double>& gravity() const { return gravity_; }
  /// The key `gravity_schedule`: the factor of `gravity` over time (constant 1 without it).
  const TimeSchedule& gravitySchedule() const { return gravitySchedule_; }
  /// The gravity acting at time t, `gravity` x gravitySchedule().factor(t) (zero beyond D): what
  /// the force, the walls' hydrostatic extrapolation and sim.published.fluidGravity use at an
  /// evaluation at sim.time = t (docs/fluid.md "Ramped gravity").
  std::array<double, 3> gravityAt(double t) const;

  // field handles
  RealField pressure, densityRate, colour, colourGradient, curvature, wallVelocity;
  /// Viscous lattice normalisation factor D / sum_b V_b r^2 (-F) of each fluid particle (1 where
  /// the support is truncated), of the previous evaluation (summed in the force loop into
  /// viscous_factor_next); registered only with viscosity_normalisation on.
  RealField viscousFactor, viscousFactorNext;
  /// Position correction: XSPH (2.66) plus particle shifting, a second rate of the positions;
  /// registered only with xsph > 0 or shifting > 0.
  RealField positionCorrection;
  // Wall normal of fixed walls from a kernel of twice the smoothing length (option
  // wall_normal: wide; computed once in initialise, issue 14 "Wetting on real walls").
  RealField wallNormal;
  IntField interface;
  /// CSF acceleration a_s of each fluid particle (Eq. 1.9 as the force stage applies it),
  /// computed after the curvature (kinematics stage) so that the walls' pressure extrapolation
  /// (constitutive stage) can balance it and the force stage adds it; registered only with the
  /// CSF form of surface tension (issue 14 H5, docs/fluid.md "Fluid at the walls under a
  /// negative gauge pressure").
  RealField surfaceAcceleration;

 private:
  void initialiseHydrostatic(Simulation& sim);
  /// sim.published.fluidGravity = gravityAt(sim.time).
  void publishGravity(Simulation& sim) const;
  /// Refuses a sound speed below the flow speed the scene implies (InputError naming the key),
  /// warns below 3 x that.
  void checkSoundSpeeds(const Simulation& sim) const;
  /// The store fields the fluid loops read and write, looked up once per stage by fields() and
  /// passed to the gather and the symmetric loops alike (store pointers move when the store
  /// grows or is reordered, so a set is never kept beyond its stage). Optional fields are null
  /// when off.
  struct Fields {
    Index n = 0, nAll = 0;  ///< real particles; real and ghosts
    const double *x = nullptr, *v = nullptr, *m = nullptr;
    double *rho = nullptr, *p = nullptr, *vw = nullptr, *acc = nullptr;
    const std::int32_t *ph = nullptr, *mt = nullptr, *mo = nullptr;
    double* drho = nullptr;        ///< continuity rate (null with density summation)
    double* corrRate = nullptr;    ///< position correction (XSPH / shifting / transport velocity)
    double* visc = nullptr;        ///< viscous_factor (null without viscosity_normalisation)
    double* nextFactor = nullptr;  ///< viscous_factor_next (idem)
    const double* aw = nullptr;    ///< previous boundary acceleration (moving boundaries only)
  };
  Fields fields(Simulation& sim) const;
  /// Widest per-particle sum of the symmetric loops (the scatter is sized for it at each layout).
  int halfWidth(int d) const;
  /// The symmetric force loop's per-particle sums (forceLoopHalf's width).
  int forceWidth(int d) const;
  template <int D> void kinematicsD(Simulation& sim);
  template <int D> void surfaceAccelerationD(Simulation& sim);  // a_s (Eq. 1.9), after the curvature
  template <int D> void computeWallNormalsD(Simulation& sim);
  template <int D> void constitutiveD(Simulation& sim);
  template <int D> void forcesD(Simulation& sim);
  // The same sums on a half neighbour list, each pair evaluated once and added to both
  // particles (fluid_half.cpp, libcore/pair_scatter.hpp).
  template <int D> void wetFlagsHalf(Simulation& sim, const Fields& f);
  template <int D> void wallExtrapolationHalf(Simulation& sim, const Fields& f);
  template <int D> void densitySummationHalf(Simulation& sim, const Fields& f);
  template <int D> void viscousFactorsHalf(Simulation& sim, const Fields& f);
  template <int D>
  void forceLoopHalf(Simulation& sim, const Fields& f, double uShift, const double* wallRho);
  /// The scatter's layout, on the candidates, once per neighbour search, with its buffers and
  /// the per-particle sums sized there for halfWidth(); then set to `width` (no allocation).
  void layoutHalf(Simulation& sim, int width);
  PairScatter scatter_;            // blocks and spill buffers of the symmetric loops
  CellWalkScratch walkScratch_;    // neighbour_list: cells: per-cell scratch of the layout
  std::vector<Index> walkBlocks_, walkSpill_;  // ... and its blocks and spill ends
  Index layoutBuild_ = -1, layoutCount_ = -1;  // neighbour search and store size of the layout
  std::vector<double> pairSum_;    // per-particle sums of the symmetric loops (sized once)
  std::vector<unsigned char> receives_;  // force loop: a moving fluid particle of a fluid material

  std::vector<MaterialData> mat_;  // by material id
  // Scratch of the force loop (sized once, no allocation in the time loop): (p - p_ref) / rho^2
  // (Eq. 5.2b) of each fluid particle and, at each boundary particle, the single fluid's density
  // at its pressure (0 with several fluids). V = m / rho is computed per pair (Volumes).
  std::vector<double> pRho2_;
  std::vector<unsigned char> wetFlag_;  // constitutive stage: boundary particle has a fluid neighbour
  Index wetBuild_ = -1, wetCount_ = -1;  // neighbour search and store size of the flags
  std::vector<double> gravity_;
  TimeSchedule gravitySchedule_;  // gravity_schedule (factor 1 without it)
  std::vector<BodyForce> bodyForces_;
  bool summation_ = false;
  PressureForm pressureForm_ = PressureForm::Volume;  // Eq. 5.2a, the default (b84d7bb)
  bool harmonicMean_ = true;
  ContinuityForm continuityForm_ = ContinuityForm::Volume;  // continuity_form (Eq. 5.1a / mass)
  bool acousticInterface_ = false;  // continuity_interface: acoustic (interfaceContinuityWeight)
  std::vector<double> ifaceWeight_;  // its weight per pair of materials (a * n + b), 1 when off
  bool wallMirrorLight_ = false;    // wall_pressure: light_mirror (a lighter fluid's own pressure at walls)
  std::vector<unsigned char> wallMirror_;  // ... per material: 1 for a fluid lighter than the heaviest
  double gamma_ = 0.0;              // surface tension coefficient (N/m)
  bool densityWeightedCsf_ = true;  // CSF weighting 2 rho_a / (rho_a + rho_b)
  bool balancedCsf_ = false;        // surface_tension_form: balanced (surface_tension.hpp)
  bool wallCsf_ = false;            // wall_pressure_surface_tension: a_s in the walls' extrapolation
  bool wallBackground_ = false;     // wall_background_pressure: p_b's force kept next to fixed walls
  bool wallPushOnly_ = false;       // wall_push_only: fluid-wall pairs with max(p - p_ref, 0)
  bool wallOverlap_ = false;        // wall_overlap_pressure: K (S_w - 1/2)+ pushes a fluid particle off the walls
  double curvatureSmoothing_ = 2.0; // balanced form: curvature Shepard radius / h
  std::vector<double> kappaWork_;   // balanced form: smoothed curvature (surface_tension.cpp)
  double normalThreshold_ = 0.05;   // |n| h below which a normal is not used (5.8)
  bool wallWetting_ = true;         // walls' colour cos(theta) enters 5.7 (1.10)
  bool wettingNormal_ = true;       // wetting: normal (prescribed contact-line normal near walls)
  double wettingScale_ = 0.15;      // wall Shepard fraction at which the normal is fully prescribed
  bool wettingGhost_ = false;       // wetting_ghost: walls' ghost colour completes |n| at the contact line
  bool wideWallNormal_ = false;     // wall_normal: wide (fixed walls' normal over 2h, set-up)
  bool wettingCurved_ = false;      // wetting_curvature: the prescribed normal follows the meniscus' curvature above the wall
  double densityDiffusion_ = 0.0;   // delta of the Molteni-Colagrossi term (0: off)
  bool normaliseViscosity_ = true;  // divide 5.4 by the discrete second moment
  double artificialViscosity_ = 0.0;  // alpha of Eq. 2.64 (0: off)
  double xsph_ = 0.0;               // epsilon of XSPH, Eq. 2.66 (0: off)
  double shifting_ = 0.0;           // coefficient A of the particle shifting velocity (0: off)
  bool pressureReference_ = false;  // background: subtract p_b in every pressure force
  bool solidGauge_ = false;         // solid_gauge: p_b subtracted only in the force on solids / plates
  bool transportVelocity_ = false;  // background pressure in the advection (Adami et al. 2013)
  bool floatPairs_ = false;         // pair_precision: float (fluid-fluid block of fluid_half.cpp)
  std::string pairPrecisionWhere_;  // where the scene set it (for the full-list error)
  double backgroundPressure_ = 0.0; // the run's background pressure (smallest of the fluids')
  double densityBound_ = 0.03;
  double cflAcoustic_ = 0.25, cflViscous_ = 0.125, cflForce_ = 0.25, cflSurface_ = 0.25;
  bool hydrostaticInit_ = false;
  double hydrostaticLevel_ = 0.0;   // coordinate (along -g) where p = background pressure
  double maxSoundSpeed_ = 0.0, maxNu_ = 0.0, minRho0_ = 0.0;
  double maxVariation_ = 0.0;
  double lastWarned_ = 0.0;
  long long boundExceeded_ = 0;
  bool viscousFactorsReady_ = false;  // viscous_factor computed once (first evaluation)
  bool viscous_ = true;   // a fluid material has viscosity > 0 (else the term 5.4 is zero)
  bool factors_ = true;   // viscous_factor allocated and used (viscosity_normalisation and viscous_)
  bool movingBoundaries_ = false;   // a non-fluid particle that is not fixed (initialise)
  RealField boundaryAcceleration_;  // Simulation::previousAcceleration, when moving boundaries
  int dim_ = 2;
};

}  // namespace poresph
