#pragma once
// Rigid bodies made of particles (module "rigid", material model "rigid"; thesis Appendix A,
// docs/rigid.md): quartz and calcite inclusions of the clay, and the plates that confine a sample.
//
// Bodies: every connected cluster of particles of one rigid material (lattice neighbours at one
// spacing, as the 6-connected clusters of a voxel image) is one body; int field `body` (-1 for
// other particles), body-frame offsets in `body_offset`. Per-body state (physics/rigid/
// rigid_body.hpp) lives outside the per-particle arrays: mass, centre of mass (A.7), principal
// inertia (A.8), unit quaternion, velocity, angular momentum.
//
// Each rate evaluation, constraints() sums the force and torque that every other module put on
// the body's particles (A.9-A.10, one parallel reduction with per-thread partial sums), adds
// gravity and the plate load, applies the body's constraints and writes the rigid acceleration
// A + alpha x r + omega x (omega x r) into each body particle's acceleration, so that the scene's
// integrator predicts the body particles along the rigid motion during the step. After the step,
// endOfStep() advances the body state (kick-drift-kick with the forces of the step's start and of
// its evaluation: velocity Verlet, A.11-A.14; free rotation by the implicit midpoint rule, which
// conserves angular momentum and energy) and places the particles exactly: x = X + R r_body,
// v = V + omega x R r_body.
//
// Pair classes owned (action = reaction in each):
//   fluid-rigid  moving wall: the fluid sees the body particles through the extrapolated pressure
//                and no-slip velocity (fluid module) and the shared pair terms of
//                libcore/fluid_pair_terms.hpp; +F on the fluid particle, -F on the body particle;
//                the continuity sum of the fluid over its rigid neighbours (Eq. 5.1a).
//   rigid-solid, rigid-rigid (different bodies), rigid-wall: the repulsion of Eq. A.18
//                (libcore/contact_repulsion.hpp) with the bulk modulus of the stiffer side (A.17).
//   rigid-solid of a `bonded` body: the solid particles of the first layer (a body particle
//                within 1.5 dx at the start) are bonded to anchor points fixed in the body frame
//                (A.6 in tension and shear too); the bond replaces the repulsion for that body.
//   rigid-solid of a `bonded: slip` plate: one bond per plate along its normal to the
//                consistent-load-weighted mean of the solid within two supports (PlateBond);
//                it replaces the repulsion between the plate and those particles.
//
// Constraints (material keys): fixed bodies, translation along chosen axes only, no rotation,
// and force-controlled plates (a plate pushed along `direction` by stress x area that moves to
// keep it; its displacement is a timeseries column).
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include "libcore/fluid_pair_terms.hpp"
#include "libcore/module.hpp"
#include "libcore/particle_store.hpp"
#include "physics/rigid/rigid_body.hpp"

namespace poresph {

/// Parameters of one "rigid" material.
struct RigidMaterial {
  int id = -1;
  std::string name;
  double density = 0.0;
  double contactModulus = 0.0;          ///< k of Eq. A.17/A.18 for rigid-rigid and rigid-wall pairs
  bool fixed = false;
  std::array<double, 3> translate{1, 1, 1};  ///< 1: free along the world axis, 0: locked
  bool rotate = true;
  std::array<double, 3> angularVelocity{0, 0, 0};  ///< initial omega (world frame)
  bool plate = false;
  std::array<double, 3> plateDirection{0, 0, 0};  ///< unit vector the load pushes the plate along
  double plateStress = 0.0, plateArea = 0.0;
  double plateRampTime = 0.0;  ///< s: the load is stress x area x min(1, t / ramp_time)
  double damping = 0.0;  ///< viscous damping of the body's velocity and spin (1/s)
  /// Bonded to the elastic solid (normal stress continuity A.6 in tension and shear too): each
  /// solid particle of the first layer around the body is held to its anchor point, fixed in the
  /// body frame, by a zero-length spring (see RigidModule::bondForce).
  bool bonded = false;
  /// Plates only (`bonded: slip`): the plate is tied along its direction to the consistent-load-
  /// weighted mean displacement of the solid within two kernel supports of its face (one bond per
  /// plate, RigidModule::PlateBond): the face slides freely along the plate (frictionless, no
  /// corrugation) and the load enters as the consistent nodal load of a uniform stress (2.76).
  bool bondSlip = false;
  std::string where;  ///< "file:line: materials[k]" for messages
};

/// One body: Newton-Euler state plus what the module needs around it.
struct RigidBody {
  rigid::BodyState state;
  int material = -1;
  Index count = 0;
  rigid::V3 X0 = rigid::V3::Zero();   ///< initial centre of mass
  rigid::V3 force = rigid::V3::Zero(), torque = rigid::V3::Zero();  ///< last evaluation (raw)
  rigid::V3 accStart = rigid::V3::Zero(), alphaTorqueStart = rigid::V3::Zero();
  rigid::V3 acc = rigid::V3::Zero(), alphaTorque = rigid::V3::Zero();  ///< constrained
  bool started = false;
};

/// Bodies found in a store (connected clusters of rigid particles): body index of each particle
/// (-1: none) and the bodies with mass, centre of mass and inertia set. Throws InputError for a
/// body of one particle or with zero inertia about an axis. Used by initialise() and describe().
struct BodyPartition {
  std::vector<std::int32_t> bodyOf;
  std::vector<RigidBody> bodies;
};

class RigidModule : public Module {
 public:
  std::string name() const override { return "rigid"; }
  std::vector<std::string> materialModels() const override { return {"rigid"}; }
  std::vector<PairClass> ownedPairs() const override {
    return {PairClass(kPhaseFluid, kPhaseRigid), PairClass(kPhaseSolid, kPhaseRigid),
            PairClass(kPhaseRigid, kPhaseRigid), PairClass(kPhaseWall, kPhaseRigid)};
  }
  /// Every class with a rigid side (the rigid rows read all their neighbours; fluid and solid
  /// rows their rigid ones).
  PairMask neighbourPairsRead() const override { return pairClassesWith(kPhaseRigid); }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override;
  void initialise(Simulation& sim) override;
  void interfaces(Simulation& sim) override;
  void constraints(Simulation& sim) override;
  void endOfStep(Simulation& sim, double dt) override;
  /// Every body's Newton-Euler state (centre, velocity, quaternion, angular momentum, initial
  /// centre, the forces of the last evaluation) for checkpoints and the health rollback: entry
  /// "bodies", 35 numbers per body. The particles' `body` and `body_offset` are store fields.
  ModuleState saveState() const override;
  void restoreState(const ModuleState& state) override;
  /// fluid_rigid (extrapolated / mirror; mirror was the default until d8fafdf, 2026-11-23 20:04
  /// UTC, hours after the first commit: the former default taken is extrapolated), recorded in
  /// checkpoints (Module::settings). The resolved value: since 2026-11-28 a scene whose fluid
  /// also meets elastic solids takes the coupling's fluid_solid model unless it sets the key.
  ModuleSettings settings() const override {
    return {{"rigid.fluid_rigid", fluidModel_ == BoundaryModel::Extrapolated ? "extrapolated" : "mirror",
             "extrapolated", "until db33ccb (2026-11-28), also where the fluid meets elastic solids"}};
  }
  double timeStepLimit(const Simulation& sim) const override;
  void diagnostics(const Simulation& sim,
                   std::vector<std::pair<std::string, double>>& columns) const override;

  /// Bodies, masses and inertia as `poresph info` prints them (before initialise()).
  std::string describe(const Simulation& sim) const override;

  // ---- for tests and tools ----
  const std::vector<RigidBody>& bodies() const { return bodies_; }
  /// Weighted bond of a `bonded: slip` plate (A.6 along the plate's normal n, A.17 stiffness):
  /// delta = n . u_plate - sum_a c_a n . u_a over the solid particles a within two kernel
  /// supports of the plate, c_a = n . s_a / sum_a n . s_a with s_a the consistent nodal load of a
  /// uniform unit stress (libcore/consistent_load.hpp, Eq. 2.76); energy K delta^2 / 2: force
  /// K delta c_a n on each particle a and -K delta n on the plate (sum c_a = 1: action =
  /// reaction). For a linear displacement field sum c_a n . u_a is the displacement of the
  /// body's surface itself, and the plate's load spread as c_a is the one that holds a uniform
  /// stress in exact discrete equilibrium.
  /// Damage-aware weights: where a tied particle carries damage D_a > 0 (the store's `damage`
  /// field, Eqs. 4.12-4.18), c_a is replaced by c_a (1 - D_a) / sum_b c_b (1 - D_b) in both the
  /// mean and the force (still sum = 1); with no damage among the tied particles the weights are
  /// c_a unchanged, bit for bit (docs/rigid.md "Damage-aware weights").
  struct PlateBond {
    int body = -1;
    rigid::V3 n = rigid::V3::Zero();
    double stiffness = 0.0;  ///< K = 2 k A / dx (the per-particle bonds of the face, summed)
    double loadArea = 0.0;   ///< sum_a n . s_a: the face's discrete area (compare with `area`)
    Index particles = 0;     ///< solid particles tied to the plate
    double delta = 0.0;      ///< of the last evaluation
    bool degraded = false;   ///< some tied particle had D > 0 at the last evaluation
    double sound = 1.0;      ///< sum_a c_a (1 - D_a) at the last evaluation (1 if !degraded)
    double damagedShareFixed = 0.0;  ///< sum_a c_a over tied particles with D_a > 0.5
    double damagedShare = 0.0;       ///< the same share with the damage-aware weights
  };
  const std::vector<PlateBond>& plateBonds() const { return plateBonds_; }
  /// Body particles within one kernel support of their body's surface (App. A.2: only these take
  /// part in the pair sums; the others can meet no particle of another body or phase).
  Index surfaceParticles(const Simulation& sim) const;
  /// Sets a body's velocity and angular velocity (world frame) and re-places its particles.
  void setBodyVelocity(Simulation& sim, size_t body, const rigid::V3& V, const rigid::V3& omega);
  /// Force of its bond on solid particle i (zero if not bonded), at the last evaluation's body
  /// placement: the interface traction of A.6 carried by that particle.
  rigid::V3 bondForceOn(const Simulation& sim, Index i) const;
  /// Body partition of the current store (connected clusters); throws for bad bodies.
  BodyPartition partition(const Simulation& sim) const;

 private:
  template <int D> void interfacesD(Simulation& sim);
  template <int D> void constraintsD(Simulation& sim);
  template <int D> void placeD(Simulation& sim, int onlyBody);
  void initialiseBonds(Simulation& sim);
  template <int D> void initialisePlateBonds(Simulation& sim);
  /// delta of every plate bond at the current positions (interfaces(), after bodyPlacement()).
  template <int D> void plateBondDeltas(const Simulation& sim);
  /// Damage-aware weight c~_a of a tied particle with stored weight c_a and damage D_a, from the
  /// plate's sum_b c_b (1 - D_b) of the same evaluation (plateBondDeltas; c_a if no damage).
  /// Sound fraction 1 - D_a of a tied particle's consistent-load share (D clamped to [0, 1]).
  static double plateSoundFactor(double Da) { return 1.0 - std::clamp(Da, 0.0, 1.0); }
  static double plateWeightOf(const PlateBond& P, double c, double Da) {
    if (!P.degraded) return c;
    return c * plateSoundFactor(Da) / P.sound;
  }
  void findSurface(Simulation& sim);
  /// Force of its bond on solid particle i (zero-length spring to its anchor point, which moves
  /// with the body: f = -K (x_i - X - R r_anchor), minimal image across periodic faces); the body
  /// receives -f at the anchor point (parallel to the spring: no net couple). Also returns the
  /// spring vector d = x_i - anchor. Called by interfaces() (solid side) and constraints()
  /// (body side), so both sides use one expression.
  template <int D>
  Vec<D> bondForce(const Simulation& sim, Index i, const double* x, const std::int32_t* mt,
                   Vec<D>& d) const;
  const RigidMaterial* materialOf(int id) const;
  double time_ = 0.0;  ///< sim.time of the evaluation (plate load ramps)
  void constrain(RigidBody& b, const rigid::V3& force, const rigid::V3& torque, rigid::V3& acc,
                 rigid::V3& torqueOut) const;

  int dim_ = 3;
  std::vector<RigidMaterial> mats_;
  std::vector<int> slot_;  // material id -> index in mats_ (-1: not rigid)
  std::array<double, 3> gravity_{0, 0, 0};
  BoundaryModel fluidModel_ = BoundaryModel::Mirror;
  /// `rigid: {fluid_rigid}` given in the scene; otherwise, where the fluid also meets elastic
  /// solids, initialise() takes the coupling's fluid_solid model (one model per fluid particle).
  bool fluidModelSet_ = false;
  IntField body_;
  RealField offset_;
  IntField surface_;  // body particles within one kernel support of the body's surface (A.2)
  bool bonds_ = false;           // some rigid material is bonded: fields below allocated
  IntField bondBody_;            // solid particles: bonded body (-1: none)
  RealField bondAnchor_;         // solid particles: anchor in the body frame
  std::vector<rigid::M3> rot_;   // per-body rotation of the current evaluation (bonds)
  std::vector<rigid::V3> place_; // per-body centre of the current evaluation (bonds)
  std::vector<double> bondPartial_;  // per-thread sums of bodyPlacement() (12 per body)
  /// Centre and rotation of every body at its particles' current (predicted) positions: centre of
  /// mass and the rotation of the polar decomposition of sum m (x - X) r_body^T (exact for a
  /// rigid placement). The bonds' anchors move with them.
  template <int D> void bodyPlacement(const Simulation& sim);
  double maxBondModulus_ = 0.0;  // largest bond modulus (time step)
  // `bonded: slip` plates: per solid particle up to 2 D plate-bond slots (index into
  // plateBonds_, -1: none) with their weight c_a, and the particle's initial position.
  std::vector<PlateBond> plateBonds_;
  int plateSlots_ = 0;
  std::vector<double> platePartial_;  // per-thread partial sums of plateBondDeltas (3 per plate)
  IntField plateBond_;
  RealField plateWeight_, plateOrigin_;
  RealField pressure_, wallVelocity_, viscousFactor_, densityRate_;
  bool fluidPairs_ = false;
  std::vector<double> solidModulus_;  // by material id: rho0 c^2 of solid materials (A.17)
  double maxContactModulus_ = 0.0, minRigidDensity_ = 0.0;
  std::vector<RigidBody> bodies_;
  std::vector<double> partial_;  // per-thread partial sums of the reduction (9 per body)
  std::vector<rigid::V3> shift_, alpha_, omega_;  // per-body scratch of constraints()
  int threads_ = 1;
};

}  // namespace poresph
