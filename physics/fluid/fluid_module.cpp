#include "physics/fluid/fluid_module.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>

#include "libcore/artificial_viscosity.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/periodic_images.hpp"
#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "physics/fluid/fluid_pair.hpp"
#include "physics/fluid/surface_tension.hpp"

namespace poresph {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

// ---------------------------------------------------------------------------------------------
// configuration

void FluidModule::configure(Simulation& sim, const std::vector<const Material*>& materials,
                            const ParameterSet* section) {
  dim_ = sim.dimension();
  const int d = dim_;
  int maxId = 0;
  for (const auto& m : sim.materials) maxId = std::max(maxId, m.id);
  for (const Material* m : materials) maxId = std::max(maxId, m->id);
  mat_.assign(static_cast<size_t>(maxId + 1), MaterialData{});
  maxSoundSpeed_ = 0.0;
  maxNu_ = 0.0;
  minRho0_ = std::numeric_limits<double>::infinity();
  for (const Material* m : materials) {
    MaterialData& md = mat_[static_cast<size_t>(m->id)];
    md.owned = true;
    const ParameterSet& p = m->parameters;
    if (m->model == "fluid") {
      md.fluid = true;
      md.rho0 = p.real("density", Range::positive());
      md.soundSpeed = p.real("sound_speed", Range::positive());
      md.viscosity = p.real("viscosity", Range::nonNegative());
      md.eos = p.choice("eos", "linear", {"linear", "tait"}) == "tait" ? Eos::Tait : Eos::Linear;
      md.taitGamma = p.real("tait_gamma", 7.0, Range{1.0, 20.0, false, false});
      md.backgroundPressure = p.real("background_pressure", 0.0, Range::any());
      md.colour = p.real("colour", 1.0, Range::closed(-1.0, 1.0));
      maxSoundSpeed_ = std::max(maxSoundSpeed_, md.soundSpeed);
      sim.materials[static_cast<size_t>(m->id)].phase = kPhaseFluid;
      sim.materials[static_cast<size_t>(m->id)].fluid = md;  // the libcore part, for coupling
      maxNu_ = std::max(maxNu_, md.viscosity / md.rho0);
      minRho0_ = std::min(minRho0_, md.rho0);
    } else if (m->model == "wall") {
      md.fluid = false;
      md.rho0 = p.real("density", Range::positive());
      const double theta = p.real("contact_angle", 90.0, Range::closed(0.0, 180.0));
      md.colour = std::cos(theta * kPi / 180.0);  // Eq. 1.10
      sim.materials[static_cast<size_t>(m->id)].phase = kPhaseWall;
      sim.materials[static_cast<size_t>(m->id)].wettingCos = md.colour;
      // empty: none given (a prescribed wall then keeps its region's velocity, initialise)
      md.wallVelocity = p.has("velocity") ? p.reals("velocity", static_cast<size_t>(d)) : std::vector<double>{};
    } else {
      p.fail("model", "is not a model of the fluid module (fluid, wall)");
    }
    p.finish();
  }

  gravity_.assign(static_cast<size_t>(d), 0.0);
  gravitySchedule_ = TimeSchedule{};
  bodyForces_.clear();
  // A scene without a `fluid:` section never reaches the keys below; it must get the same
  // default pressure gradient, Eq. 5.2a (the member initialiser in fluid_module.hpp is
  // overwritten here).
  pressureForm_ = PressureForm::Volume;
  if (section) {
    const ParameterSet& s = *section;
    if (s.has("gravity")) gravity_ = s.reals("gravity", static_cast<size_t>(d));
    // Ramped gravity (docs/fluid.md "Ramped gravity"): g(t) = gravity x factor(t), the factor a
    // table (libcore/time_schedule.hpp) evaluated at each evaluation's sim.time.
    gravitySchedule_ = s.has("gravity_schedule") ? TimeSchedule::read(s.section("gravity_schedule"))
                                                 : TimeSchedule{};
    if (!gravitySchedule_.constant() && !s.has("gravity"))
      s.fail("gravity_schedule", "scales `gravity`, which the section does not set");
    if (s.has("body_forces")) {
      for (const ParameterSet& b : s.sectionList("body_forces")) {
        BodyForce f;
        f.acceleration = b.reals("acceleration", static_cast<size_t>(d));
        f.lo = b.has("region_min") ? b.reals("region_min", static_cast<size_t>(d))
                                   : std::vector<double>(static_cast<size_t>(d), -1e300);
        f.hi = b.has("region_max") ? b.reals("region_max", static_cast<size_t>(d))
                                   : std::vector<double>(static_cast<size_t>(d), 1e300);
        for (int a = 0; a < d; ++a)
          if (!(f.lo[static_cast<size_t>(a)] < f.hi[static_cast<size_t>(a)]))
            b.fail("region_max", "must be larger than region_min along every axis");
        b.finish();
        bodyForces_.push_back(f);
      }
    }
    summation_ = s.choice("density", "continuity", {"continuity", "summation"}) == "summation";
    // Pressure gradient of the fluid-fluid pairs (fluid_pair.hpp FluidPressureForm): Eq. 5.2a
    // (volume, the default: the energy-consistent partner of the default continuity Eq. 5.1a and
    // balanced at rest between unequal densities), Eq. 5.2b (symmetric, the default before
    // 2026-11-27) or Hu-Adams (docs/fluid.md "Eq. 5.2a").
    {
      const std::string form =
          s.choice("pressure_gradient", "volume", {"symmetric", "hu_adams", "volume"});
      pressureForm_ = form == "hu_adams" ? PressureForm::HuAdams
                      : form == "volume" ? PressureForm::Volume
                                         : PressureForm::Symmetric;
    }
    // Eq. 5.2b between fluids of different rest densities (issue 16, docs/drainage.md "A lighter
    // gas in the throat"): its term m_b p_a / rho_a^2 of a light particle a summed over heavy
    // neighbours b is rho_heavy / rho_light times what light neighbours give, so at an interface
    // the light phase is pushed off by its own (background) pressure within a few steps. The
    // volume-weighted forms (Hu-Adams; the thesis' Eq. 5.2a) cancel at rest.
    if (pressureForm_ == PressureForm::Symmetric) {
      double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
      for (const MaterialData& md : mat_)
        if (md.fluid) lo = std::min(lo, md.rho0), hi = std::max(hi, md.rho0);
      if (hi > 2.0 * lo)
        std::fprintf(stderr,
                     "warning: %s: pressure_gradient symmetric (Eq. 5.2b) between fluids of "
                     "densities %g and %g kg/m^3: a particle of the lighter fluid at their "
                     "interface gets %gx its own-pressure term from its heavier neighbours and is "
                     "thrown off within a few steps; use pressure_gradient: volume (Eq. 5.2a) "
                     "or hu_adams (docs/drainage.md \"A lighter gas in the throat\")\n",
                     s.where("pressure_gradient").c_str(), lo, hi, hi / lo);
    }
    // Continuity pair term (libcore continuityTerm): Eq. 5.1a or the mass form, the
    // energy-consistent partner of 5.2b (docs/fluid.md "Energy-consistent continuity").
    continuityForm_ = s.choice("continuity_form", "volume", {"volume", "mass"}) == "mass"
                          ? ContinuityForm::Mass
                          : ContinuityForm::Volume;
    // The neighbour velocity in the continuity term of a pair of two different fluids (issue 16,
    // docs/drainage.md "The inlet meniscus at density ratio 1000"): `mean` takes v_b (Eq. 5.1a
    // as written); `acoustic` the interface velocity of the linearised (acoustic) Riemann problem
    // between the two, v* = (Z_a v_a + Z_b v_b)/(Z_a + Z_b), Z = rho0 c0 (fluid_pair.hpp
    // interfaceContinuityWeight). Equal impedances give Eq. 5.1a exactly.
    acousticInterface_ =
        s.choice("continuity_interface", "mean", {"mean", "acoustic"}) == "acoustic";
    // The pressure a fluid particle sees at a wall particle (issue 14, docs/fluid.md "Gas bubble
    // trapped in a dead-end pore"): `extrapolated` (Adami et al. 2012) is the Shepard mean of the
    // wall's fluid neighbours of every fluid; `light_mirror` gives a fluid lighter than the
    // heaviest fluid of the scene its own pressure and density at the wall (the mirror model),
    // so that at a contact line the heavy fluid's pressure in the wall's mean does not pull the
    // light one into the wall. The heaviest fluid keeps the extrapolation.
    wallMirrorLight_ =
        s.choice("wall_pressure", "extrapolated", {"extrapolated", "light_mirror"}) == "light_mirror";
    harmonicMean_ =
        s.choice("viscosity_mean", "harmonic", {"harmonic", "arithmetic"}) == "harmonic";
    gamma_ = s.real("surface_tension", 0.0, Range::nonNegative());
    sim.published.surfaceTension = gamma_;  // for the drainage numbers (Eqs. 5.11-5.12)
    densityWeightedCsf_ =
        s.choice("surface_tension_weighting", "density", {"density", "none"}) == "density";
    balancedCsf_ = s.choice("surface_tension_form", "csf", {"csf", "balanced"}) == "balanced";
    // The walls' extrapolated pressure (Adami et al. 2012) balances the fluid's body force g;
    // true also the CSF acceleration a_s (Eq. 1.9), which is a volume force on the fluid too (at a
    // contact line its wall-normal part would push fluid into the wall). Default false: measured
    // ~1 m/s^2 on the main job's crossing gas (not their cause), and with it the 2D capillary
    // entry at 1.1 f* advances 0.139 w over its second half (asserted > 0.15; 0.187 without).
    // Issue 14 H5, docs/fluid.md "Fluid at the walls under a negative gauge pressure". Only with
    // the CSF form (the balanced form is applied after the extrapolation).
    wallCsf_ = s.boolean("wall_pressure_surface_tension", false);
    curvatureSmoothing_ = s.real("curvature_smoothing", 2.0, Range::closed(0.0, 3.0));
    normalThreshold_ = s.real("normal_threshold", 0.05, Range::closed(0.0, 1.0));
    wallWetting_ = s.boolean("wall_wetting", true);
    wettingNormal_ = s.choice("wetting", "normal", {"normal", "colour"}) == "normal";
    wettingScale_ = s.real("wetting_scale", 0.15, Range{0.0, 1.0, true, false});
    wettingGhost_ = s.boolean("wetting_ghost", false);
    // Wall normal n_w of the wetting model near fixed walls: `local` (default) the gradient of the
    // wall indicator over the particle's own support, `wide` from a field computed once at set-up
    // with a kernel of twice the smoothing length (voxel-staircase walls, issue 14).
    wideWallNormal_ = s.choice("wall_normal", "local", {"local", "wide"}) == "wide";
    // Contact-line normal at the height of the interface above the wall (issue 14, the 120-degree
    // bias): true = the prescribed normal is that of the circular meniscus meeting the wall at
    // theta (cos theta(s) = cos theta + s kappa / (D - 1)), false = theta at every height.
    wettingCurved_ = s.boolean("wetting_curvature", false);
    densityDiffusion_ = s.real("density_diffusion", 0.0, Range::closed(0.0, 1.0));
    normaliseViscosity_ = s.boolean("viscosity_normalisation", true);
    artificialViscosity_ = s.real("artificial_viscosity", 0.0, Range::closed(0.0, 10.0));
    xsph_ = s.real("xsph", 0.0, Range::closed(0.0, 1.0));
    shifting_ = s.real("shifting", 0.0, Range::closed(0.0, 10.0));
    // pressure_reference: none (absolute pressure in every force), background (p - p_b in every
    // pressure force: fluid-fluid, fluid-wall and both sides of the fluid-solid / fluid-rigid
    // pairs), or solid_gauge (issue 16): the fluid's side of every pair keeps the absolute
    // pressure, as with none, so that the walls' extrapolated pressure (Adami et al. 2012) stays
    // positive in the force and pushes; the elastic solid and the rigid plates receive the
    // force with p - p_b, as with background, so the clay is not loaded by p_b. The pair forces
    // of a fluid-solid pair then differ by the p_b term m_a m_b p_b (1/rho_a^2 + 1/rho_b^2)
    // grad W (Eq. 5.2b's form at the boundary), whose sum over a complete support is ~0
    // (docs/fluid.md "The solid-only gauge"). Not the drainage setting: without the tensile
    // instability of the gauge forces the fluid's mean pressure stays at p_b, so the outlet side
    // of a periodic drainage sits at -dP/2 (not ~0) and sucks on the clay (main job: damaged
    // 8.3 % against 0.40 %); the drainage scenes use wall_push_only (below) instead.
    {
      const std::string ref = s.choice("pressure_reference", "none", {"none", "background", "solid_gauge"});
      pressureReference_ = ref == "background";
      solidGauge_ = ref == "solid_gauge";
    }
    // With pressure_reference: background the pressure forces use p - p_b, which is negative
    // where the flow lowers the pressure (the drainage's outlet side); the walls' extrapolated
    // pressure (Adami et al. 2012) then pulls a fluid particle into the wall instead of pushing
    // it out (a wall is impermeable only with a positive pressure in the force: issue 14 H5,
    // measured at the main job's outlet). true: a fluid particle with a fixed-wall neighbour
    // keeps the background pressure's force
    //   a_b = -(p_b / m_a) sum_b (V_a^2 + V_b^2) grad W_ab   (over all its neighbours; Adami et
    // al. 2013's form), ~0 on a regular lattice whose support the wall completes and restoring
    // towards it: the positive pressure the wall needs, on the fluid side only (walls are fixed;
    // solids and plates still see p - p_b). Default false: on the reproducer it removes the
    // crossings but the largest density variation grows to 5.9 % at 9.5 ms (1.4 % without) in the
    // outlet reservoir's gas at the wall-clay corner, and the damaged fraction doubles
    // (docs/fluid.md "Fluid at the walls under a negative gauge pressure").
    wallBackground_ = s.boolean("wall_background_pressure", false);
    // wall_push_only (issue 16, the drainage scenes' setting): the fluid-wall pairs (fixed
    // `model: wall` particles) take the positive parts of the force pressures,
    //   -m_w [max(p_a - p_ref, 0) / rho_a^2 + max(p_w - p_ref, 0) / rho_w^2] grad W_aw
    // (Eq. 5.2b's pair with Adami et al. 2012's extrapolated p_w; Hu-Adams likewise), so a fixed
    // wall pushes a fluid particle with a positive gauge pressure and never pulls one with a
    // negative gauge (the tensile instability at the wall that let the outlet reservoir's fluid
    // through the walls, docs/fluid.md "Fluid at the walls under a negative gauge pressure").
    // The fluid-fluid pairs keep p - p_ref (their pressure level is the one of `background`),
    // and the solid and the plates are not touched (their suction is physical). A wall cannot
    // hold the fluid in tension then: the hydrostatic balance at a wall is exact where
    // p >= p_ref only. Full neighbour list (the gather loop).
    wallPushOnly_ = s.boolean("wall_push_only", false);
    // wall_overlap_pressure (issue 16; a short-range repulsion, named as such: it does not remove
    // the cause below, it stops its effect at the face). The fixed walls' kernel sum at a fluid
    // particle a, S_w = sum_w V_w W_aw (with the rigid bodies' share, so that a face where a
    // wall meets a plate counts as one face), is 1/2 at the face of a wall at least a support thick
    // (the half-space of a normalised kernel; quintic h = dx on the lattice: 0.500 at the face,
    // 0.215 at the first fluid layer, +0.62 per dx beyond the face, the same on a wall
    // particle's row as between two), whatever the lattice under the face. With the key a
    // particle past that level gets the pressure its summation density would give the overlap,
    //   a_a += -(K / rho_a) (S_w - 1/2)+ grad_a S_w,    K = rho0 c0^2 (the fluid's bulk modulus),
    // the gradient of the energy sum_a V_a K (S_w,a - 1/2)+^2 / 2 (a fixed wall needs no
    // reaction; the clay and the plates keep their own pairs). Walls and rigid bodies, not the
    // clay (S_b over every boundary, the first form): in imaged rock a fluid particle in a
    // one-voxel pore along a wall has S_b above 1/2 on the lattice at rest (the clay on its other
    // sides), and the thesis-size scene's such particle was thrown off the wall at the first step
    // (density check at step 9). Walls alone leave the main job's y = 0 face at z 0.6-0.7 mm
    // (wall below the plate's edge) reached late: water 0.21 dx past it at 11.8 ms. Zero for
    // every particle on the fluid side of a flat face. Why it is
    // needed: the Adami wall pushes a fluid particle through the pressure of its continuity
    // density only; in the main job a reservoir gas particle at the wall-clay corner overlapped
    // the wall by S_w 0.36 -> 0.97 while its density stayed 1000-1006 kg/m^3, because its
    // continuity lost as much leaving the clay, whose mirror model counts the clay twice, as it
    // gained entering the wall (docs/fluid.md "Fluid creeping through the walls at a positive
    // gauge pressure"). It also acts in concave corners of the walls, where S_w passes 1/2 inside
    // the fluid (two faces: a particle within ~0.3 dx of both), and rounds them off. Full
    // neighbour list (the gather loop).
    wallOverlap_ = s.boolean("wall_overlap_pressure", false);
    transportVelocity_ = s.boolean("transport_velocity", false);
    densityBound_ = s.real("density_variation_bound", 0.03, Range{0.0, 1.0, true, false});
    cflAcoustic_ = s.real("cfl_acoustic", 0.25, Range{0.0, 1.0, true, false});
    cflViscous_ = s.real("cfl_viscous", 0.125, Range{0.0, 1.0, true, false});
    cflForce_ = s.real("cfl_force", 0.25, Range{0.0, 1.0, true, false});
    cflSurface_ = s.real("cfl_surface_tension", 0.25, Range{0.0, 1.0, true, false});
    if (s.has("hydrostatic_level")) {
      hydrostaticInit_ = true;
      hydrostaticLevel_ = s.real("hydrostatic_level");
    }
    // Arithmetic of the fluid-fluid pairs of the symmetric loop (fluid_half.cpp): double, or
    // float (positions and velocities relative to the row's particle, sums in double;
    // docs/fluid.md "Pair precision").
    floatPairs_ = s.choice("pair_precision", "double", {"double", "float"}) == "float";
    if (floatPairs_) {
      if (gamma_ > 0.0)
        s.fail("pair_precision", "float needs the half neighbour list, which surface tension "
                                 "(surface_tension > 0) does not support; use double");
      if (xsph_ > 0.0 || shifting_ > 0.0 || transportVelocity_)
        s.fail("pair_precision", "float is not available with xsph, shifting or "
                                 "transport_velocity (their pairs take the double loop); use double");
      pairPrecisionWhere_ = s.where("pair_precision");
    }
    s.finish();
  }
  publishGravity(sim);

  // One background pressure per run (issue 14): the smallest of the fluids' (all equal in the
  // shipped scenes). With `pressure_reference: background` it is subtracted in the pressure
  // force (a uniform pressure then exerts no force on any arrangement); with
  // `transport_velocity` it drives the particle regularisation instead (Adami et al. 2013).
  backgroundPressure_ = 0.0;
  {
    bool first = true;
    for (const Material* m : materials) {
      const MaterialData& md = mat_[static_cast<size_t>(m->id)];
      if (!md.fluid) continue;
      backgroundPressure_ = first ? md.backgroundPressure : std::min(backgroundPressure_, md.backgroundPressure);
      first = false;
    }
  }
  if (transportVelocity_ && !(backgroundPressure_ > 0.0) && section)
    section->fail("transport_velocity",
                  "needs a positive background_pressure of the fluid materials (it drives the "
                  "transport velocity)");
  // Continuity weight of each pair of materials (continuity_interface above): 1 unless acoustic
  // and two different fluids.
  {
    const size_t nmat = mat_.size();
    ifaceWeight_.assign(nmat * nmat, 1.0);
    if (acousticInterface_)
      for (size_t a = 0; a < nmat; ++a)
        for (size_t b = a + 1; b < nmat; ++b)
          if (mat_[a].fluid && mat_[b].fluid) {
            const double w = interfaceContinuityWeight(mat_[a].rho0 * mat_[a].soundSpeed,
                                                       mat_[b].rho0 * mat_[b].soundSpeed);
            ifaceWeight_[a * nmat + b] = w;
            ifaceWeight_[b * nmat + a] = 2.0 - w;  // exactly what the symmetric loop gives b
          }
  }
  // wall_pressure: light_mirror (above): which fluids take their own pressure at the walls.
  {
    double heaviest = 0.0;
    for (const MaterialData& m : mat_)
      if (m.fluid) heaviest = std::max(heaviest, m.rho0);
    wallMirror_.assign(mat_.size(), 0);
    if (wallMirrorLight_)
      for (size_t a = 0; a < mat_.size(); ++a) wallMirror_[a] = mat_[a].fluid && mat_[a].rho0 < heaviest;
  }
  // The fluid side's pressure offset (fluid-wall pairs here, the fluid's side of the coupling's
  // and the rigid module's pairs) and the boundary side's (what the solid / plate receives).
  sim.fluidPairSettings = FluidPairSettings{pressureForm_ == PressureForm::HuAdams, harmonicMean_,
                                            artificialViscosity_, sim.kernel.h(),
                                            pressureReference_ ? backgroundPressure_ : 0.0,
                                            continuityForm_,
                                            pressureReference_ || solidGauge_ ? backgroundPressure_ : 0.0};

  // fields (produce = register-if-absent)
  auto& st = sim.store;
  // Single precision in the rollback copy (libcore/health.hpp): a restart re-evaluates it.
  pressure = st.addReal("pressure", 1, kFieldDefault | kFieldRollbackSingle, "fluid");
  densityRate = st.addReal("density_rate", 1, kFieldNone, "fluid");
  // Inviscid fluids (every fluid material at viscosity 0, e.g. artificial viscosity only, as
  // DualSPHysics' case A; issue 17, memory): the viscous term 5.4 is zero in every pair, so
  // neither its lattice normalisation factors nor the boundary's no-slip velocity (read by the
  // viscous term only; the artificial viscosity 2.64 takes the boundary's own velocity) are
  // needed: viscous_factor, viscous_factor_next and wall_velocity are not allocated (40 B per
  // particle in 3D) and the symmetric loops' sums narrow. wall_velocity is kept when the scene
  // has materials of other modules (the coupling and rigid modules read it through the store).
  viscous_ = maxNu_ > 0.0;
  bool otherModules = false;
  for (const Material& m : sim.materials)
    otherModules = otherModules || (m.model != "fluid" && m.model != "wall");
  wallVelocity = viscous_ || otherModules
                     ? st.addReal("wall_velocity", d, kFieldToGhosts, "fluid")
                     : RealField{};
  // Per-particle factor of the viscous lattice normalisation (forces stage), read by the pair
  // terms of both particles of a pair (also by the coupling module, through the store).
  factors_ = normaliseViscosity_ && viscous_;
  viscousFactor = factors_
                      ? st.addReal("viscous_factor", 1, kFieldToGhosts | kFieldCheckpoint, "fluid")
                      : RealField{};
  viscousFactorNext = factors_
                          ? st.addReal("viscous_factor_next", 1, kFieldNone, "fluid")
                          : RealField{};
  viscousFactorsReady_ = false;
  // Colour (5.6), normal (5.7), curvature (5.8) and the interface flag are needed only by the
  // CSF surface tension (1.9) and the wetting colour of walls (1.10), which acts only through
  // it: a scene without surface tension does not allocate them and skips those stages.
  colour = RealField{};
  colourGradient = RealField{};
  curvature = RealField{};
  interface = IntField{};
  if (surfaceTensionActive()) {
    colour = st.addReal("colour", 1, kFieldDefault, "fluid");
    colourGradient = st.addReal("colour_gradient", d, kFieldOutput | kFieldToGhosts, "fluid");
    curvature = st.addReal("curvature", 1, kFieldOutput | kFieldToGhosts, "fluid");
    interface = st.addInt("interface", 1, kFieldOutput, "fluid");
  }
  surfaceAcceleration = RealField{};
  if (gamma_ > 0.0 && !balancedCsf_)
    surfaceAcceleration =
        st.addReal("surface_acceleration", d, kFieldOutput | kFieldToGhosts, "fluid");
  wallNormal = RealField{};
  if (surfaceTensionActive() && wallWetting_ && wettingNormal_ && wideWallNormal_)
    wallNormal = st.addReal("wall_normal", d, kFieldDefault, "fluid");
  // Every particle (the solid's small-strain form integrates the same density field for all of
  // its particles): fixed fluid and wall particles get a zero rate, so nothing changes there.
  if (!summation_) sim.addIntegrated(st.density(), densityRate, false);
  positionCorrection = RealField{};
  if (xsph_ > 0.0 || shifting_ > 0.0 || transportVelocity_) {
    // XSPH (Eq. 2.66) and particle shifting move a particle with v + dv: the correction dv is a
    // second rate of the positions, advanced by the integrator like any field (one field for
    // both: the integrators take one rate per field).
    positionCorrection = sim.positionCorrection();  // shared with the other modules
  }
}

void FluidModule::initialise(Simulation& sim) {
  auto& st = sim.store;
  const int d = dim_;
  const Index n = st.realCount();
  double* rho = st.data(st.density());
  double* m = st.data(st.mass());
  double* v = st.data(st.velocity());
  double* col = colour.valid() ? st.data(colour) : nullptr;
  double* p = st.data(pressure);
  std::int32_t* ph = st.data(st.phase());
  std::int32_t* mo = st.data(sim.motion);
  const std::int32_t* mt = st.data(st.material());
  double cellVolume = 1.0;
  for (int a = 0; a < d; ++a) cellVolume *= sim.spacing;
  // The hydrostatic initial state is in equilibrium with the gravity of the start time
  // (gravity_schedule's factor at sim.time, normally t = 0; none when that factor is 0).
  const std::array<double, 3> gStart = gravityAt(sim.time);
  double gNorm = 0.0;
  for (double g : gStart) gNorm += g * g;
  gNorm = std::sqrt(gNorm);
  for (Index i = 0; i < n; ++i) {
    const int id = mt[i];
    if (id < 0 || id >= static_cast<int>(mat_.size())) continue;
    const MaterialData& md = mat_[static_cast<size_t>(id)];
    if (!md.owned) {
      // Another module's boundary (solid, rigid): its wetting colour cos(theta) (Eq. 1.10).
      if (col) col[i] = sim.materials[static_cast<size_t>(id)].wettingCos;
      continue;
    }
    if (md.fluid) {
      ph[i] = kPhaseFluid;
      if (rho[i] <= 0.0 || hydrostaticInit_) rho[i] = md.rho0;
      if (m[i] <= 0.0) m[i] = md.rho0 * cellVolume;
      if (col) col[i] = md.colour;
      p[i] = pressureOf(md, rho[i]);
    } else {
      ph[i] = kPhaseWall;
      // A wall stays where it is; its material's `velocity` then enters the no-slip mirror and
      // the continuity only (an infinite plate sliding along itself). With the region's `motion:
      // prescribed` it moves with that velocity (the material's, else the region's): a
      // translating plate (issue 14, docs/fluid.md "Contact angle on a moving wall"); constant
      // velocity, so its acceleration a_w in the wall pressure (Adami et al. 2012) is 0.
      if (mo[i] != kMotionPrescribed) mo[i] = kMotionFixed;
      if (rho[i] <= 0.0) rho[i] = md.rho0;
      if (m[i] <= 0.0) m[i] = md.rho0 * cellVolume;
      if (col) col[i] = md.colour;
      if (!md.wallVelocity.empty())
        for (int a = 0; a < d; ++a) v[i * d + a] = md.wallVelocity[static_cast<size_t>(a)];
      else if (mo[i] != kMotionPrescribed)
        for (int a = 0; a < d; ++a) v[i * d + a] = 0.0;
    }
  }
  checkSoundSpeeds(sim);
  if (hydrostaticInit_ && gNorm > 0.0) initialiseHydrostatic(sim);
  // Moving boundaries (solids, prescribed walls) need their acceleration in the wall pressure.
  movingBoundaries_ = false;
  for (Index i = 0; i < n && !movingBoundaries_; ++i)
    movingBoundaries_ = ph[i] != kPhaseFluid && mo[i] != kMotionFixed;
  if (movingBoundaries_) boundaryAcceleration_ = sim.previousAcceleration();
  // Boundary particles of other modules: a volume is needed in the fluid sums.
  for (Index i = 0; i < n; ++i)
    if (ph[i] != kPhaseFluid && (rho[i] <= 0.0 || m[i] <= 0.0))
      throw InputError("fluid: boundary particle " + std::to_string(i) +
                       " has no positive density and mass (needed by the extended summation)");
  if (wallNormal.valid())
    dispatchDimension(dim_, [&](auto dc) { this->template computeWallNormalsD<decltype(dc)::value>(sim); });
}

// Wall normal of the fixed walls for the wetting model (option `wall_normal: wide`; issue 14,
// "Wetting on real walls"). On a voxel staircase the gradient of the wall indicator over one
// support (3h for the quintic kernel) turns at every step: on a wall tilted by 15 degrees (steps
// 3.7 dx long) it deviates from the plane's normal by up to 20 degrees (rms 12-14, measured
// over the fluid particles within 2 dx of the wall), and the prescribed contact-line normal
// m_theta = n_w cos(theta) + t_w sin(theta) turns with it. Here each fixed wall particle w gets
//   g_w = sum_b phi_b V_b grad W_2h(x_w - x_b),   phi_b = +1 fluid, -1 boundary,
// the gradient of (fluid indicator - boundary indicator) with the same kernel at twice the
// smoothing length (support 6h), pointing from the walls into the fluid; computed once from the
// set-up and carried by the wall particles (walls are fixed or translate with a constant
// prescribed velocity, and a translating wall's normal does not change). The fluid particle's
// wall normal is then the kernel mean sum_w V_w W_aw g_w (kinematicsD), which deviates by
// rms 2-3 degrees, at most 4-5, on the 15 and 30 degree staircases. Set-up search over the real
// particles and their periodic images within the wide support (the run's neighbour list and
// ghost halo reach one support only). Other modules' boundaries (solid, rigid) move and keep
// the local gradient.
template <int D>
void FluidModule::computeWallNormalsD(Simulation& sim) {
  auto& st = sim.store;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const std::int32_t* ph = st.data(st.phase());
  double* wn = st.data(wallNormal);
  const Kernel Kw(sim.kernel.type(), D, 2.0 * sim.kernel.h());
  const double R = Kw.support();
  // Real particles and their periodic images within R (libcore/periodic_images.hpp): the run's
  // halo reaches one support only. A period shorter than 2R would pair a particle with its own
  // image.
  for (int a = 0; a < D; ++a)
    if (sim.domain.periodic[static_cast<size_t>(a)] && sim.domain.length(a) < 2.0 * R)
      throw InputError("fluid: wall_normal: wide needs periodic lengths of at least " +
                       std::to_string(2.0 * R) + " m (two supports of the kernel at 2h); axis " +
                       std::to_string(a) + " is " + std::to_string(sim.domain.length(a)) + " m");
  std::vector<double> X(x, x + static_cast<size_t>(n) * D);
  std::vector<Index> origin;
  appendPeriodicImages<D>(sim.domain, R, X, origin);
  NeighbourSearch search;
  NeighbourList near;
  search.build(X.data(), D, n, static_cast<Index>(origin.size()), R, near);
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    Vec<D> g = Vec<D>::Zero();
    if (ph[i] == kPhaseWall)
      for (auto p = near.offset[static_cast<size_t>(i)]; p < near.offset[static_cast<size_t>(i) + 1]; ++p) {
        const Index k = near.index[static_cast<size_t>(p)];
        const Index j = origin[static_cast<size_t>(k)];
        Vec<D> r;
        for (int a = 0; a < D; ++a) r[a] = X[static_cast<size_t>(i * D + a)] - X[static_cast<size_t>(k * D + a)];
        const double phi = ph[j] == kPhaseFluid ? 1.0 : -1.0;
        g += (phi * m[j] / rho[j] * Kw.F(r.norm())) * r;  // grad_w W points from w towards j
      }
    for (int a = 0; a < D; ++a) wn[i * D + a] = g[a];
  }
  st.refreshGhosts(wallNormal);
}

// The weakly compressible model (Eq. 1.4) needs the sound speed well above the flow speed
// (Mach < 0.1 keeps |rho - rho0| / rho0 ~ Ma^2 < 1 %). The flow speed a scene implies: its
// initial velocities, the free-fall speed sqrt(2 g H) over the height H of its fluid, and
// sqrt(2 f L) for a body force f acting over the domain length L. A sound speed below that
// speed cannot represent the flow at all: refused, naming the material's key; below 3 times it
// (Mach > 1/3, density variations ~10 %, the health check's default bound): a warning. The
// usual design rule is 10 times (the message says so).
void FluidModule::checkSoundSpeeds(const Simulation& sim) const {
  const auto& st = sim.store;
  const Index n = st.realCount();
  const int d = dim_;
  const double* x = st.data(st.position());
  const double* v = st.data(st.velocity());
  const std::int32_t* mt = st.data(st.material());
  // The strongest gravity the run reaches: `gravity` x the schedule's largest |factor| (the
  // direction is that of `gravity`).
  double g = 0.0;
  for (double c : gravity_) g += c * c;
  g = std::sqrt(g);
  const double gMax = g * gravitySchedule_.largestFactor();
  double fMax = largestBodyForce(), length = 0.0;
  for (int a = 0; a < d; ++a) length = std::max(length, sim.domain.length(a));
  for (size_t id = 0; id < mat_.size(); ++id) {
    const MaterialData& md = mat_[id];
    if (!md.owned || !md.fluid) continue;
    double v2max = 0.0, lo = 1e300, hi = -1e300;
    Index count = 0;
    for (Index i = 0; i < n; ++i) {
      if (mt[i] != static_cast<std::int32_t>(id)) continue;
      ++count;
      double v2 = 0.0, along = 0.0;
      for (int a = 0; a < d; ++a) {
        v2 += v[i * d + a] * v[i * d + a];
        if (g > 0.0) along -= x[i * d + a] * gravity_[static_cast<size_t>(a)] / g;
      }
      v2max = std::max(v2max, v2);
      lo = std::min(lo, along);
      hi = std::max(hi, along);
    }
    if (count == 0) continue;
    struct Speed { double value; std::string why; };
    std::vector<Speed> speeds = {{std::sqrt(v2max), "its largest initial velocity"}};
    if (gMax > 0.0 && hi > lo)
      speeds.push_back({std::sqrt(2.0 * gMax * (hi - lo)),
                        "sqrt(2 g H), free fall over its height H = " + std::to_string(hi - lo) + " m"});
    if (fMax > 0.0)
      speeds.push_back({std::sqrt(2.0 * fMax * length),
                        "sqrt(2 f L), the body force over the domain length L = " +
                            std::to_string(length) + " m"});
    const Speed* top = &speeds[0];
    for (const auto& sp : speeds)
      if (sp.value > top->value) top = &sp;
    if (!(top->value > 0.0)) continue;
    const ParameterSet& p = sim.materials[id].parameters;
    std::ostringstream m;
    m.precision(4);
    m << "the flow speed this scene implies for '" << sim.materials[id].name << "' is "
      << top->value << " m/s (" << top->why << "); the weakly compressible model (Eq. 1.4) needs "
      << "sound_speed >= 10 x that, " << 10.0 * top->value << " m/s";
    if (md.soundSpeed < top->value) p.fail("sound_speed", "is below it: " + m.str());
    if (md.soundSpeed < 3.0 * top->value)  // Mach > 1/3: ~10 % density variation ahead
      std::fprintf(stderr, "warning: %s: sound_speed %g m/s: %s\n", p.where("sound_speed").c_str(),
                   md.soundSpeed, m.str().c_str());
  }
}

// Hydrostatic initial state, dp/dz = -rho0(z) |g| integrated down every vertical column of fluid
// particles (columns: the particles' positions across g, binned at the spacing), starting from
// p = p_b at the height `hydrostatic_level`. Each particle gets the density its own EOS gives at
// that pressure, so a column holding several fluids (a gas bubble in water, layered liquids)
// starts in equilibrium: inside a bubble the pressure is that of the water at its depth, not
// the gas' own (1000 times lighter) column. For a single fluid this is p_b + rho0 |g| (level - z).
// Masses are scaled with the density so that the particle volumes stay the lattice cells.
void FluidModule::initialiseHydrostatic(Simulation& sim) {
  auto& st = sim.store;
  const int d = dim_;
  const Index n = st.realCount();
  const double* x = st.data(st.position());
  double* rho = st.data(st.density());
  double* m = st.data(st.mass());
  double* p = st.data(pressure);
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const std::array<double, 3> gStart = gravityAt(sim.time);  // initialise(): the start's gravity
  double gNorm = 0.0;
  for (double g : gStart) gNorm += g * g;
  gNorm = std::sqrt(gNorm);
  struct Entry {
    std::array<long, 3> column;
    double height;
    Index i;
  };
  std::vector<Entry> e;
  // Bins of width dx centred on the lattice of the first fluid particle (offset), so that
  // particles of one lattice line never straddle a bin edge whatever their rounding.
  double offset[3] = {0.0, 0.0, 0.0};
  bool first = true;
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid) continue;
    double height = 0.0;
    for (int a = 0; a < d; ++a) height -= x[i * d + a] * gStart[static_cast<size_t>(a)] / gNorm;
    Entry en{{0, 0, 0}, height, i};
    for (int a = 0; a < d; ++a) {  // position across g, binned
      const double across = x[i * d + a] + height * gStart[static_cast<size_t>(a)] / gNorm;
      const double u = across / sim.spacing;
      if (first) offset[a] = u - std::floor(u);
      en.column[static_cast<size_t>(a)] = std::lround(std::floor(u - offset[a] + 0.5));
    }
    first = false;
    e.push_back(en);
  }
  std::sort(e.begin(), e.end(), [](const Entry& a, const Entry& b) {
    return a.column != b.column ? a.column < b.column : a.height > b.height;
  });
  double pPrev = 0.0, rhoPrev = 0.0, zPrev = 0.0;
  for (size_t k = 0; k < e.size(); ++k) {
    const MaterialData& md = mat_[static_cast<size_t>(mt[e[k].i])];
    const bool top = k == 0 || e[k].column != e[k - 1].column;
    const double pk = top ? md.backgroundPressure + md.rho0 * gNorm * (hydrostaticLevel_ - e[k].height)
                          : pPrev + 0.5 * (rhoPrev + md.rho0) * gNorm * (zPrev - e[k].height);
    // The fluid is compressed in place: a particle keeps its volume V = m / rho (the lattice
    // cell) and its mass follows the density. Keeping m = rho0 V instead leaves m / rho off the
    // cell volume by the compression (7 % for gas at depth): the particle volumes then no longer
    // tile the space and the pressure forces (5.2b, Hu-Adams) at a gas-water interface are out of
    // balance; with gas expanded beyond its cell this drove water into a rising bubble.
    const double volume = m[e[k].i] / rho[e[k].i];
    rho[e[k].i] = densityOf(md, pk);
    m[e[k].i] = rho[e[k].i] * volume;
    p[e[k].i] = pressureOf(md, rho[e[k].i]);
    pPrev = pk;
    rhoPrev = md.rho0;
    zPrev = e[k].height;
  }
}

// ---------------------------------------------------------------------------------------------
// stages

FluidModule::Fields FluidModule::fields(Simulation& sim) const {
  auto& st = sim.store;
  Fields f;
  f.n = st.realCount();
  f.nAll = st.size();
  f.x = st.data(st.position());
  f.v = st.data(st.velocity());
  f.m = st.data(st.mass());
  f.rho = st.data(st.density());
  f.p = st.data(pressure);
  f.vw = wallVelocity.valid() ? st.data(wallVelocity) : nullptr;
  f.acc = st.data(sim.acceleration);
  f.ph = st.data(st.phase());
  f.mt = st.data(st.material());
  f.mo = st.data(sim.motion);
  f.drho = summation_ ? nullptr : st.data(densityRate);
  f.corrRate = positionCorrection.valid() ? st.data(positionCorrection) : nullptr;
  f.visc = factors_ ? st.data(viscousFactor) : nullptr;
  f.nextFactor = factors_ ? st.data(viscousFactorNext) : nullptr;
  f.aw = movingBoundaries_ ? st.data(boundaryAcceleration_) : nullptr;
  return f;
}

std::array<double, 3> FluidModule::gravityAt(double t) const {
  const double factor = gravitySchedule_.factor(t);
  std::array<double, 3> g{0, 0, 0};
  for (size_t a = 0; a < gravity_.size() && a < 3; ++a) g[a] = gravity_[a] * factor;
  return g;
}

void FluidModule::publishGravity(Simulation& sim) const {
  sim.published.fluidGravity = gravityAt(sim.time);
}

void FluidModule::kinematics(Simulation& sim) {
  publishGravity(sim);  // the gravity of this evaluation's time (gravity_schedule)
  dispatchDimension(dim_, [&](auto dc) { this->template kinematicsD<decltype(dc)::value>(sim); });
}
void FluidModule::constitutive(Simulation& sim) {
  dispatchDimension(dim_, [&](auto dc) { this->template constitutiveD<decltype(dc)::value>(sim); });
}
void FluidModule::forces(Simulation& sim) {
  dispatchDimension(dim_, [&](auto dc) { this->template forcesD<decltype(dc)::value>(sim); });
}

template <int D>
void FluidModule::kinematicsD(Simulation& sim) {
  auto& st = sim.store;
  const Fields f = fields(sim);
  const Index n = f.n;
  const auto& nl = sim.neighbours;
  const Kernel& W = sim.kernel;

  // Density summation (option; number-density form rho_a = m_a sum_b W_ab, Hu & Adams, so that
  // it holds across a density jump; boundary particles count as full neighbours).
  if (summation_ && nl.half) {
    densitySummationHalf<D>(sim, f);  // fluid_half.cpp
    st.refreshGhosts(st.density());
  } else if (summation_) {
    const double w0 = W.value(0.0);
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (f.ph[i] != kPhaseFluid) continue;
      double s = w0;
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        Vec<D> r;
        for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
        s += W.value(r.norm());
      }
      f.rho[i] = f.m[i] * s;
    }
    st.refreshGhosts(st.density());
  }

  if (!surfaceTensionActive()) return;  // no colour fields allocated (see configure)
  // Colour gradient (Eq. 5.7) on interface particles only: a particle whose neighbours all have
  // its colour costs one comparison per neighbour.
  const double* col = st.data(colour);
  double* ng = st.data(colourGradient);
  double* kap = st.data(curvature);
  std::int32_t* itf = st.data(interface);
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    Vec<D> g = Vec<D>::Zero();
    int flag = 0;
    if (f.ph[i] == kPhaseFluid) {
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        const double dc = col[j] - col[i];
        if (dc == 0.0) continue;
        if (f.ph[j] != kPhaseFluid && (!wallWetting_ || wettingNormal_)) continue;
        flag = 1;
        Vec<D> r;
        for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
        const double Vj = f.m[j] / f.rho[j];
        // Unweighted Eq. 5.7: the normal and its curvature (5.8) are those of the colour field on
        // both sides of the interface; the density weighting 2 rho_a / (rho_a + rho_b) of the
        // force is applied in the force stage (weighting the normal here would leave only the
        // heavy side's particles with a reliable normal, and the curvature 1/r of their band,
        // inside the interface: +6 % on the Laplace jump at density ratio 1000, R/dx = 10).
        g += (Vj * dc * W.F(r.norm())) * r;
      }
    }
    for (int a = 0; a < D; ++a) ng[i * D + a] = g[a];
    itf[i] = flag;
  }

  // Wetting by a prescribed contact-line normal (option wetting: normal; the thesis' reading of
  // Eq. 1.10, "near the solid contact interface these values are employed to compute the local
  // unit normal", in Brackbill's wall-adhesion form): near a boundary the outward liquid normal
  // m = -n/|n| is turned towards m_theta = n_w cos(theta) + t_w sin(theta), n_w the wall normal
  // (into the fluid), t_w the tangent along the wall pointing away from the liquid, cos(theta)
  // the wall colour (Eq. 1.10, Shepard mean over the boundary neighbours). The blend weight is
  // s = min(1, chi / wetting_scale), chi = sum_w V_w W_aw the boundary's Shepard fraction.
  // n_w: -grad of the boundary indicator over i's support (`wall_normal: local`), or with
  // `wall_normal: wide` the kernel mean sum_w V_w W_aw g_w of the fixed walls' set-up normals
  // (computeWallNormalsD: over twice the smoothing length, flat across voxel steps).
  // Reads and writes only particle i's own gradient (gather form).
  if (wallWetting_ && wettingNormal_) {
    const double thrW = normalThreshold_ / W.h();
    const double scale = wettingScale_;
    const double* wnrm = wallNormal.valid() ? st.data(wallNormal) : nullptr;
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (f.ph[i] != kPhaseFluid || !itf[i]) continue;
      Vec<D> ni;
      for (int a = 0; a < D; ++a) ni[a] = ng[i * D + a];
      const double nn = ni.norm();
      if (nn <= thrW) continue;
      double chi = 0.0, cw = 0.0;
      Vec<D> nw = Vec<D>::Zero();
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        if (f.ph[j] == kPhaseFluid) continue;
        Vec<D> r;
        for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
        const double rn = r.norm();
        const double Vj = f.m[j] / f.rho[j];
        const double w = Vj * W.value(rn);
        chi += w;
        cw += w * col[j];
        if (wnrm && f.ph[j] == kPhaseWall) {
          for (int a = 0; a < D; ++a) nw[a] += w * wnrm[j * D + a];  // wall_normal: wide (set-up)
        } else {
          nw -= (Vj * W.F(rn)) * r;  // -grad of the wall indicator: points from the wall to i
        }
      }
      const double nwn = nw.norm();
      if (chi <= 0.0 || nwn <= 0.0) continue;
      nw /= nwn;
      const Vec<D> mo = -ni / nn;
      Vec<D> t = mo - mo.dot(nw) * nw;
      const double tn = t.norm();
      if (tn < 1e-12) continue;
      t /= tn;
      double cosT = std::clamp(cw / chi, -1.0, 1.0);
      if (wettingCurved_) {
        // Option wetting_curvature (issue 14, the +4 degree bias of the 120-degree caps): the
        // prescribed angle theta (Eq. 1.10) is that of the meniscus AT the wall. The normal is
        // prescribed over a band ~2 dx thick; prescribing theta at every height of that band
        // bends the meniscus into a straight foot (the measured cap, a circle fitted above the
        // band and cut with the wall, then meets the wall at theta + delta / (r sin theta), delta
        // the foot's height: +4 degrees at 120, r ~ 8 dx). A circle of curvature kappa (Eq. 1.6,
        // > 0 for a convex liquid) that meets the wall at theta has, at height s above it, the
        // angle cos theta(s) = cos theta + s kappa, kappa its curvature in the plane of n_w and m
        // (2D: kappa; 3D: kappa / 2, exact for a spherical cap). s is the height of the interface
        // point x_i + c_i (dx/2) m (the plane of the ghost colour) above the wall's surface, half
        // a spacing above the nearest wall particle along n_w; kappa the Shepard mean of the
        // previous evaluation's curvature over the interface neighbours (a single particle's
        // kappa scatters by ~50 % of 1/R at R/dx 10). Colour-symmetric: c, kappa and cos theta
        // all change sign with the phases swapped.
        const double halfDx = 0.5 * (sim.spacing > 0.0 ? sim.spacing : W.h());
        double depth = 1e300, ks = 0.0, kw = 0.0;
        for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
          const Index j = nl.index[static_cast<size_t>(k)];
          Vec<D> r;
          for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
          if (f.ph[j] != kPhaseFluid) {
            depth = std::min(depth, r.dot(nw));
          } else if (itf[j]) {
            const double w = f.m[j] / f.rho[j] * W.value(r.norm());
            ks += w * kap[j];
            kw += w;
          }
        }
        const double wi = f.m[i] / f.rho[i] * W.value(0.0);
        ks += wi * kap[i];
        kw += wi;
        const double s = std::max(0.0, depth - halfDx + col[i] * halfDx * cosT);
        cosT = std::clamp(cosT + s * (ks / kw) / (D - 1), -1.0, 1.0);
      }
      const double sinT = std::sqrt(std::max(0.0, 1.0 - cosT * cosT));
      const Vec<D> mt = cosT * nw + sinT * t;
      const double sw = std::min(1.0, chi / scale);
      Vec<D> mn = (1.0 - sw) * mo + sw * mt;
      const double mnn = mn.norm();
      if (mnn <= 0.0) continue;
      // Ghost colour (option wetting_ghost, default off; issue 14): the boundary neighbours enter
      // the magnitude |n| (the CSF's interface delta) with the colour the fluid would have there
      // if the interface continued straight into the wall at the prescribed angle: +1 (liquid)
      // behind the plane through x_I = x_i + c_i (dx/2) m (the interface, half a spacing from
      // i along the outward liquid normal m), -1 in front of it. Without it the delta of the
      // particles at the contact line is cut by the wall (|n| h ~ 0.2-0.6 instead of ~1) and the
      // Young force of the kink between the bulk and the prescribed normal is too weak to beat
      // the drop's resistance: 150 degrees settled at ~140 (measured, docs/fluid.md). With it
      // and wetting_scale 0.05, 30-150 degrees within 5; not the default because it moves the
      // 60-degree capillary entry threshold above 1.1 times Young-Laplace (docs/fluid.md).
      double mag = nn;
      if (wettingGhost_) {
        const double halfDx = 0.5 * (sim.spacing > 0.0 ? sim.spacing : W.h());
        const Vec<D> uo = mn / mnn;
        Vec<D> xI;
        for (int a = 0; a < D; ++a) xI[a] = f.x[i * D + a] + col[i] * halfDx * uo[a];
        Vec<D> gt = ni;
        for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
          const Index j = nl.index[static_cast<size_t>(k)];
          if (f.ph[j] == kPhaseFluid) continue;
          Vec<D> r, d;
          for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a], d[a] = f.x[j * D + a] - xI[a];
          const double dc = (d.dot(uo) < 0.0 ? 1.0 : -1.0) - col[i];
          if (dc == 0.0) continue;
          gt += (f.m[j] / f.rho[j] * dc * W.F(r.norm())) * r;
        }
        mag = (1.0 - sw) * nn + sw * gt.norm();  // the same blend as the direction
      }
      mn *= -mag / mnn;
      for (int a = 0; a < D; ++a) ng[i * D + a] = mn[a];
    }
  }
  st.refreshGhosts(colourGradient);
  st.refreshGhosts(interface);

  // Curvature kappa = -div(n_hat) (Eq. 1.6) from the differences of unit normals as in Eq. 5.8,
  // over the neighbours with a reliable normal (|n| h > threshold), with a moment-matrix
  // correction so that the thin band of interface neighbours still gives the exact divergence of
  // a linear field (without it the curvature of a 2D droplet at R/dx = 15 is ~10 % too large).
  const double h = W.h();
  const double thr = normalThreshold_ / h;
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    kap[i] = 0.0;
    if (!itf[i] || f.ph[i] != kPhaseFluid) continue;
    Vec<D> ni;
    for (int a = 0; a < D; ++a) ni[a] = ng[i * D + a];
    const double nn = ni.norm();
    if (nn <= thr) continue;
    const Vec<D> ui = ni / nn;
    // grad(n_hat) A from A M = sum_b V_b (n_hat_b - n_hat_a) (F r_ab)^T with the moment matrix
    // M = -sum_b V_b F r_ab r_ab^T of the neighbours used (exact for a linear field even when
    // those neighbours form a thin band along the interface); kappa = -tr(A).
    Mat<D> G = Mat<D>::Zero(), M = Mat<D>::Zero();
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const Index j = nl.index[static_cast<size_t>(k)];
      if (f.ph[j] != kPhaseFluid || !itf[j]) continue;
      Vec<D> nj;
      for (int a = 0; a < D; ++a) nj[a] = ng[j * D + a];
      const double nnj = nj.norm();
      if (nnj <= thr) continue;
      Vec<D> r;
      for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
      const double Vj = f.m[j] / f.rho[j];
      const double F = W.F(r.norm());
      G += (Vj * F) * (nj / nnj - ui) * r.transpose();
      M -= (Vj * F) * r * r.transpose();
    }
    const double tr = M.trace();
    if (tr <= 0.0) continue;
    if (M.determinant() > 1e-4 * std::pow(tr / D, D)) {
      kap[i] = -(G * M.inverse()).trace();
    } else {
      kap[i] = -G.trace() * D / tr;  // isotropic normalisation (Morris 2000)
    }
  }
  st.refreshGhosts(curvature);  // the force stage reads the neighbours' curvature
  if (surfaceAcceleration.valid()) surfaceAccelerationD<D>(sim);
}

// CSF surface tension, Eq. 1.9 with the colour gradient of Eq. 5.7 (colour jump 2 => 1/2):
//   a_s = (gamma / 2) kappa_a |n_W| / |n_U| n_a / rho_a   on interface particles, 0 elsewhere.
// The normal n_a (colour_gradient: unweighted 5.7, turned by the wetting model near walls) is
// scaled to the density-weighted magnitude |n_W| = |sum w V dc grad W| (w = 2 rho_a/(rho_a+rho_b):
// the force acts on the heavy side, whose acceleration it does not overload); the curvature is
// the weighted mean over the straddling pairs of their midpoint curvature, i.e. that of the
// interface, not of the particle's own level line (the weighted force sits on the heavy side
// only, where 1/r is larger than at the interface by ~dx/R). Computed here, after the curvature
// and before the constitutive stage, so that the walls' pressure extrapolation can balance it
// (wall_pressure_surface_tension, issue 14 H5); the force stage adds it (the same values as
// when the force loop summed these pairs itself, bit for bit).
template <int D>
void FluidModule::surfaceAccelerationD(Simulation& sim) {
  auto& st = sim.store;
  const Fields f = fields(sim);
  const Index n = f.n;
  const auto& nl = sim.neighbours;
  const Kernel& W = sim.kernel;
  const double* col = st.data(colour);
  const double* ng = st.data(colourGradient);
  const double* kap = st.data(curvature);
  const std::int32_t* itf = st.data(interface);
  double* as = st.data(surfaceAcceleration);
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  const bool wallPairs = wallWetting_ && !wettingNormal_;  // wetting: colour (walls' colour in 5.7)
  W.withFixedType<D>([&](const auto K) {  // the kernel type fixed at compile time, as the force loop
#pragma omp parallel for schedule(dynamic, 256)
  for (Index i = 0; i < n; ++i) {
    for (int a = 0; a < D; ++a) as[i * D + a] = 0.0;
    if (f.ph[i] != kPhaseFluid || !itf[i]) continue;
    const int ida = f.mt[i];
    if (ida < 0 || ida >= nm || !md[ida].fluid) continue;
    Vec<D> nU = Vec<D>::Zero(), nW = Vec<D>::Zero();
    double kS = 0.0, wS = 0.0;
    for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
      const Index j = nl.index[static_cast<size_t>(k)];
      const bool fl = f.ph[j] == kPhaseFluid;
      if (col[j] == col[i] || !(fl || wallPairs)) continue;
      Vec<D> r;
      for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
      const double F = K.F(r.norm());
      if (F == 0.0) continue;
      const Vec<D> gradW = F * r;
      // The pairs of Eq. 5.7 again: unweighted and density-weighted normal, and the curvature
      // where the pair straddles the interface.
      const double dc = col[j] - col[i], Vb = f.m[j] / f.rho[j];
      nU += (Vb * dc) * gradW;
      const double w = densityWeightedCsf_ && fl ? 2.0 * f.rho[i] / (f.rho[i] + f.rho[j]) : 1.0;
      nW += (w * Vb * dc) * gradW;
      const double kb = fl ? kap[j] : 0.0, ka = kap[i];
      // The pair's share of the force sits on its heavy side (w > 1): there the curvature is
      // moved towards the partner's, kappa_a + (1 - 1/w)(kappa_b - kappa_a), so that the two
      // sides' forces of the pair add up to (kappa_a + kappa_b)/2, the curvature at the
      // interface, whatever the density ratio (w_ab kappa_a' + w_ba kappa_b' = kappa_a + kappa_b
      // with w_ab + w_ba = 2). At equal densities w = 1: each particle keeps its own kappa (the
      // lattice-aligned wetting depends on that near the contact line); at ratio 1000 the heavy
      // side takes the mean (the harmonic mean, exact for (D-1)/r, is biased low by the
      // particle noise of kappa, ~50 % of 1/R per particle at R/dx = 10).
      const double beta = (kb != 0.0 && w > 1.0) ? 1.0 - 1.0 / w : 0.0;
      const double km = ka + beta * (kb - ka);
      const double wt = w * Vb * std::abs(dc * F) * r.norm();
      kS += km * wt;
      wS += wt;
    }
    const double nu = nU.norm();
    const double scale = nu > 0.0 ? nW.norm() / nu : 1.0;
    const double kappa = wS > 0.0 ? kS / wS : kap[i];
    for (int a = 0; a < D; ++a) as[i * D + a] = 0.5 * gamma_ * kappa * scale * ng[i * D + a] / f.rho[i];
  }
  });
  // Only the walls' extrapolation reads a ghost's a_s (the force loop reads its own particle's).
  if (wallCsf_) st.refreshGhosts(surfaceAcceleration);
}

template <int D>
void FluidModule::constitutiveD(Simulation& sim) {
  auto& st = sim.store;
  const Fields f = fields(sim);
  const Index n = f.n;
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());

  // Equation of state (Eq. 1.4 or Tait) and the largest density variation.
  double maxVar = 0.0;
#pragma omp parallel for schedule(static) reduction(max : maxVar)
  for (Index i = 0; i < n; ++i) {
    if (f.ph[i] != kPhaseFluid) continue;
    const int id = f.mt[i];
    if (id < 0 || id >= nm || !md[id].fluid) continue;
    f.p[i] = pressureOf(md[id], f.rho[i]);
    maxVar = std::max(maxVar, std::abs(f.rho[i] - md[id].rho0) / md[id].rho0);
  }
  maxVariation_ = maxVar;
  if (maxVar > densityBound_) {
    ++boundExceeded_;
    if (maxVar > 1.5 * lastWarned_) {
      std::fprintf(stderr,
                   "warning: fluid: max density variation %.3g %% exceeds the bound %.3g %% at "
                   "step %lld (t = %.6g s): the sound speed is too low for this flow\n",
                   100.0 * maxVar, 100.0 * densityBound_, static_cast<long long>(sim.step),
                   sim.time);
      lastWarned_ = maxVar;
    }
  }
  st.refreshGhosts(pressure);

  // Boundary particles (walls, other phases): pressure and velocity extrapolated from the fluid
  // neighbours (extended summation with a hydrostatic correction, Adami et al. 2012):
  //   p_w = (sum_f p_f W_wf + g . sum_f rho_f r_wf W_wf) / sum_f W_wf,
  //   v~_w = 2 v_w - sum_f v_f W_wf / sum_f W_wf   (no-slip in the viscous term).
  const auto& nl = sim.neighbours;
  const Kernel& W = sim.kernel;
  Vec<D> g;
  {
    const std::array<double, 3> gNow = gravityAt(sim.time);  // x the gravity_schedule's factor
    for (int a = 0; a < D; ++a) g[a] = gNow[static_cast<size_t>(a)];
  }
  // Only boundary particles with a fluid neighbour are extrapolated (issue 17): they are
  // flagged from the fluid particles' candidate lists (Simulation::neighbourCandidates: the
  // lists are symmetric; a ghost neighbour flags its source), so that the neighbours of the
  // dry boundary (in a rock scene ~87 % of the particles are solid) are not swept. The flags
  // are a superset of the wet boundary until the next neighbour search, so with a Verlet skin
  // they are refreshed only then. The others get p = 0 and v~ = v, what the sweep gave them
  // (no fluid neighbour: sum W = 0), and so does a flagged one without a fluid neighbour now.
  if (wetFlag_.size() < static_cast<size_t>(n)) wetFlag_.resize(static_cast<size_t>(n));
  unsigned char* wet = wetFlag_.data();
  if (wetBuild_ != sim.neighbourBuilds() || wetCount_ != st.size()) {
    wetBuild_ = sim.neighbourBuilds();
    wetCount_ = st.size();
    const auto& cl = sim.neighbourCandidates();
    const Index* ghostSource = st.ghostSources().data();
    if (cl.half) {
      wetFlagsHalf<D>(sim, f);  // fluid_half.cpp
    } else {
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) wet[i] = 0;
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (f.ph[i] != kPhaseFluid) continue;
        for (auto k = cl.offset[i]; k < cl.offset[i + 1]; ++k) {
          const Index j = cl.index[static_cast<size_t>(k)];
          if (f.ph[j] == kPhaseFluid) continue;
          const Index b = j < n ? j : ghostSource[j - n];
#pragma omp atomic write
          wet[b] = 1;
        }
      }
    }
  }
  // With surface tension (wall_pressure_surface_tension, issue 14 H5) each fluid neighbour's
  // CSF acceleration a_s,f (Eq. 1.9, surfaceAccelerationD) joins the body force of the
  // hydrostatic term, p_w = sum_f [p_f + rho_f (g + a_s,f - a_w) . r_wf] W_wf / sum_f W_wf:
  // the wall then holds the CSF force's wall-normal part at a contact line as it holds gravity.
  const double* as = wallCsf_ && surfaceAcceleration.valid() ? st.data(surfaceAcceleration) : nullptr;
  if (nl.half) {
    wallExtrapolationHalf<D>(sim, f);  // fluid_half.cpp (no surface tension: full list)
  } else {
#pragma omp parallel for schedule(dynamic, 512)
    for (Index i = 0; i < n; ++i) {
      if (f.ph[i] == kPhaseFluid) continue;
      if (!wet[i]) {
        f.p[i] = 0.0;
        if (f.vw)
          for (int a = 0; a < D; ++a) f.vw[i * D + a] = f.v[i * D + a];
        continue;
      }
      // A moving boundary: g - a_w (Adami et al. 2012, Eq. 27), a_w of the last evaluation.
      Vec<D> ga = g;
      if (f.aw && f.mo[i] != kMotionFixed)
        for (int a = 0; a < D; ++a) ga[a] -= f.aw[i * D + a];
      double sw = 0.0, sp = 0.0, ss = 0.0;
      Vec<D> srr = Vec<D>::Zero(), sv = Vec<D>::Zero();
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        if (f.ph[j] != kPhaseFluid) continue;
        Vec<D> r;
        for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
        const double w = W.value(r.norm());
        sw += w;
        sp += f.p[j] * w;
        srr += (f.rho[j] * w) * r;
        if (as) {
          double ar = 0.0;
          for (int a = 0; a < D; ++a) ar += as[j * D + a] * r[a];
          ss += f.rho[j] * w * ar;  // rho_f (a_s,f . r_wf) W_wf
        }
        if (f.vw)
          for (int a = 0; a < D; ++a) sv[a] += f.v[j * D + a] * w;
      }
      if (sw > 0.0) {
        f.p[i] = (as ? sp + ga.dot(srr) + ss : sp + ga.dot(srr)) / sw;
        if (f.vw)
          for (int a = 0; a < D; ++a) f.vw[i * D + a] = 2.0 * f.v[i * D + a] - sv[a] / sw;
      } else {
        f.p[i] = 0.0;
        if (f.vw)
          for (int a = 0; a < D; ++a) f.vw[i * D + a] = f.v[i * D + a];
      }
    }
  }
  st.refreshGhosts(pressure);
  if (wallVelocity.valid()) st.refreshGhosts(wallVelocity);
}

template <int D>
void FluidModule::forcesD(Simulation& sim) {
  auto& st = sim.store;
  const Fields f = fields(sim);
  const Index n = f.n;
  const auto& nl = sim.neighbours;
  const Kernel& W = sim.kernel;
  const bool xsphOn = xsph_ > 0.0, shiftOn = shifting_ > 0.0, tvOn = transportVelocity_;
  const double pOff = pressureReference_ ? backgroundPressure_ : 0.0;
  // Transport velocity (Adami et al. 2013): particles move with v + dt a_b,
  // a_b = -(p_b / m_a) sum_b (V_a^2 + V_b^2) grad W_ab (the background pressure's force, here
  // only in the advection).
  const double tvScale = tvOn ? sim.dt * backgroundPressure_ : 0.0;
  // Shifting velocity scale: the largest fluid speed (particles at rest are not shifted).
  double uShift = 0.0;
  if (shiftOn) {
#pragma omp parallel for schedule(static) reduction(max : uShift)
    for (Index i = 0; i < n; ++i) {
      if (f.ph[i] != kPhaseFluid) continue;
      double v2 = 0.0;
      for (int a = 0; a < D; ++a) v2 += f.v[i * D + a] * f.v[i * D + a];
      uShift = std::max(uShift, std::sqrt(v2));
    }
  }
  const double* kap = gamma_ > 0.0 ? st.data(curvature) : nullptr;
  const std::int32_t* itf = gamma_ > 0.0 ? st.data(interface) : nullptr;
  const double* col = gamma_ > 0.0 ? st.data(colour) : nullptr;
  const double* as = surfaceAcceleration.valid() ? st.data(surfaceAcceleration) : nullptr;
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  const double h = W.h();
  const bool huAdams = pressureForm_ == PressureForm::HuAdams;  // the wall pairs and the balanced CSF
  Vec<D> g;
  {
    const std::array<double, 3> gNow = gravityAt(sim.time);  // x the gravity_schedule's factor
    for (int a = 0; a < D; ++a) g[a] = gNow[static_cast<size_t>(a)];
  }

  // Lattice normalisation of the Laplacian (5.3/5.4): sum_b V_b |r_ab|^2 (-F_ab) = D holds in
  // the continuum only; on the particle lattice it is a few per cent off at h ~ 1.3 dx, which
  // becomes the same error on the effective viscosity. Each particle's factor D / moment makes
  // the Laplacian of a quadratic field exact (1 where the support is truncated); a pair uses the
  // mean of its two factors (a boundary pair: the fluid particle's), so that the viscous pair
  // forces are equal and opposite and momentum is conserved.
  // The factors of the previous evaluation are used (the pair forces stay equal and opposite;
  // particles move a small fraction of dx per step, so the factor changes by far less than its
  // own lattice correction); this evaluation's moments are summed in the force loop below, so
  // no extra neighbour pass is paid (it cost ~9 % of the step). Only the first evaluation of a
  // run computes them in a pass of their own. They are checkpointed, so a restart continues
  // with the same factors.
  if (factors_ && !viscousFactorsReady_) {
    if (nl.half) {
      viscousFactorsHalf<D>(sim, f);  // fluid_half.cpp
    } else {
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (f.ph[i] != kPhaseFluid) {
          f.visc[i] = 1.0;
          continue;
        }
        double moment = 0.0;  // sum_b V_b |r_ab|^2 (-F_ab) over every neighbour
        for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
          const Index j = nl.index[static_cast<size_t>(k)];
          Vec<D> r;
          for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
          moment -= (f.m[j] / f.rho[j]) * r.squaredNorm() * W.F(r.norm());
        }
        f.visc[i] = moment > 0.5 * D ? D / moment : 1.0;
      }
    }
    st.refreshGhosts(viscousFactor);
    viscousFactorsReady_ = true;
  }
  const FluidPairSettings pairSettings = sim.fluidPairSettings;

  // The pair loop with the kernel type fixed at compile time (one switch per loop, not per
  // pair), and per-particle quantities computed once instead of once per pair: (p - p_ref) /
  // rho^2 and, with one fluid material, the density the fluid has at a boundary particle's
  // extrapolated pressure (Tait: a pow per wall pair otherwise). Same values bit for bit.
  const Index nAll = st.size();
  const MaterialData* single = nullptr;
  {
    int fluids = 0;
    for (int id = 0; id < nm; ++id)
      if (md[id].owned && md[id].fluid) { single = &md[id]; ++fluids; }
    if (fluids != 1) single = nullptr;
  }
  // (p - p_ref) / rho^2 is read at fluid particles only (fluid-fluid pairs) and the wall density
  // at boundary particles only (fluid-boundary pairs): one array holds both, each particle the
  // one its phase needs (issue 17, memory: 8 B per particle less; same values).
  if (pRho2_.size() < static_cast<size_t>(nAll)) pRho2_.resize(static_cast<size_t>(nAll));
  double* pRho2W = pRho2_.data();
#pragma omp parallel for schedule(static)
  for (Index j = 0; j < nAll; ++j) {
    if (f.ph[j] == kPhaseFluid)
      pRho2W[j] = (f.p[j] - pOff) / (f.rho[j] * f.rho[j]);  // Eq. 5.2b's p_b / rho_b^2
    else
      pRho2W[j] = single ? densityOf(*single, f.p[j]) : 0.0;
  }
  const Volumes vol{f.m, f.rho};  // V = m / rho, computed per pair (fluid_pair.hpp)
  const double* pRho2 = pRho2W;
  const double* wallRho = single ? pRho2W : nullptr;  // at boundary particles (above)
  const FluidFluidOptions ffOptions{pressureForm_, pOff, artificialViscosity_, h};
  const bool bgOn = wallBackground_ && pOff > 0.0;  // wall_background_pressure (configure)
  if (bgOn && nl.half)
    throw InputError("fluid: wall_background_pressure needs the full neighbour list (neighbour_list: "
                     "full or auto), or wall_background_pressure: false");
  if (wallPushOnly_ && nl.half)
    throw InputError("fluid: wall_push_only needs the full neighbour list (neighbour_list: full or "
                     "auto), or wall_push_only: false");
  if (wallOverlap_ && nl.half)
    throw InputError("fluid: wall_overlap_pressure needs the full neighbour list (neighbour_list: "
                     "full or auto), or wall_overlap_pressure: false");
  if (wallMirrorLight_ && nl.half)
    throw InputError("fluid: wall_pressure: light_mirror needs the full neighbour list "
                     "(neighbour_list: full or auto)");
  if (nl.half) {
    forceLoopHalf<D>(sim, f, uShift, wallRho);  // fluid_half.cpp
  } else {
    if (floatPairs_)
      throw InputError(pairPrecisionWhere_ + ": float needs the half neighbour list "
                       "(neighbour_list: half or auto); this run uses the full list");
    W.withFixedType<D>([&](const auto K) {
#pragma omp parallel for schedule(dynamic, 256)
    for (Index i = 0; i < n; ++i) {
      if (f.nextFactor) f.nextFactor[i] = 1.0;
      if (f.ph[i] != kPhaseFluid || f.mo[i] == kMotionFixed) continue;
      const int ida = f.mt[i];
      if (ida < 0 || ida >= nm || !md[ida].fluid) continue;
      const MaterialData& ma = md[ida];
      const double rhoa = f.rho[i], pa = f.p[i], mua = ma.viscosity;
      const double Va = f.m[i] / rhoa;
      const double fa = f.visc ? f.visc[i] : 1.0;
      double moment = 0.0;
      FluidPairSide<D> sideA;
      sideA.m = f.m[i];
      sideA.rho = rhoa;
      sideA.p = pa;
      sideA.props = &ma;
      Vec<D> va;
      for (int a = 0; a < D; ++a) va[a] = f.v[i * D + a];
      sideA.v = va;
      Vec<D> aP = Vec<D>::Zero(), aV = Vec<D>::Zero(), aA = Vec<D>::Zero(), dvX = Vec<D>::Zero(),
             gradC = Vec<D>::Zero();
      double divv = 0.0, diff = 0.0;
      const bool mirrorAtWalls = wallMirror_[static_cast<size_t>(ida)] != 0;
      Vec<D> tv = Vec<D>::Zero();
      Vec<D> bg = Vec<D>::Zero();  // sum_b (V_a^2 + V_b^2) grad W (wall_background_pressure)
      double sW = 0.0;                   // S_w = sum_w V_w W_aw, fixed walls (wall_overlap_pressure)
      Vec<D> gradSW = Vec<D>::Zero();    // the walls' part of its gradient, sum_w V_w grad W_aw
      bool nearWall = false;
      for (auto k = nl.offset[i]; k < nl.offset[i + 1]; ++k) {
        const Index j = nl.index[static_cast<size_t>(k)];
        Vec<D> r;
        for (int a = 0; a < D; ++a) r[a] = f.x[i * D + a] - f.x[j * D + a];
        const double F = K.F(r.norm());
        if (F == 0.0) continue;
        const Vec<D> gradW = F * r;
        Vec<D> vb;
        for (int a = 0; a < D; ++a) vb[a] = f.v[j * D + a];
        moment -= vol[j] * r.squaredNorm() * F;  // for the next evaluation's factor
        if (shiftOn) gradC += (f.m[j] / f.rho[j]) * gradW;  // grad of sum_b V_b W_ab (all neighbours)
        if (tvOn) {
          const double Vb = f.m[j] / f.rho[j];
          tv += (Va * Va + Vb * Vb) * gradW;
        }
        if (bgOn) {
          const double Vb = f.m[j] / f.rho[j];
          bg += (Va * Va + Vb * Vb) * gradW;
          nearWall = nearWall || f.ph[j] == kPhaseWall;
        }
        if (f.ph[j] == kPhaseWall) {
          // Fixed boundary: extrapolated pressure, no-slip velocity (the shared pair terms).
          // wall_pressure: light_mirror: a lighter fluid takes its own pressure and density there.
          // wall_push_only: the positive parts of the force pressures p - p_ref (configure).
          BoundaryPairSide<D> sideW = wallPairSide<D>(f, j, vol, wallRho, vb);
          FluidPairSide<D> sideP = sideA;
          if (wallPushOnly_) {
            sideW.p = std::max(sideW.p, pOff);  // rho_w stays the density at the extrapolated p_w
            sideP.p = std::max(sideP.p, pOff);
          }
          const FluidPairResult<D> t =
              fluidBoundaryPair<D>(r, F, sideP, sideW, pairSettings,
                                   mirrorAtWalls ? BoundaryModel::Mirror : BoundaryModel::Extrapolated);
          aP += t.pressure;
          aV += fa * t.viscous;
          aA += t.artificial;
          divv += t.divergence;
          if (wallOverlap_) {  // wall_overlap_pressure: S_w and grad S_w (configure)
            sW += vol[j] * K.value(r.norm());
            gradSW += vol[j] * gradW;
          }
          continue;
        }
        if (f.ph[j] != kPhaseFluid) {  // fluid-solid / fluid-rigid: the coupling's pairs
          // wall_overlap_pressure: a plate's (rigid) share of the face level, not the clay's
          if (wallOverlap_ && f.ph[j] == kPhaseRigid) sW += vol[j] * K.value(r.norm());
          continue;
        }
        const int idb = f.mt[j];
        const double rhob = f.rho[j], pb = f.p[j];
        const double mub = (idb >= 0 && idb < nm) ? md[idb].viscosity : mua;
        const double Vb = vol[j];
        if (densityDiffusion_ > 0.0 && idb == ida)  // Molteni-Colagrossi density diffusion
          diff += densityDiffusionTerm(Vb, rhoa, rhob, F);
        // XSPH (2.66) within one material: averaging across a density jump would drag the light
        // phase with the heavy one.
        if (xsphOn && idb == ida) dvX += xsphTerm<D>(f.m[j], rhoa, rhob, K.value(r.norm()), vb, va);
        const double mb = f.m[j];
        const Vec<D> vab = va - vb;
        const double fab = 0.5 * (fa + (f.visc ? f.visc[j] : 1.0));
        const double muBar = mua + mub > 0.0
                                 ? (harmonicMean_ ? 4.0 * mua * mub / (mua + mub) : mua + mub)
                                 : 0.0;
        // Pressure (5.2b, 5.2a or Hu & Adams), viscosity (5.4), artificial viscosity (2.64): the terms
        // written once for both pair loops (physics/fluid/fluid_pair.hpp).
        const double cb = (idb >= 0 && idb < nm) ? md[idb].soundSpeed : ma.soundSpeed;
        const FluidPairParticle pa_{f.m[i], rhoa, Va, pa, pRho2[i], ma.soundSpeed};
        const FluidPairParticle pb_{mb, rhob, Vb, pb, pRho2[j], cb};
        FluidFluidAccel<D> ta, unusedB;
        fluidFluidPair<D, false>(r, gradW, F, vab, pa_, pb_, muBar, fab, ffOptions, ta, unusedB);
        aP += ta.pressure;
        aV += ta.viscous;
        aA += ta.artificial;
        // Eq. 5.1a / mass form; between two fluids with continuity_interface: acoustic, v_b is
        // the interface velocity (weight 2 Z_b / (Z_a + Z_b), 1 within one material)
        // (the weight is looked up only when that option is on: with it off every weight is 1,
        // and 1 * x = x, so the sums are the same bits)
        const double cterm = continuityTerm(continuityForm_, rhoa, mb, Vb, vab.dot(gradW));
        if (acousticInterface_ && idb >= 0 && idb < nm)
          divv += ifaceWeight_[static_cast<size_t>(ida * nm + idb)] * cterm;
        else
          divv += cterm;
      }
      if (f.nextFactor) f.nextFactor[i] = moment > 0.5 * D ? D / moment : 1.0;
      if (nearWall) aP -= (pOff / f.m[i]) * bg;  // wall_background_pressure
      Vec<D> ai = aP + aV + aA + g;
      if (sW > 0.5)  // wall_overlap_pressure: -(K / rho_a) (S_w - 1/2) grad S_w (0 without the key)
        ai -= (ma.rho0 * ma.soundSpeed * ma.soundSpeed / rhoa * (sW - 0.5)) * gradSW;
      addBodyForces<D>(f.x + i * D, ai);
      // CSF surface tension, Eq. 1.9: a_s of this evaluation (surfaceAccelerationD, kinematics).
      if (as)
        for (int a = 0; a < D; ++a) ai[a] += as[i * D + a];
      for (int a = 0; a < D; ++a) f.acc[i * D + a] += ai[a];
      if (f.drho) f.drho[i] += rhoa * divv + densityDiffusion_ * h * ma.soundSpeed * diff;
      if (f.corrRate) {
        // Particle shifting (Lind et al. 2012; velocity form of Sun et al. 2017's
        // dr = -CFL Ma (2h)^2 grad C): dv_s = -A h U grad C moves particles from crowded to sparse
        // regions; |dv_s| is capped at U / 2. Both phases fill the domain, so grad C ~ 0 across a
        // liquid-gas interface of consistent volumes: no interface treatment is applied (a free
        // surface would need one).
        Vec<D> dv = xsph_ * dvX;
        if (tvOn) dv -= (tvScale / f.m[i]) * tv;
        if (shiftOn) {
          Vec<D> ds = -shifting_ * h * uShift * gradC;
          const double cap = 0.5 * uShift, len = ds.norm();
          if (len > cap) ds *= cap / len;
          dv += ds;
        }
        for (int a = 0; a < D; ++a) f.corrRate[i * D + a] += dv[a];
      }
    }
    });
  }
  if (balancedCsf_ && gamma_ > 0.0) {  // balanced-force CSF (surface_tension.cpp)
    BalancedCsfArrays arr;
    arr.x = f.x;
    arr.m = f.m;
    arr.rho = f.rho;
    arr.phase = f.ph;
    arr.motion = f.mo;
    arr.colour = col;
    arr.curvature = kap;
    arr.interface = itf;
    arr.acceleration = f.acc;
    BalancedCsfSettings set;
    set.gamma = gamma_;
    set.huAdams = huAdams;
    set.volumeForm = pressureForm_ == PressureForm::Volume;
    set.smoothingRadius = curvatureSmoothing_;
    addBalancedSurfaceForce<D>(nl, W, n, arr, set, kappaWork_);
  }
  if (f.nextFactor) {  // this evaluation's factors, for the next one (see above)
    std::memcpy(f.visc, f.nextFactor, sizeof(double) * static_cast<size_t>(n));
    st.refreshGhosts(viscousFactor);
  }
}

// ---------------------------------------------------------------------------------------------
// time step and diagnostics

double FluidModule::timeStepLimit(const Simulation& sim) const {
  const auto& st = sim.store;
  const Index n = st.realCount();
  const int d = dim_;
  const double* v = st.data(st.velocity());
  const double* acc = st.data(sim.acceleration);
  const std::int32_t* ph = st.data(st.phase());
  double vmax2 = 0.0, amax2 = 0.0;
#pragma omp parallel for schedule(static) reduction(max : vmax2, amax2)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid) continue;
    double v2 = 0.0, a2 = 0.0;
    for (int a = 0; a < d; ++a) {
      v2 += v[i * d + a] * v[i * d + a];
      a2 += acc[i * d + a] * acc[i * d + a];
    }
    vmax2 = std::max(vmax2, v2);
    amax2 = std::max(amax2, a2);
  }
  const double h = sim.kernel.h();
  double dt = std::numeric_limits<double>::infinity();
  if (maxSoundSpeed_ > 0.0) dt = std::min(dt, cflAcoustic_ * h / (maxSoundSpeed_ + std::sqrt(vmax2)));
  if (maxNu_ > 0.0) dt = std::min(dt, cflViscous_ * h * h / maxNu_);  // largest kinematic viscosity
  if (amax2 > 0.0) dt = std::min(dt, cflForce_ * std::sqrt(h / std::sqrt(amax2)));  // Eq. 2.49
  if (vmax2 > 0.0) dt = std::min(dt, 0.25 * h / std::sqrt(vmax2));                   // Eq. 2.49
  if (gamma_ > 0.0 && std::isfinite(minRho0_))  // capillary waves (Brackbill et al. 1992)
    dt = std::min(dt, cflSurface_ * std::sqrt(minRho0_ * h * h * h / (2.0 * kPi * gamma_)));
  return dt;
}

ModuleSettings FluidModule::settings() const {
  const char* form = pressureForm_ == FluidPressureForm::Symmetric ? "symmetric"
                     : pressureForm_ == FluidPressureForm::HuAdams ? "hu_adams"
                                                                   : "volume";
  return {
      {"fluid.density", summation_ ? "summation" : "continuity", "continuity"},
      // Eq. 5.2b (symmetric) was the default until b84d7bb, 2026-11-27; Eq. 5.2a since.
      {"fluid.pressure_gradient", form, "symmetric", "until 2026-11-27 (b84d7bb)"},
      {"fluid.continuity_form", continuityForm_ == ContinuityForm::Mass ? "mass" : "volume",
       "volume"},
      {"fluid.continuity_interface", acousticInterface_ ? "acoustic" : "mean", "mean"},
      {"fluid.wall_pressure", wallMirrorLight_ ? "light_mirror" : "extrapolated", "extrapolated"},
      {"fluid.viscosity_mean", harmonicMean_ ? "harmonic" : "arithmetic", "harmonic"},
      {"fluid.surface_tension_form", balancedCsf_ ? "balanced" : "csf", "csf"},
      {"fluid.surface_tension_weighting", densityWeightedCsf_ ? "density" : "none", "density"},
      {"fluid.wall_pressure_surface_tension", wallCsf_ ? "true" : "false", "false"},
      {"fluid.wall_background_pressure", wallBackground_ ? "true" : "false", "false"},
      {"fluid.wall_push_only", wallPushOnly_ ? "true" : "false", "false"},
      {"fluid.wall_overlap_pressure", wallOverlap_ ? "true" : "false", "false"},
      {"fluid.wetting", wettingNormal_ ? "normal" : "colour", "normal"},
      {"fluid.wall_normal", wideWallNormal_ ? "wide" : "local", "local"},
      {"fluid.pressure_reference", pressureReference_ ? "background" : solidGauge_ ? "solid_gauge" : "none",
       "none"},
      {"fluid.pair_precision", floatPairs_ ? "float" : "double", "double"},
  };
}

void FluidModule::diagnostics(const Simulation& sim,
                              std::vector<std::pair<std::string, double>>& columns) const {
  const auto& st = sim.store;
  const Index n = st.realCount();
  const int d = dim_;
  const double* v = st.data(st.velocity());
  const double* m = st.data(st.mass());
  const std::int32_t* ph = st.data(st.phase());
  double vmax2 = 0.0, ek = 0.0;
#pragma omp parallel for schedule(static) reduction(max : vmax2) reduction(+ : ek)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid) continue;
    double v2 = 0.0;
    for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
    vmax2 = std::max(vmax2, v2);
    ek += 0.5 * m[i] * v2;
  }
  // From the density field (not the last EOS evaluation), so that the row of a restarted run
  // equals the row the interrupted run wrote at that time.
  columns.emplace_back("fluid_max_density_variation", std::max(0.0, largestDensityVariation(sim).value));
  columns.emplace_back("fluid_max_speed", std::sqrt(vmax2));
  columns.emplace_back("fluid_kinetic_energy", ek);
  // Compression energy sum m e(rho) (libcore internalEnergyOf): with the kinetic energy it is
  // what an inviscid fluid conserves.
  const double* rho = st.data(st.density());
  const std::int32_t* mt = st.data(st.material());
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  double internal = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : internal)
  for (Index i = 0; i < n; ++i)
    if (ph[i] == kPhaseFluid && mt[i] >= 0 && mt[i] < nm && md[mt[i]].fluid)
      internal += m[i] * internalEnergyOf(md[mt[i]], rho[i]);
  columns.emplace_back("fluid_internal_energy", internal);
}

MaxAt FluidModule::largestDensityVariation(const Simulation& sim) const {
  const auto& st = sim.store;
  const Index n = st.realCount();
  const double* rho = st.data(st.density());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  MaxAt worst;
#pragma omp parallel for schedule(static) reduction(maxAt : worst)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid || mt[i] < 0 || mt[i] >= nm || !md[mt[i]].fluid) continue;
    const double var = std::abs(rho[i] - md[mt[i]].rho0) / md[mt[i]].rho0;
    if (var > worst.value || (var == worst.value && i < worst.particle)) worst = MaxAt{var, i};
  }
  return worst;
}

void FluidModule::checkHealth(const Simulation& sim, const HealthLimits& limits,
                              std::vector<HealthIssue>& issues) const {
  const MaxAt var = largestDensityVariation(sim);
  if (var.particle >= 0 && var.value > limits.densityVariation)
    issues.push_back({"density_variation", "density", var.particle, var.value,
                      limits.densityVariation,
                      "|rho - rho0| / rho0 of a fluid particle: the flow is no longer weakly "
                      "compressible; raise the sound speed, lower the time step or check the "
                      "set-up"});
  // Mach number |v| / c0 of each fluid particle (the weakly compressible model assumes << 1).
  const auto& st = sim.store;
  const Index n = st.realCount();
  const int d = dim_;
  const double* v = st.data(st.velocity());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  MaxAt mach;
#pragma omp parallel for schedule(static) reduction(maxAt : mach)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid || mt[i] < 0 || mt[i] >= nm || !md[mt[i]].fluid) continue;
    double v2 = 0.0;
    for (int a = 0; a < d; ++a) v2 += v[i * d + a] * v[i * d + a];
    const double ma = std::sqrt(v2) / md[mt[i]].soundSpeed;
    if (ma > mach.value || (ma == mach.value && i < mach.particle)) mach = MaxAt{ma, i};
  }
  if (mach.particle >= 0 && !(mach.value <= limits.maxMach))
    issues.push_back({"max_mach", "velocity", mach.particle, mach.value, limits.maxMach,
                      "|v| / sound_speed of a fluid particle: the flow is faster than the weakly "
                      "compressible model allows; raise the sound speed or look for a blow-up"});
}

bool FluidModule::energyAccount(const Simulation& sim, EnergyAccount& account) const {
  const auto& st = sim.store;
  const Index n = st.realCount();
  const int d = dim_;
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const std::int32_t* ph = st.data(st.phase());
  const std::int32_t* mt = st.data(st.material());
  const MaterialData* md = mat_.data();
  const int nm = static_cast<int>(mat_.size());
  // A gravity that varies in time (gravity_schedule) has no potential: its work is counted
  // like the body forces' (untracked, at its largest magnitude) and E_p is left out.
  const bool ramped = !gravitySchedule_.constant();
  double g[3] = {0, 0, 0}, gNorm = 0.0;
  for (int a = 0; a < d; ++a) {
    g[a] = gravity_[static_cast<size_t>(a)];
    gNorm += g[a] * g[a];
  }
  gNorm = std::sqrt(gNorm);
  double fMax = largestBodyForce();
  if (ramped) {
    fMax = std::max(fMax, gNorm * gravitySchedule_.largestFactor());
    g[0] = g[1] = g[2] = 0.0;
    gNorm = 0.0;
  }
  const double* rho = st.data(st.density());
  double potential = 0.0, internal = 0.0, mass = 0.0, compression = 0.0, lo = 1e300, hi = -1e300;
#pragma omp parallel for schedule(static) reduction(+ : potential, internal, mass, compression) \
    reduction(min : lo) reduction(max : hi)
  for (Index i = 0; i < n; ++i) {
    if (ph[i] != kPhaseFluid || mt[i] < 0 || mt[i] >= nm || !md[mt[i]].fluid) continue;
    double gx = 0.0;
    for (int a = 0; a < d; ++a) gx += g[a] * x[i * d + a];
    potential -= m[i] * gx;  // E_p = -m g.x
    internal += m[i] * internalEnergyOf(md[mt[i]], rho[i]);
    mass += m[i];
    // Kinetic energy of a flow at Mach 0.1: the scale of the compression energy the weakly
    // compressible fluid exchanges without accounting for it.
    const double c = 0.1 * md[mt[i]].soundSpeed;
    compression += 0.5 * m[i] * c * c;
    const double along = gNorm > 0.0 ? gx / gNorm : 0.0;
    lo = std::min(lo, along);
    hi = std::max(hi, along);
  }
  account.stored += potential + internal;
  if (gNorm > 0.0 && hi > lo) account.storedRange += mass * gNorm * (hi - lo);
  // Body forces (e.g. a drainage pressure drop) and a ramped gravity do work that is not
  // accounted: their scale is m |f| times the domain diagonal.
  double diagonal = 0.0;
  for (int a = 0; a < d; ++a) diagonal += sim.domain.length(a) * sim.domain.length(a);
  account.untrackedScale += compression + mass * fMax * std::sqrt(diagonal);
  // Surface energy: gamma times the interface, at most the perimeter of every fluid particle.
  if (gamma_ > 0.0 && st.realCount() > 0)
    account.untrackedScale += gamma_ * static_cast<double>(n) * 2.0 * d *
                              std::pow(sim.spacing, d - 1);
  return true;
}

std::string FluidModule::describe(const Simulation& /*sim*/) const {
  if (gravitySchedule_.constant()) return "";
  std::ostringstream o;
  o << "fluid gravity: [";
  for (size_t a = 0; a < gravity_.size(); ++a) o << (a ? ", " : "") << gravity_[a];
  o << "] m/s^2 x factor(t), gravity_schedule " << gravitySchedule_.describe() << "\n";
  return o.str();
}

PORESPH_REGISTER_MODULE(FluidModule, "fluid")

}  // namespace poresph
