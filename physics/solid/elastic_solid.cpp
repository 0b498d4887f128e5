// Elastic solid module: see elastic_solid.hpp and docs/solid.md. Equation numbers are those of
// the thesis (../shared/seeds/002_*.txt from the repository root), Chapter 2.4 unless stated otherwise.
#include "physics/solid/elastic_solid.hpp"

#include "libcore/artificial_viscosity.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>
#include <type_traits>

#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "libcore/consistent_load.hpp"
#include "libcore/corrections.hpp"
#include "libcore/periodic_images.hpp"
#include "libcore/time_schedule.hpp"

namespace poresph::solid {

namespace {

// Relative displacement of a pair by minimum image along the periodic axes (period[a] > 0): u is
// each particle's own minimum image of x - X, which jumps by a period where a particle has slid
// past half a period from its reference, while the pair's difference stays small. |d| < L/4 needs
// no rounding, so the common case costs one comparison per axis. Used by the TL kinematics
// (Eqs. 2.67 / 2.82) and the displacement form (Eq. 2.89); tests/unit/test_solid_periodic_slide.cpp.
template <int D, class V>
inline void wrapPairDisplacement(V& d, const double* period) {
  for (int a = 0; a < D; ++a)
    if (period[a] > 0.0 && std::abs(d[a]) >= 0.25 * period[a])
      d[a] -= period[a] * std::round(d[a] / period[a]);
}

// Minimum image of a pair separation along the periodic axes, the member loops' form of
// "if (L > 0 && |d| >= L / 4) d -= L round(d / L)" (the family's minimumImage, and
// wrapPairDisplacement on the TL displacements): the quarter periods are precomputed (0.25 L is
// exact) and +inf on a non-periodic axis, so a member costs one comparison per axis and the period
// is tested only where |d| passed it (an infinite d on a non-periodic axis). The same values bit
// for bit. A plain value: the member loops copy it per particle, so GCC keeps it in registers
// instead of reloading the periods through the closures at every member (docs/performance.md
// "Solid pair loops (stop 33)").
struct PairImage {
  double period[3] = {0.0, 0.0, 0.0};
  double quarter[3] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
                       std::numeric_limits<double>::infinity()};
  PairImage(const double* L, int d) {
    for (int a = 0; a < d; ++a)
      if (L[a] > 0.0) {
        period[a] = L[a];
        quarter[a] = 0.25 * L[a];
      }
  }
  template <int D>
  void apply(Vec<D>& d) const {
    for (int a = 0; a < D; ++a)
      if (std::abs(d[a]) >= quarter[a] && period[a] > 0.0)
        d[a] -= period[a] * std::round(d[a] / period[a]);
  }
};

// The TL member loops (one particle's family) as functions of their own, compiled twice on x86-64
// with GCC: for the baseline (SSE2) and for AVX2, the copy chosen once at load time by the processor
// (ifunc), as the fluid's block (fluid_half.cpp). The AVX2 copy uses the three-operand VEX forms and
// the wider registers; neither copy contracts to FMA ("avx2" does not enable it) and GCC reorders no
// floating-point sum, so both give the same bits as the loops inline (docs/performance.md "Solid
// pair loops (stop 33)").
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define PORESPH_MEMBER_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define PORESPH_MEMBER_CLONES
#endif

// Conservative hourglass pass, one particle (forcesDim): M_a, the direct force and e2 (see there).
template <int D, bool kStored, class K, class Stiffness>
PORESPH_MEMBER_CLONES void hourglassMembers(const K kernel, const Stiffness stiffness,
                                            const PairImage im, Index i, std::int64_t q0,
                                            std::int64_t q1, const std::int32_t* fam,
                                            const Index* idx, const double* hgK, const double* V0,
                                            const double* hgW, const double* X, const double* x,
                                            const double* Fg, double* Mout, double* directOut,
                                            double* e2Out) {
  const Mat<D> Fi = Eigen::Map<const Mat<D>>(Fg + i * D * D);
  const Vec<D> Xi = Eigen::Map<const Vec<D>>(X + i * D);
  const Vec<D> xi = Eigen::Map<const Vec<D>>(x + i * D);
  const double ki = hgK[i];
  Mat<D> M = Mat<D>::Zero();
  Vec<D> direct = Vec<D>::Zero();
  double e2 = 0.0;
  for (std::int64_t q = q0; q < q1; ++q) {
    const Index j = idx[fam[q]];
    const double kab = stiffness(ki, hgK[j]);
    if (kab == 0.0) continue;
    Vec<D> Xji = Eigen::Map<const Vec<D>>(X + j * D) - Xi;
    Vec<D> xji = Eigen::Map<const Vec<D>>(x + j * D) - xi;
    im.apply<D>(Xji);
    im.apply<D>(xji);
    double c;
    if constexpr (kStored) {
      c = kab * V0[j] * hgW[q];  // W0_ab / |X_ab|^2 stored (family_storage fast)
    } else {
      const double r0 = Xji.norm();
      c = kab * V0[j] * kernel.value(r0) / (r0 * r0);
    }
    const Vec<D> res = xji - 0.5 * (Fi + Eigen::Map<const Mat<D>>(Fg + j * D * D)) * Xji;
    M.noalias() += c * res * Xji.transpose();
    direct.noalias() += c * res;
    e2 += c * res.squaredNorm();
  }
  Eigen::Map<Mat<D>>{Mout} = M;
  Eigen::Map<Vec<D>>{directOut} = direct;
  *e2Out = e2;
}

// The force loop's members of one particle without artificial viscosity, pairwise hourglass
// spring or XSPH (forcesDim): Eq. 2.76 into f, Eq. 2.68 into Fdot.
template <int D, bool kStoredReverse>
PORESPH_MEMBER_CLONES void forceMembers(std::int64_t q0, std::int64_t q1, const std::int32_t* fam,
                                        const Index* idx, const double* V0, const double* G,
                                        const double* GR, const std::int32_t* revSlot,
                                        const std::int64_t* off, const std::int32_t* row,
                                        const double* Pf, const double* v, const double* PiIn,
                                        const double* viIn, double* fOut, double* FdotOut) {
  const Mat<D> Pi = Eigen::Map<const Mat<D>>(PiIn);
  const Vec<D> vi = Eigen::Map<const Vec<D>>(viIn);
  Vec<D> f = Vec<D>::Zero();
  Mat<D> Fdot = Mat<D>::Zero();
  for (std::int64_t q = q0; q < q1; ++q) {
    const Index j = idx[fam[q]];
    const double Vj = V0[j];  // m_j / rho0_j
    const Vec<D> g = Eigen::Map<const Vec<D>>(G + q * D);
    const double* grp;
    if constexpr (kStoredReverse)
      grp = GR + q * D;
    else
      grp = G + (off[row[j]] + revSlot[q]) * D;
    const Vec<D> gr = Eigen::Map<const Vec<D>>(grp);
    // P_b read in place: a copy (const Mat<D> Pj = ...) went through the stack, and the product
    // then loaded a pair of coefficients that straddled two of the copy's stores, which the
    // processor cannot forward: the force loop's largest stall on the thesis-size scene (44 % of
    // its samples at the add after that load, perf annotate). The same coefficients and products.
    const Eigen::Map<const Mat<D>> Pj(Pf + j * D * D);
    f.noalias() += Vj * (Pi * g - Pj * gr);  // 2.76 (times m_a / V_a = rho0_a)
    const Vec<D> vji = Eigen::Map<const Vec<D>>(v + j * D) - vi;
    Fdot.noalias() += Vj * vji * g.transpose();  // 2.68
  }
  Eigen::Map<Vec<D>>{fOut} = f;
  Eigen::Map<Mat<D>>{FdotOut} = Fdot;
}

// The deformation gradient of one particle, Eq. 2.67 (kinematicsDim).
template <int D>
PORESPH_MEMBER_CLONES void defGradMembers(const PairImage im, Index i, std::int64_t q0,
                                          std::int64_t q1, const std::int32_t* fam,
                                          const Index* idx, const double* V0, const double* G,
                                          const double* u, double* Fout) {
  const Vec<D> ui = Eigen::Map<const Vec<D>>(u + i * D);
  Mat<D> Fi = Mat<D>::Identity();
  for (std::int64_t q = q0; q < q1; ++q) {
    const Index j = idx[fam[q]];
    const double Vj = V0[j];  // m_j / rho0_j
    const Vec<D> g = Eigen::Map<const Vec<D>>(G + q * D);
    Vec<D> d = Eigen::Map<const Vec<D>>(u + j * D) - ui;
    im.apply<D>(d);
    Fi.noalias() += Vj * d * g.transpose();  // 2.67
  }
  Eigen::Map<Mat<D>>{Fout} = Fi;
}

constexpr unsigned kInternal = kFieldCheckpoint;  // state that is neither output nor ghosted

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// The loads' ramp_time: libcore linearRamp / linearRampRate (libcore/time_schedule.hpp).

// Isotropic law sigma = lambda tr(eps) 1 + 2 mu eps (Eqs. 2.74, 2.84 in Lame form: k = lambda +
// 2 mu / 3 in 3D; in 1D and plane stress lambda is the reduced one, see lameParameters()).
template <int D>
Mat<D> isotropicLaw(const Mat<D>& eps, double lambda, double mu) {
  return lambda * eps.trace() * Mat<D>::Identity() + 2.0 * mu * eps;
}

/// "file:line: key ...: " before a message about a scene entry (empty when set up in code).
std::string prefix(const std::string& where) { return where.empty() ? std::string() : where + ": "; }
}  // namespace

void lameParameters(double E, double nu, int dim, Plane plane, double& lambda, double& mu) {
  if (dim == 1) {  // uniaxial stress: sigma = E eps
    lambda = 0.0;
    mu = 0.5 * E;
    return;
  }
  mu = E / (2.0 * (1.0 + nu));
  lambda = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  if (dim == 2 && plane == Plane::Stress) lambda = 2.0 * lambda * mu / (lambda + 2.0 * mu);
}

// ------------------------------------------------------------------------------------------------
// configure: materials, boundary conditions, fields
// ------------------------------------------------------------------------------------------------
ModuleSettings ElasticSolidModule::settings() const {
  ModuleSettings out;
  const char* form = formulation_ == Formulation::SmallStrainStress ? "small_strain_stress"
                     : formulation_ == Formulation::SmallStrainDisplacement
                         ? "small_strain_displacement"
                         : "total_lagrangian";
  for (const ElasticMaterial& e : mats_) {
    const std::string m = "materials." + e.name + ".";
    out.push_back({m + "formulation", form, "total_lagrangian"});
    if (dim_ == 2) out.push_back({m + "plane", plane_ == Plane::Stress ? "stress" : "strain", "strain"});
    if (e.law.type == solid::DamageLawType::Elastic) continue;
    out.push_back({m + "damage.law", solid::damageLawName(e.law.type)});
    out.push_back({m + "damage.split",
                   e.law.splitType == solid::EnergySplit::Spectral ? "spectral" : "volumetric",
                   "volumetric"});
    if (e.law.type == solid::DamageLawType::RankineMohrCoulomb)
      out.push_back({m + "damage.tensile_measure",
                     e.law.tensileMeasure == solid::TensileMeasure::Stress ? "stress" : "strain",
                     "strain"});
  }
  if (anyHourglass_)
    out.push_back({"solid.hourglass_form", hourglassConservative_ ? "conservative" : "pairwise",
                   "conservative"});
  if (anyDamage_)
    out.push_back({"solid.damage_commit", commitAtEvaluation_ ? "evaluation" : "step_end",
                   "step_end"});
  // The solid's own kernel width (kernel-affecting); "kernel": the scene's h.
  out.push_back({"solid.smoothing_length", ownH_ > 0.0 ? settingNumber(ownH_) : "kernel", "kernel"});
  return out;
}

void ElasticSolidModule::configure(Simulation& sim, const std::vector<const Material*>& materials,
                                   const ParameterSet* section) {
  const int dim = sim.dimension();
  dim_ = dim;
  if (materials.empty()) throw InputError("solid module: no material with model 'elastic'");
  mats_.clear();
  slot_.assign(std::max<size_t>(sim.materials.size(), 1), -1);
  bool first = true;
  for (const Material* m : materials) {
    const ParameterSet& p = m->parameters;
    ElasticMaterial e;
    e.materialId = m->id;
    e.name = m->name;
    e.density = p.real("density", Range::positive());
    e.young = p.real("young_modulus", Range::positive());
    const Range nuRange{-1.0, 0.5, true, true};
    e.poisson = dim == 1 ? p.real("poisson_ratio", 0.0, nuRange) : p.real("poisson_ratio", nuRange);
    const std::string f = p.choice("formulation", "total_lagrangian",
                                   {"small_strain_stress", "small_strain_displacement",
                                    "total_lagrangian"});
    const Formulation form = f == "small_strain_stress" ? Formulation::SmallStrainStress
                             : f == "small_strain_displacement"
                                 ? Formulation::SmallStrainDisplacement
                                 : Formulation::TotalLagrangian;
    Plane pl = Plane::Strain;
    if (dim == 2) {
      pl = p.choice("plane", "strain", {"strain", "stress"}) == "stress" ? Plane::Stress
                                                                         : Plane::Strain;
    } else if (p.has("plane")) {
      p.fail("plane", "plane strain/stress applies to 2D runs only (this run is " +
                          std::to_string(dim) + "D)");
    }
    if (first) {
      formulation_ = form;
      plane_ = pl;
      formulationWhere_ = p.where("formulation");
    } else if (form != formulation_ || pl != plane_) {
      p.fail("formulation", "all elastic materials of a run must use the same formulation and "
                            "plane assumption");
    }
    first = false;
    if (p.has("artificial_viscosity")) {
      const ParameterSet av = p.section("artificial_viscosity");
      e.avAlpha = av.real("alpha", 0.0, Range::nonNegative());
      e.avBeta = av.real("beta", 0.0, Range::nonNegative());
      av.finish();
    }
    e.xsph = p.real("xsph_epsilon", 0.0, Range::closed(0.0, 1.0));
    e.damping = p.real("damping", 0.0, Range::nonNegative());
    e.hourglass = p.real("hourglass", 0.0, Range::closed(0.0, 1000.0));
    if (e.hourglass > 0.0 && form != Formulation::TotalLagrangian)
      p.fail("hourglass", "hourglass control is for the total_lagrangian formulation only");
    // Wetting of the solid's surface by the fluids (Eq. 1.10: its colour is cos(theta)); what
    // the fluid reads from libcore, so contact angles hold on walls that deform and move.
    const double theta = p.real("contact_angle", 90.0, Range::closed(0.0, 180.0));
    sim.materials[static_cast<size_t>(m->id)].wettingCos = std::cos(theta * M_PI / 180.0);
    sim.materials[static_cast<size_t>(m->id)].phase = kPhaseSolid;
    const bool hasDamage = p.has("damage");
    const ParameterSet damage = hasDamage ? p.section("damage") : ParameterSet();
    p.finish();
    lameParameters(e.young, e.poisson, dim, pl, e.lambda, e.mu);
    // constitutive law (physics/solid/constitutive_law.hpp): bulk/deviator split of dimension 3
    // in 3D and plane strain, 2 in plane stress, 1 in 1D
    e.law = ConstitutiveLaw(e.young, e.lambda, e.mu,
                            dim == 3 || (dim == 2 && pl == Plane::Strain) ? 3 : dim);
    if (hasDamage) {
      if (form == Formulation::SmallStrainDisplacement)
        p.fail("damage", "the displacement-based form (Eqs. 2.89-2.90) has no stress to degrade; "
                         "use formulation total_lagrangian or small_strain_stress with damage");
      e.law.configureDamage(damage);
      anyDamage_ = true;
    }
    if (form == Formulation::SmallStrainDisplacement && e.lambda > e.mu * (1.0 + 1e-12))
      p.fail("poisson_ratio",
             "the displacement-based form (Eqs. 2.89-2.90) is a sum of pair terms whose "
             "transverse part (mu - lambda) u_ab turns anti-restoring when lambda > mu, and runs "
             "blow up (measured: nu = 0.3 in plane strain diverges within 400 steps); it needs "
             "nu <= 0.25 (3D, plane strain) or nu <= 1/3 (plane stress). Use formulation "
             "small_strain_stress or total_lagrangian for this material");
    e.waveSpeed = std::sqrt(e.law.waveModulus() / e.density);  // 2.50 (bounds damaged states)
    sim.materials[static_cast<size_t>(m->id)].waveSpeed = e.waveSpeed;  // for contact pairs
    if (static_cast<size_t>(m->id) >= slot_.size()) slot_.resize(static_cast<size_t>(m->id) + 1, -1);
    slot_[static_cast<size_t>(m->id)] = static_cast<int>(mats_.size());
    mats_.push_back(e);
  }

  boundaries_.clear();
  anyMirror_ = false;
  anyPartial_ = false;
  if (section) {
    if (section->has("boundaries")) {
      int k = 0;
      for (const ParameterSet& b : section->sectionList("boundaries")) {
        Boundary bc;
        const std::string t = b.choice(
            "type", {"clamped", "velocity", "displacement", "traction", "pressure", "symmetry"});
        bc.type = t == "clamped" ? BoundaryType::Clamped
                  : t == "symmetry" ? BoundaryType::Symmetry
                  : t == "velocity" ? BoundaryType::Velocity
                  : t == "displacement" ? BoundaryType::Displacement
                  : t == "traction" ? BoundaryType::Traction
                                    : BoundaryType::Pressure;
        bc.label = b.string("name", "boundary " + std::to_string(k));
        bc.where = b.where(b.has("box") ? "box" : b.has("shell") ? "shell" : "material");
        if (b.has("box")) {
          const ParameterSet box = b.section("box");
          const auto lo = box.reals("min", static_cast<size_t>(dim));
          const auto hi = box.reals("max", static_cast<size_t>(dim));
          box.finish();
          bc.hasBox = true;
          for (int a = 0; a < dim; ++a) {
            bc.boxMin[static_cast<size_t>(a)] = lo[static_cast<size_t>(a)];
            bc.boxMax[static_cast<size_t>(a)] = hi[static_cast<size_t>(a)];
          }
        }
        if (b.has("material")) {
          const std::string mn = b.string("material");
          for (const auto& m : sim.materials)
            if (m.name == mn) bc.material = m.id;
          if (bc.material < 0) b.fail("material", "no material of that name in the scene");
        }
        if (b.has("shell")) {
          const ParameterSet sh = b.section("shell");
          const auto c = sh.reals("centre", static_cast<size_t>(dim));
          bc.shellMin = sh.real("r_min", Range::nonNegative());
          bc.shellMax = sh.real("r_max", Range::positive());
          sh.finish();
          bc.hasShell = true;
          for (int a = 0; a < dim; ++a) bc.shellCentre[static_cast<size_t>(a)] = c[static_cast<size_t>(a)];
        }
        if (!bc.hasBox && !bc.hasShell && bc.material < 0)
          b.fail("type", "a boundary needs a 'box' {min, max}, a 'shell' {centre, r_min, r_max} "
                         "and/or a 'material' to select its particles");
        auto vec = [&](const std::string& key) {
          const auto v = b.reals(key, static_cast<size_t>(dim));
          for (int a = 0; a < dim; ++a) bc.value[static_cast<size_t>(a)] = v[static_cast<size_t>(a)];
        };
        if (bc.type == BoundaryType::Velocity) vec("velocity");
        if (bc.type == BoundaryType::Displacement) vec("displacement");
        if (bc.type == BoundaryType::Traction) vec("traction");
        if (bc.type == BoundaryType::Pressure) bc.pressure = b.real("pressure");
        bc.rampTime = b.real("ramp_time", 0.0, Range::nonNegative());
        if (b.has("components")) {
          // Per-component imposed motion (a roller: u.e2 imposed, sigma.n.e1 = 0; thesis Eq.
          // 4.31): only the listed axes are imposed, the others are free.
          if (bc.type != BoundaryType::Velocity && bc.type != BoundaryType::Displacement)
            b.fail("components", "only velocity and displacement boundaries impose components "
                                 "(a roller support is {type: velocity, velocity: [0, 0], "
                                 "components: [y]})");
          const YAML::Node list = b.raw("components");
          if (!list.IsSequence() || list.size() == 0)
            b.fail("components", "a non-empty list of axes, e.g. [y] or [x, z]");
          bc.imposed = {false, false, false};
          for (const auto& item : list) {
            const std::string axis = item.IsScalar() ? item.as<std::string>() : std::string("?");
            int a = axis == "x" ? 0 : axis == "y" ? 1 : axis == "z" ? 2 : -1;
            if (a < 0 || a >= dim)
              b.fail("components", "'" + axis + "' is not an axis of this " + std::to_string(dim) +
                                       "D run (use x" + std::string(dim > 1 ? ", y" : "") +
                                       std::string(dim > 2 ? ", z" : "") + ")");
            if (bc.imposed[static_cast<size_t>(a)])
              b.fail("components", "axis '" + axis + "' is listed twice");
            bc.imposed[static_cast<size_t>(a)] = true;
          }
          for (int a = 0; a < dim; ++a)
            if (!bc.imposed[static_cast<size_t>(a)] && bc.value[static_cast<size_t>(a)] != 0.0)
              b.fail(bc.type == BoundaryType::Velocity ? "velocity" : "displacement",
                     "component " + std::to_string(a) + " is free (not in 'components') and must "
                     "be 0, not " + fmt(bc.value[static_cast<size_t>(a)]));
          for (int a = 0; a < dim; ++a) bc.partial = bc.partial || !bc.imposed[static_cast<size_t>(a)];
        }
        if (bc.type == BoundaryType::Displacement && !(bc.rampTime > 0.0))
          b.fail("ramp_time", "an imposed displacement needs ramp_time > 0 (the velocity is "
                              "displacement / ramp_time during the ramp)");
        if (b.has("area")) {
          if (bc.type != BoundaryType::Traction)
            b.fail("area", "only traction boundaries take an area per particle (pressure areas "
                           "come from the kernel)");
          bc.area = b.real("area", Range::positive());
        }
        if (b.has("mirror")) {
          if (bc.type != BoundaryType::Clamped && bc.type != BoundaryType::Symmetry)
            b.fail("mirror", "a mirror layer is a clamped or symmetry boundary");
          const ParameterSet mp = b.section("mirror");
          const auto pt = mp.reals("point", static_cast<size_t>(dim));
          const auto nr = mp.reals("normal", static_cast<size_t>(dim));
          mp.finish();
          double nn = 0.0;
          for (int a = 0; a < dim; ++a) nn += nr[static_cast<size_t>(a)] * nr[static_cast<size_t>(a)];
          if (!(nn > 0.0)) b.fail("mirror", "the mirror normal must not be zero");
          bc.mirror = true;
          for (int a = 0; a < dim; ++a) {
            bc.mirrorPoint[static_cast<size_t>(a)] = pt[static_cast<size_t>(a)];
            bc.mirrorNormal[static_cast<size_t>(a)] = nr[static_cast<size_t>(a)] / std::sqrt(nn);
          }
          anyMirror_ = true;
        }
        if (bc.type == BoundaryType::Symmetry && !bc.mirror)
          b.fail("type", "a symmetry boundary needs its plane: mirror: {point: [..], normal: [..]}");
        b.finish();
        anyPartial_ = anyPartial_ || bc.partial;
        boundaries_.push_back(bc);
        ++k;
      }
    }
    if (section->has("initial_velocity")) {
      // standing-wave initial velocity v = amplitude sin(k . X) on the free particles
      const ParameterSet w = section->section("initial_velocity");
      const auto A = w.reals("amplitude", static_cast<size_t>(dim));
      const auto k = w.reals("wavevector", static_cast<size_t>(dim));
      w.finish();
      hasWave_ = true;
      for (int a = 0; a < dim; ++a) {
        waveAmplitude_[static_cast<size_t>(a)] = A[static_cast<size_t>(a)];
        waveVector_[static_cast<size_t>(a)] = k[static_cast<size_t>(a)];
      }
    }
    if (section->has("smoothing_length")) {
      // the solid's own h (issue 13: the damage regularisation 2h set apart from the fluid's)
      ownH_ = section->real("smoothing_length", Range::positive());
      if (formulation_ != Formulation::TotalLagrangian)
        section->fail("smoothing_length", "a solid smoothing length of its own needs the "
                                          "total_lagrangian formulation (the small-strain forms "
                                          "use the run's neighbour lists)");
    }
    // TL reference family: `fast` keeps both corrected gradients g_ab and g_ba per member
    // (2 D doubles, read in sequence), `compact` keeps g_ab and the slot of b's own entry for a
    // (D doubles + one int: 2.1 kB less per particle in 3D at ~106 members, but the force loop
    // then gathers g_ba from b's row: +43 % in the TL force loop, measured on the Ketton crop).
    if (section->has("family_storage")) {
      compactFamily_ = section->choice("family_storage", "fast", {"fast", "compact"}) == "compact";
      if (compactFamily_ && formulation_ != Formulation::TotalLagrangian)
        section->fail("family_storage", "a reference family exists only with the "
                                        "total_lagrangian formulation");
    }
    // Hourglass control (docs/solid.md): `conservative` (default) derives the force from a
    // penalty energy (a stored energy, in the balance); `pairwise` is Ganzenmueller's (2015)
    // projected pair spring, not a gradient: its power is counted as dissipation.
    if (section->has("hourglass_form")) {
      hourglassConservative_ =
          section->choice("hourglass_form", "conservative", {"conservative", "pairwise"}) ==
          "conservative";
      if (formulation_ != Formulation::TotalLagrangian)
        section->fail("hourglass_form", "hourglass control is for the total_lagrangian "
                                        "formulation only");
    }
    // Where D is committed (docs/damage.md "The commit lag"): `step_end` (default) after the
    // step, the stored acceleration keeping D^n for the next half kick (an O(dt) lag);
    // `evaluation` at every rate evaluation before the stress (a^{n+1} with D^{n+1}).
    if (section->has("damage_commit")) {
      commitAtEvaluation_ =
          section->choice("damage_commit", "step_end", {"step_end", "evaluation"}) == "evaluation";
      if (!anyDamage_)
        section->fail("damage_commit", "no elastic material of the run has a `damage:` law");
    }
    if (section->has("gravity")) {
      const auto g = section->reals("gravity", static_cast<size_t>(dim));
      for (int a = 0; a < dim; ++a) gravity_[static_cast<size_t>(a)] = g[static_cast<size_t>(a)];
      hasGravity_ = false;
      for (int a = 0; a < dim; ++a) hasGravity_ = hasGravity_ || g[static_cast<size_t>(a)] != 0.0;
    }
    section->finish();
  }

  // ---- fields ----
  ParticleStore& s = sim.store;
  const std::string me = "solid";
  refPos_ = s.addReal("reference_position", dim, kFieldDefault, me);
  disp_ = s.addReal("displacement", dim, kFieldOutput | kFieldToGhosts, me);
  strain_ = s.addReal("strain", dim * dim, kFieldOutput, me);
  stress_ = s.addReal("stress", dim * dim, kFieldDefault, me);
  energy_ = s.addReal("internal_energy", 1, kFieldOutput | kFieldCheckpoint, me);
  energyRate_ = s.addReal("internal_energy_rate", 1, kFieldNone, me);
  work_ = s.addReal("solid_work", 3, kFieldCheckpoint, me);
  workRate_ = s.addReal("solid_work_rate", 3, kFieldNone, me);
  bc_ = s.addInt("solid_boundary", 1, kFieldOutput | kFieldCheckpoint, me);
  bcForce_ = s.addReal("solid_boundary_force", dim, kInternal, me);
  if (anyMirror_) mirror_ = s.addInt("solid_mirror_source", 1, kInternal, me);
  if (anyDamage_) {
    damage_ = s.addReal("damage", 1, kFieldOutput | kFieldCheckpoint, me);
    damageReleased_ = s.addReal("damage_dissipation", 1, kFieldCheckpoint, me);
    damageDegradable_ = s.addReal("damage_degradable_energy", 1, kFieldCheckpoint, me);
    bool history = false;
    for (const auto& e : mats_) history = history || e.law.type == DamageLawType::RankineMohrCoulomb;
    if (history) damageHistory_ = s.addReal("damage_history", kDamageHistory, kFieldCheckpoint, me);
  }
  if (formulation_ == Formulation::TotalLagrangian) {
    // Periodic domains: the reference families are built with periodic images at initialise()
    // (minimum-image separations); a period shorter than two supports is refused there.
    defGrad_ = s.addReal("deformation_gradient", dim * dim, kFieldDefault, me);
    piola_ = s.addReal("first_piola", dim * dim, kFieldNone, me);
    anyHourglass_ = false;
    for (const auto& e : mats_) anyHourglass_ = anyHourglass_ || e.hourglass > 0.0;
    // the penalty energy density of the conservative hourglass control (per unit reference
    // volume), written by forces() at the evaluation's positions
    if (anyHourglass_ && hourglassConservative_)
      hgEnergy_ = s.addReal("solid_hourglass_energy", 1, kFieldOutput, me);
  } else {
    densityRate_ = s.addReal("density_rate", 1, kFieldNone, me);
    corrFields_ = registerCorrectionFields(s, "solid_correction", me);
    sim.addIntegrated(s.density(), densityRate_, false);
  }
  bool anyXsph = false;
  for (const auto& m : mats_) anyXsph = anyXsph || m.xsph > 0.0;
  if (anyXsph) {
    // XSPH (2.66) moves the particles with the corrected velocity v^ = v + dv^: the correction
    // dv^ is a second rate of the positions, advanced by the integrator like any other field.
    xsph_ = sim.positionCorrection();  // the core field every module adds into
  }
  sim.addIntegrated(energy_, energyRate_, false);
  sim.addIntegrated(work_, workRate_, false);
}

// ------------------------------------------------------------------------------------------------
// initialise: reference state, boundary sets, reference family (TL)
// ------------------------------------------------------------------------------------------------
const Kernel& ElasticSolidModule::solidKernel(const Simulation& sim) const {
  return ownH_ > 0.0 ? kernel_ : sim.kernel;
}

void ElasticSolidModule::initialise(Simulation& sim) {
  if (ownH_ > 0.0) kernel_ = Kernel(sim.kernel.type(), sim.dimension(), ownH_);
  dispatchDimension(sim.dimension(), [&](auto d) { initialiseDim<decltype(d)::value>(sim); });
  if (anyDamage_) {  // no commit yet: the first one releases with its own degradable energy
    double* phi = sim.store.data(damageDegradable_);
    std::fill(phi, phi + sim.store.realCount(), -1.0);
  }
  initialised_ = true;
}

template <int D>
void ElasticSolidModule::initialiseDim(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  if (s.ghostCount() != 0) s.clearGhosts();
  const std::int32_t* mat = s.data(s.material());
  std::int32_t* phase = s.data(s.phase());
  std::int32_t* motion = s.data(sim.motion);
  double* m = s.data(s.mass());
  double* rho = s.data(s.density());
  double* v = s.data(s.velocity());
  const double* x = s.data(s.position());
  double* X = s.data(refPos_);
  std::int32_t* bc = s.data(bc_);
  const double volumeUnit = std::pow(sim.spacing, D);

  std::vector<Index> mine;
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0) continue;
    mine.push_back(i);
    const ElasticMaterial& e = mats_[static_cast<size_t>(k)];
    phase[i] = kPhaseSolid;
    if (!(rho[i] > 0.0)) rho[i] = e.density;
    if (!(m[i] > 0.0)) {
      if (!(sim.spacing > 0.0))
        throw InputError("solid module: particle masses are zero and the run has no spacing to "
                         "derive them from (set Simulation::spacing or the masses)");
      m[i] = e.density * volumeUnit;
    }
    for (int a = 0; a < D; ++a) X[i * D + a] = x[i * D + a];
  }

  // Boundary sets, selected in the reference configuration; the last matching boundary wins.
  for (Index i : mine) {
    bc[i] = 0;
    for (size_t b = 0; b < boundaries_.size(); ++b) {
      const Boundary& B = boundaries_[b];
      bool in = true;
      if (B.material >= 0 && mat[i] != B.material) in = false;
      if (B.hasBox)
        for (int a = 0; a < D; ++a)
          if (X[i * D + a] < B.boxMin[static_cast<size_t>(a)] ||
              X[i * D + a] > B.boxMax[static_cast<size_t>(a)])
            in = false;
      if (B.hasShell) {
        double r2 = 0.0;
        for (int a = 0; a < D; ++a) {
          const double d = X[i * D + a] - B.shellCentre[static_cast<size_t>(a)];
          r2 += d * d;
        }
        const double r = std::sqrt(r2);
        if (r < B.shellMin || r > B.shellMax) in = false;
      }
      if (in) bc[i] = static_cast<std::int32_t>(b + 1);
    }
    if (bc[i] > 0) {
      const Boundary& B = boundaries_[static_cast<size_t>(bc[i] - 1)];
      if (B.type == BoundaryType::Clamped || B.type == BoundaryType::Symmetry) {
        motion[i] = kMotionFixed;  // driven by the module (mirror images) or at rest
        for (int a = 0; a < D; ++a) v[i * D + a] = 0.0;
      } else if (B.type == BoundaryType::Velocity || B.type == BoundaryType::Displacement) {
        // all components imposed: prescribed; some free (roller): integrated, the imposed
        // components are set by constraints()
        motion[i] = B.partial ? kMotionFree : kMotionPrescribed;
      }
    }
  }
  for (size_t b = 0; b < boundaries_.size(); ++b) {
    Index count = 0;
    for (Index i : mine) count += bc[i] == static_cast<std::int32_t>(b + 1);
    if (count == 0)
      throw InputError(prefix(boundaries_[b].where) + "solid module: boundary '" + boundaries_[b].label +
                       "' selects no solid particle (check its box/material)");
  }

  if (hasWave_)
    for (Index i : mine) {
      if (motion[i] != kMotionFree) continue;
      double phase = 0.0;
      for (int a = 0; a < D; ++a) phase += waveVector_[static_cast<size_t>(a)] * X[i * D + a];
      for (int a = 0; a < D; ++a) v[i * D + a] = waveAmplitude_[static_cast<size_t>(a)] * std::sin(phase);
    }

  // Mirror layers: the source of each layer particle is the solid particle (not in a boundary
  // set) nearest to its reflection; it must coincide with it (the layer mirrors the body).
  if (anyMirror_) {
    std::int32_t* src = s.data(mirror_);
    const std::int32_t* ids = s.data(s.id());
    std::vector<Index> srcIndex(static_cast<size_t>(n), -1);
    for (Index i : mine) src[i] = 0;
    for (Index i : mine) {
      if (bc[i] == 0) continue;
      const Boundary& B = boundaries_[static_cast<size_t>(bc[i] - 1)];
      if (!B.mirror) continue;
      Vec<D> p, nrm, Xi = Eigen::Map<const Vec<D>>(X + i * D);
      for (int a = 0; a < D; ++a) {
        p[a] = B.mirrorPoint[static_cast<size_t>(a)];
        nrm[a] = B.mirrorNormal[static_cast<size_t>(a)];
      }
      const Vec<D> Xr = Xi - 2.0 * (Xi - p).dot(nrm) * nrm;
      double best = std::numeric_limits<double>::infinity();
      Index arg = -1;
      for (Index j : mine) {
        if (bc[j] == bc[i]) continue;  // another set may be the image (corners of two planes)
        const double d2 = (Eigen::Map<const Vec<D>>(X + j * D) - Xr).squaredNorm();
        if (d2 < best) { best = d2; arg = j; }
      }
      if (arg < 0 || std::sqrt(best) > 0.1 * sim.spacing) {
        std::ostringstream msg;
        msg << prefix(B.where) << "solid module: mirror boundary '" << B.label << "': the layer particle at "
            << Xi.transpose() << " has no solid particle at its mirror image " << Xr.transpose()
            << " (the layer must mirror the body's particle arrangement across the plane)";
        throw InputError(msg.str());
      }
      src[i] = ids[arg] + 1;
      srcIndex[static_cast<size_t>(i)] = arg;
    }
    for (Index i : mine) {
      const Index j = srcIndex[static_cast<size_t>(i)];
      if (j >= 0 && src[j] > 0 && src[srcIndex[static_cast<size_t>(j)]] > 0)
        throw InputError("solid module: mirror layers chained more than twice (the image of an "
                         "image of a layer particle is again a layer particle)");
    }
    // A layer thinner than twice the support leaves the layer particles next to the body with a
    // truncated support: the images are then not exact and energy is not conserved.
    for (size_t b = 0; b < boundaries_.size(); ++b) {
      const Boundary& B = boundaries_[b];
      if (!B.mirror) continue;
      double depth = 0.0;
      for (Index i : mine) {
        if (bc[i] != static_cast<std::int32_t>(b + 1)) continue;
        double d = 0.0;
        for (int a = 0; a < D; ++a)
          d += (B.mirrorPoint[static_cast<size_t>(a)] - X[i * D + a]) * B.mirrorNormal[static_cast<size_t>(a)];
        depth = std::max(depth, std::abs(d));
      }
      if (depth < 2.0 * solidKernel(sim).support() - sim.spacing)
        throw InputError(prefix(B.where) + "solid module: mirror boundary '" + B.label + "' is " + fmt(depth) +
                         " m deep; it must be at least twice the kernel support (" +
                         fmt(2.0 * solidKernel(sim).support()) + " m) deep");
    }
  }

  // Reference neighbours (among the solid particles only).
  const Index nm = static_cast<Index>(mine.size());
  std::vector<double> Xm(static_cast<size_t>(nm * D));
  for (Index k = 0; k < nm; ++k)
    for (int a = 0; a < D; ++a) Xm[static_cast<size_t>(k * D + a)] = X[mine[static_cast<size_t>(k)] * D + a];
  // Periodic axes: images of the particles within a support of a periodic face (shifted by
  // +-period, edges and corners included) join the search, so that a reference family crosses
  // the face; `origin` maps an image back to its particle. Families use minimum-image
  // separations, which needs a period of at least two supports where a family crosses a face.
  const double support = solidKernel(sim).support();
  period_ = {0.0, 0.0, 0.0};
  for (int a = 0; a < D; ++a)
    if (sim.domain.periodic[static_cast<size_t>(a)]) period_[static_cast<size_t>(a)] = sim.domain.length(a);
  std::vector<Index> origin;
  {
    const Index images = appendPeriodicImages<D>(sim.domain, support, Xm, origin);
    for (int a = 0; a < D; ++a)
      if (images > 0 && period_[static_cast<size_t>(a)] > 0.0 &&
          period_[static_cast<size_t>(a)] < 2.0 * support)
        throw InputError(prefix(formulationWhere_) +
                         "solid module: the total_lagrangian reference families cross a periodic "
                         "face of axis " + std::to_string(a) + ", whose period " +
                         fmt(period_[static_cast<size_t>(a)]) + " m is shorter than two kernel "
                         "supports (" + fmt(2.0 * support) + " m): a family would hold a "
                         "particle and its own image");
  }
  const Index nx = static_cast<Index>(origin.size());
  NeighbourSearch search;
  NeighbourList ref;
  if (nm > 0) search.build(Xm.data(), D, nm, nx, support, ref);
  auto volume = [&](Index i) { return m[i] / mats_[static_cast<size_t>(slotOf(mat[i]))].density; };
  const Kernel& W = solidKernel(sim);

  // Corrected reference gradients g_ab = grad~_{a,0} W~_{ab,0} (mixed correction 2.63b, computed
  // by libcore/corrections on the reference positions of the solid particles).
  std::vector<double> Vm(static_cast<size_t>(nx));
  for (Index k = 0; k < nx; ++k)
    Vm[static_cast<size_t>(k)] = volume(mine[static_cast<size_t>(origin[static_cast<size_t>(k)])]);
  CorrectionBuffer buffer;
  buffer.resize(D, nm);
  if (nm > 0)
    computeCorrection<D>(Correction::Mixed, W, Xm.data(), Vm.data(), nm, ref, buffer.arrays());
  const CorrectionView view = buffer.view(Correction::Mixed, W);
  // Corrected gradient of the pair (k, ref entry p) from both ends, computed where needed (no
  // per-pair table: a table of both gradients was the largest allocation of a 3D start, ~3.4 kB
  // per solid particle on top of the family itself):
  //   g_ab = grad~_a W~ at a = k with r = X_a - X_b,  g_ba = grad~_b W~ at b = origin with -r.
  // (-r is exact and grad W(-r) = -grad W(r) bitwise, so g_ba equals what b's own row holds.)
  auto forward = [&](Index k, std::int64_t p) {
    const Index kx = ref.index[static_cast<size_t>(p)];  // a particle or an image
    const Vec<D> r = Eigen::Map<const Vec<D>>(Xm.data() + k * D) -
                     Eigen::Map<const Vec<D>>(Xm.data() + kx * D);
    return view.gradient<D>(k, W.gradient<D>(r), W.value(r.norm()));
  };
  auto backward = [&](Index k, std::int64_t p) {
    const Index kx = ref.index[static_cast<size_t>(p)];
    const Vec<D> r = Eigen::Map<const Vec<D>>(Xm.data() + kx * D) -
                     Eigen::Map<const Vec<D>>(Xm.data() + k * D);
    return view.gradient<D>(origin[static_cast<size_t>(kx)], W.gradient<D>(r), W.value(r.norm()));
  };
  // Imposed traction / pressure: nominal force per particle (reference configuration). The
  // outward normal of a pressure boundary is -grad(sum_b V_b W_ab) (the Shepard sum decreases
  // outwards).
  double* f = s.data(bcForce_);
  std::memset(f, 0, sizeof(double) * static_cast<size_t>(n * D));
  // s_a = V_a sum_b V_b (g_ab - g_ba) (libcore/consistent_load.hpp, Eq. 2.76), where needed.
  std::vector<double> unitLoad;
  if (std::any_of(boundaries_.begin(), boundaries_.end(),
                  [](const Boundary& B) { return B.type == BoundaryType::Pressure; }))
    unitLoad = consistentLoadVectors<D>(W, sim.domain, Xm.data(), Vm.data(), nm);
  for (Index k = 0; k < nm; ++k) {
    const Index i = mine[static_cast<size_t>(k)];
    if (bc[i] == 0) continue;
    const Boundary& B = boundaries_[static_cast<size_t>(bc[i] - 1)];
    if (B.type != BoundaryType::Traction && B.type != BoundaryType::Pressure) continue;
    const double area = B.area > 0.0 ? B.area : std::pow(sim.spacing, D - 1);
    Vec<D> force;
    if (B.type == BoundaryType::Traction) {
      for (int a = 0; a < D; ++a) force[a] = B.value[static_cast<size_t>(a)] * area;
    } else {
      // Consistent nodal load: the force that balances the discrete internal force (2.76) of a
      // uniform stress -p 1, f_a = p V_a sum_b V_b (g_ab - g_ba). It is non-zero only within a
      // support of a free surface; selecting the particles within one support of the loaded
      // surface applies the pressure there, and a body under uniform pressure on all its
      // surfaces is then in exact discrete equilibrium.
      force = B.pressure * Eigen::Map<const Vec<D>>(unitLoad.data() + k * D);
    }
    for (int a = 0; a < D; ++a) f[i * D + a] = force[a];
  }

  if (formulation_ != Formulation::TotalLagrangian) return;

  // ---- Total-Lagrangian reference family with corrected gradients (Eqs. 2.67-2.68) ----
  // The family is held by the module, not the store: compressed rows over the solid particles
  // only (row k of solid particle mine[k], members [famOffset_[k], famOffset_[k + 1])), found
  // through the per-particle int field solid_family_row (-1: not this module's particle), which
  // the store permutes with the particles. Fluid, wall and ghost particles hold 4 bytes instead
  // of a padded row of the largest family (docs/particle-store.md "Memory").
  int cap = 1;
  famOffset_.assign(static_cast<size_t>(nm) + 1, 0);
  for (Index k = 0; k < nm; ++k) {
    const auto c = ref.offset[static_cast<size_t>(k) + 1] - ref.offset[static_cast<size_t>(k)];
    cap = std::max<int>(cap, static_cast<int>(c));
    famOffset_[static_cast<size_t>(k) + 1] = famOffset_[static_cast<size_t>(k)] + c;
  }
  if (familyCapacity_ != 0 && familyCapacity_ != cap)
    throw std::logic_error("solid module: initialise() called twice with different families");
  familyCapacity_ = cap;
  const size_t members = static_cast<size_t>(famOffset_.back());
  familyRow_ = s.addInt("solid_family_row", 1, kInternal | kFieldConstant, "solid");
  famIds_.assign(members, 0);
  famG_.assign(members * D, 0.0);
  // The reverse gradient g_ba of a pair: stored (family_storage: fast) or found as b's own entry
  // for a by its slot in b's family (compact).
  if (compactFamily_) famRevSlot_.assign(members, 0);
  else famGR_.assign(members * D, 0.0);
  std::int32_t* row = s.data(familyRow_);
  std::fill(row, row + s.size(), -1);
  for (Index k = 0; k < nm; ++k) row[mine[static_cast<size_t>(k)]] = static_cast<std::int32_t>(k);
  std::int32_t* fam = famIds_.data();
  double* G = famG_.data();
  std::int32_t* revSlot = compactFamily_ ? famRevSlot_.data() : nullptr;
  double* GR = compactFamily_ ? nullptr : famGR_.data();
  const std::int32_t* ids = s.data(s.id());
  const std::int64_t* off = famOffset_.data();
  // Rows written in place, members in the order of their solid index b (fam holds b until the
  // last pass turns it into b's particle id), each with g_ab and g_ba.
#pragma omp parallel if (nm > 512)
  {
    std::vector<std::pair<Index, std::int64_t>> order;  // (b, ref entry), one row at a time
#pragma omp for schedule(static)
    for (Index k = 0; k < nm; ++k) {
      const auto b0 = ref.offset[static_cast<size_t>(k)], b1 = ref.offset[static_cast<size_t>(k) + 1];
      order.clear();
      for (auto p = b0; p < b1; ++p)
        order.emplace_back(origin[static_cast<size_t>(ref.index[static_cast<size_t>(p)])], p);
      std::sort(order.begin(), order.end());
      for (size_t q = 0; q < order.size(); ++q) {
        const std::int64_t at = off[k] + static_cast<std::int64_t>(q);
        fam[at] = static_cast<std::int32_t>(order[q].first);
        const Vec<D> g = forward(k, order[q].second);
        for (int a = 0; a < D; ++a) G[at * D + a] = g[a];
        if (GR) {
          const Vec<D> gr = backward(k, order[q].second);
          for (int a = 0; a < D; ++a) GR[at * D + a] = gr[a];
        }
      }
    }
  }
  // Compact: the slot of a in b's row (families are symmetric: same radius), then ids.
  if (revSlot) {
#pragma omp parallel for schedule(static) if (nm > 512)
    for (Index k = 0; k < nm; ++k) {
      for (std::int64_t q = off[k]; q < off[k + 1]; ++q) {
        const Index b = fam[q];
        const std::int32_t* first = fam + off[b];
        const std::int32_t* last = fam + off[b + 1];
        const std::int32_t* it = std::lower_bound(first, last, static_cast<std::int32_t>(k));
        if (it == last || *it != k)
          throw std::logic_error("solid module: reference family is not symmetric");
        revSlot[q] = static_cast<std::int32_t>(it - first);
      }
    }
  }
  // Hourglass control: the fastest mode it adds. A particle moving against its family (the
  // zero-energy pattern the control acts on) feels sum_b c_ab (u_a - u_b) with u_b = -u_a, i.e.
  // omega^2 = 2 sum_b k_ab V_b W0_ab / |X_ab|^2 / rho0_a; leapfrog needs omega dt < 2.
  // elasticTimeStepLimit() takes the smaller of Eq. 2.50 and 2 / omega (docs/solid.md).
  hourglassOmega2_ = 0.0;
  if (anyHourglass_) {
    const double* Xr = s.data(refPos_);
    double w2 = 0.0;
#pragma omp parallel for schedule(static) reduction(max : w2) if (nm > 512)
    for (Index k = 0; k < nm; ++k) {
      const Index i = mine[static_cast<size_t>(k)];
      const ElasticMaterial& e = mats_[static_cast<size_t>(slotOf(mat[i]))];
      double sum = 0.0;
      for (std::int64_t q = off[k]; q < off[k + 1]; ++q) {
        const Index j = mine[static_cast<size_t>(fam[q])];  // fam holds b until the pass below
        const ElasticMaterial& ej = mats_[static_cast<size_t>(slotOf(mat[j]))];
        double r2 = 0.0;
        for (int a = 0; a < D; ++a) {
          double d = Xr[j * D + a] - Xr[i * D + a];
          const double L = period_[static_cast<size_t>(a)];
          if (L > 0.0) d -= L * std::round(d / L);
          r2 += d * d;
        }
        if (r2 > 0.0)
          sum += 0.5 * (e.hourglass * e.young + ej.hourglass * ej.young) * volume(j) *
                 W.value(std::sqrt(r2)) / r2;
      }
      w2 = std::max(w2, 2.0 * sum / e.density);
    }
    hourglassOmega2_ = w2;
  }
  // family_storage fast, conservative hourglass control: the reference-state factor
  // W(|X_ab|) / |X_ab|^2 per member, computed as the pass computed it per member before (the same
  // minimum image, norm and kernel); 8 B per member (docs/performance.md "The rock scene's step")
  famHgW_.clear();
  if (anyHourglass_ && hourglassConservative_ && !compactFamily_) {
    famHgW_.assign(members, 0.0);
    double* hw = famHgW_.data();
    const double* Xr = s.data(refPos_);
    W.withFixedType<D>([&](const auto K) {
#pragma omp parallel for schedule(static) if (nm > 512)
      for (Index k = 0; k < nm; ++k) {
        const Index i = mine[static_cast<size_t>(k)];
        const Vec<D> Xi = Eigen::Map<const Vec<D>>(Xr + i * D);
        for (std::int64_t q = off[k]; q < off[k + 1]; ++q) {
          const Index j = mine[static_cast<size_t>(fam[q])];  // fam holds b until the pass below
          Vec<D> Xji = Eigen::Map<const Vec<D>>(Xr + j * D) - Xi;
          for (int a = 0; a < D; ++a) {
            const double L = period_[static_cast<size_t>(a)];
            if (L > 0.0 && std::abs(Xji[a]) >= 0.25 * L) Xji[a] -= L * std::round(Xji[a] / L);
          }
          const double r0 = Xji.norm();
          hw[q] = K.value(r0) / (r0 * r0);
        }
      }
    });
  }
#pragma omp parallel for schedule(static) if (nm > 512)
  for (Index k = 0; k < nm; ++k)
    for (std::int64_t q = off[k]; q < off[k + 1]; ++q)
      fam[q] = ids[mine[static_cast<size_t>(fam[q])]];
  // F = 1 at the start
  double* F = s.data(defGrad_);
  for (Index i : mine) Eigen::Map<Mat<D>>(F + i * D * D).setIdentity();
}

void ElasticSolidModule::rebuildIdMap(const Simulation& sim) {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* ids = s.data(s.id());
  std::int32_t maxId = 0;
  for (Index i = 0; i < n; ++i) maxId = std::max(maxId, ids[i]);
  if (idToIndex_.size() < static_cast<size_t>(maxId) + 1) idToIndex_.resize(static_cast<size_t>(maxId) + 1);
  std::fill(idToIndex_.begin(), idToIndex_.end(), Index(-1));
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) idToIndex_[static_cast<size_t>(ids[i])] = i;
}

void ElasticSolidModule::refreshReferenceVolumes(const Simulation& sim) {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* m = s.data(s.mass());
  if (refVolume_.size() < static_cast<size_t>(n)) refVolume_.resize(static_cast<size_t>(n));
  double* V0 = refVolume_.data();
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    V0[i] = k < 0 ? 0.0 : m[i] / mats_[static_cast<size_t>(k)].density;
  }
}

template <int D>
void ElasticSolidModule::applyMirrors(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* src = s.data(mirror_);
  double* u = s.data(disp_);
  double* v = s.data(s.velocity());
  double* x = s.data(s.position());
  const double* X = s.data(refPos_);
  const std::int32_t* bc = s.data(bc_);
  // pass 0: images that are body particles; pass 1: images that are themselves layer particles
  // (corners where two planes meet)
  for (int pass = 0; pass < 2; ++pass) {
#pragma omp parallel for schedule(static) if (n > 512)
    for (Index i = 0; i < n; ++i) {
      if (src[i] <= 0) continue;
      const Index j = idToIndex_[static_cast<size_t>(src[i] - 1)];
      if ((src[j] > 0) != (pass == 1)) continue;
      const Boundary& B = boundaries_[static_cast<size_t>(bc[i] - 1)];
      Vec<D> uj = Eigen::Map<const Vec<D>>(u + j * D), vj = Eigen::Map<const Vec<D>>(v + j * D);
      if (B.type == BoundaryType::Symmetry) {  // even reflection: R = 1 - 2 n n
        Vec<D> nrm;
        for (int a = 0; a < D; ++a) nrm[a] = B.mirrorNormal[static_cast<size_t>(a)];
        uj -= 2.0 * uj.dot(nrm) * nrm;
        vj -= 2.0 * vj.dot(nrm) * nrm;
      } else {  // clamp: odd reflection u(layer) = -u(image)
        uj = -uj;
        vj = -vj;
      }
      for (int a = 0; a < D; ++a) {
        u[i * D + a] = uj[a];
        v[i * D + a] = vj[a];
        x[i * D + a] = X[i * D + a] + uj[a];
      }
    }
  }
}

// ------------------------------------------------------------------------------------------------
// kinematics: displacements, F (TL) or correction data and strain (small strain)
// ------------------------------------------------------------------------------------------------
void ElasticSolidModule::kinematics(Simulation& sim) {
  if (!initialised_) throw std::logic_error("solid module: initialise() was not called");
  if (sim.dt > 0.0) {
    const double limit = elasticTimeStepLimit(sim);
    if (sim.dt > limit * (1.0 + 1e-12))
      throw InputError("solid module: time step dt = " + fmt(sim.dt) +
                       " s exceeds the elastic CFL limit h sqrt(rho/(lambda + 2 mu)) (or 2 / omega "
                       "of the hourglass control, the smaller) = " +
                       fmt(limit) + " s (thesis Eq. 2.50, h = " + fmt(solidKernel(sim).h()) +
                       " m); reduce dt or let the run choose it (adaptive stepping)");
  }
  // The step_end damage commit (damage.cpp) asks for F at x^{n+1}; the evaluation of the step
  // computed it there already unless something moved the solid since (a module's endOfStep, a
  // reorder): F is a function of the solid's positions only, so when they and the particle order
  // are the same bit for bit, F, the strain and the displacements of that evaluation are kept.
  if (reuseDeformationGradient_ && fValid_ && formulation_ == Formulation::TotalLagrangian &&
      sameSolidPositions(sim)) {
    ++fSkipped_;
    return;
  }
  dispatchDimension(sim.dimension(), [&](auto d) { kinematicsDim<decltype(d)::value>(sim); });
  if (formulation_ == Formulation::TotalLagrangian && anyDamage_ && !commitAtEvaluation_)
    recordSolidPositions(sim);
}

// Positions of this module's particles (packed in store order) and the ids of every real
// particle, at the last F (the reuse above). Both in parallel (issue 17: they were serial passes
// over every particle at each evaluation and step end): the rows in kSolidChunks fixed chunks,
// each chunk's solid particles counted, then packed at the chunk's place in store order (the
// same array as one pass in order).
namespace {
constexpr int kSolidChunks = 64;
}

void ElasticSolidModule::recordSolidPositions(const Simulation& sim) {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const int d = sim.dimension();
  const std::int32_t* mat = s.data(s.material());
  const double* x = s.data(s.position());
  const std::int32_t* ids = s.data(s.id());
  Index start[kSolidChunks + 1];
  start[0] = 0;
#pragma omp parallel for schedule(static)
  for (int c = 0; c < kSolidChunks; ++c) {
    Index k = 0;
    for (Index i = n * c / kSolidChunks; i < n * (c + 1) / kSolidChunks; ++i) k += slotOf(mat[i]) >= 0;
    start[c + 1] = k;
  }
  for (int c = 0; c < kSolidChunks; ++c) start[c + 1] += start[c];
  fIds_.resize(static_cast<size_t>(n));
  fPositions_.resize(static_cast<size_t>(start[kSolidChunks] * d));
  std::int32_t* fi = fIds_.data();
  double* fp = fPositions_.data();
#pragma omp parallel for schedule(static)
  for (int c = 0; c < kSolidChunks; ++c) {
    double* to = fp + start[c] * d;
    for (Index i = n * c / kSolidChunks; i < n * (c + 1) / kSolidChunks; ++i) {
      fi[i] = ids[i];
      if (slotOf(mat[i]) < 0) continue;
      for (int a = 0; a < d; ++a) *to++ = x[i * d + a];
    }
  }
  fValid_ = true;
}

bool ElasticSolidModule::sameSolidPositions(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const int d = sim.dimension();
  if (static_cast<size_t>(n) != fIds_.size()) return false;
  const std::int32_t* mat = s.data(s.material());
  const double* x = s.data(s.position());
  const std::int32_t* ids = s.data(s.id());
  const std::int32_t* fi = fIds_.data();
  Index start[kSolidChunks + 1];
  start[0] = 0;
  int differ = 0;
#pragma omp parallel for schedule(static) reduction(| : differ)
  for (int c = 0; c < kSolidChunks; ++c) {
    const Index i0 = n * c / kSolidChunks, i1 = n * (c + 1) / kSolidChunks;
    Index k = 0;
    if (i1 > i0 && std::memcmp(fi + i0, ids + i0, sizeof(std::int32_t) * static_cast<size_t>(i1 - i0)) != 0)
      differ = 1;
    for (Index i = i0; i < i1; ++i) k += slotOf(mat[i]) >= 0;
    start[c + 1] = k;
  }
  if (differ) return false;
  for (int c = 0; c < kSolidChunks; ++c) start[c + 1] += start[c];
  if (static_cast<size_t>(start[kSolidChunks] * d) != fPositions_.size()) return false;
  const double* fp = fPositions_.data();
#pragma omp parallel for schedule(static) reduction(| : differ)
  for (int c = 0; c < kSolidChunks; ++c) {
    const double* at = fp + start[c] * d;
    for (Index i = n * c / kSolidChunks; i < n * (c + 1) / kSolidChunks; ++i) {
      if (slotOf(mat[i]) < 0) continue;
      if (std::memcmp(at, x + i * d, sizeof(double) * static_cast<size_t>(d)) != 0) {
        differ = 1;
        break;
      }
      at += d;
    }
  }
  return differ == 0;
}

template <int D>
void ElasticSolidModule::kinematicsDim(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* x = s.data(s.position());
  const double* X = s.data(refPos_);
  double* u = s.data(disp_);
  // periodic axes: displacements by minimum image (valid while |u| < half the period)
  double period[3] = {0.0, 0.0, 0.0};
  for (int a = 0; a < D; ++a)
    if (sim.domain.periodic[static_cast<size_t>(a)]) period[a] = sim.domain.length(a);
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (slotOf(mat[i]) < 0) continue;
    for (int a = 0; a < D; ++a) {
      double d = x[i * D + a] - X[i * D + a];
      if (period[a] > 0.0) d -= period[a] * std::round(d / period[a]);  // wrapped particles
      u[i * D + a] = d;
    }
  }
  if (anyMirror_ || formulation_ == Formulation::TotalLagrangian) rebuildIdMap(sim);
  if (anyMirror_) applyMirrors<D>(sim);
  if (s.ghostCount() > 0) s.refreshGhosts(disp_);
  // The pair's relative displacement u_b - u_a by minimum image (wrapPairDisplacement): without
  // it a strip sliding more than L/2 along a periodic axis inverted (J < 0).
  const bool periodicU = period[0] > 0.0 || period[1] > 0.0 || period[2] > 0.0;
  auto relative = [&](const double* ub, const Vec<D>& ua) {
    Vec<D> d = Eigen::Map<const Vec<D>>(ub) - ua;
    if (periodicU) wrapPairDisplacement<D>(d, period);
    return d;
  };

  if (formulation_ == Formulation::TotalLagrangian) {
    const std::int32_t* fam = famIds_.data();
    const std::int32_t* row = s.data(familyRow_);
    const std::int64_t* off = famOffset_.data();
    const double* G = famG_.data();
    double* F = s.data(defGrad_);
    refreshReferenceVolumes(sim);
    const double* V0 = refVolume_.data();
    const Index* idx = idToIndex_.data();
    Index bad = n;
    // the displacements' minimum image as a plain value (PairImage: wrapPairDisplacement's
    // values), the arrays passed to defGradMembers once per particle (not reloaded per member)
    const PairImage image(period, D);
#pragma omp parallel for schedule(static) reduction(min : bad) if (n > 512)
    for (Index i = 0; i < n; ++i) {
      if (slotOf(mat[i]) < 0) continue;
      Mat<D> Fi;
      defGradMembers<D>(image, i, off[row[i]], off[row[i] + 1], fam, idx, V0, G, u, Fi.data());
      Eigen::Map<Mat<D>>(F + i * D * D) = Fi;
      if (!(Fi.determinant() > 0.0)) bad = std::min(bad, i);
    }
    if (bad < n) {
      const Mat<D> Fb = Eigen::Map<const Mat<D>>(F + bad * D * D);
      throw NumericalError("solid module: deformation gradient of particle " + std::to_string(bad) +
                           " (id " + std::to_string(s.data(s.id())[bad]) + ") has J = det F = " +
                           fmt(Fb.determinant()) + " <= 0 at step " + std::to_string(sim.step) +
                           ", time " + fmt(sim.time) + " s: the solid inverted (time step too "
                           "large or the loading too violent)");
    }
    return;
  }

  // ---- small strain: solid-solid neighbours of the current configuration, their mixed
  // correction (2.63b, libcore/corrections), then strain (2.82) and the continuity rate (2.85) ----
  const double* m = s.data(s.mass());
  const double* rho = s.data(s.density());
  double* eps = s.data(strain_);
  double* rhoRate = s.data(densityRate_);
  const double* v = s.data(s.velocity());
  const NeighbourList& nl = sim.neighbours;
  const Kernel& W = solidKernel(sim);
  const std::int32_t* phase = s.data(s.phase());
  auto isMine = [&](Index j) { return phase[j] == kPhaseSolid && slotOf(mat[j]) >= 0; };
  // filtered list (memory kept between steps): rows of every real particle, solid pairs only
  solidNeighbours_.offset.resize(static_cast<size_t>(n) + 1);
  solidNeighbours_.index.resize(nl.index.size());
  {
    std::int64_t c = 0;
    for (Index i = 0; i < n; ++i) {
      solidNeighbours_.offset[static_cast<size_t>(i)] = c;
      if (!isMine(i)) continue;
      for (auto p = nl.offset[static_cast<size_t>(i)]; p < nl.offset[static_cast<size_t>(i) + 1]; ++p)
        if (isMine(nl.index[static_cast<size_t>(p)]))
          solidNeighbours_.index[static_cast<size_t>(c++)] = nl.index[static_cast<size_t>(p)];
    }
    solidNeighbours_.offset[static_cast<size_t>(n)] = c;
  }
  const NeighbourList& sn = solidNeighbours_;
  computeVolumes(s, volume_);
  computeCorrection<D>(Correction::Mixed, W, x, volume_.data(), n, sn, corrFields_.arrays(s));
  if (s.ghostCount() > 0) {
    s.refreshGhosts(corrFields_.matrix);
    s.refreshGhosts(corrFields_.shepardSum);
    s.refreshGhosts(corrFields_.shepardGradient);
  }
  const CorrectionView view = corrFields_.view(s, Correction::Mixed, W);
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (!isMine(i)) continue;
    const Vec<D> xi = Eigen::Map<const Vec<D>>(x + i * D);
    Mat<D> gu = Mat<D>::Zero(), gv = Mat<D>::Zero();
    const Vec<D> ui = Eigen::Map<const Vec<D>>(u + i * D);
    const Vec<D> vi = Eigen::Map<const Vec<D>>(v + i * D);
    for (auto p = sn.offset[static_cast<size_t>(i)]; p < sn.offset[static_cast<size_t>(i) + 1]; ++p) {
      const Index j = sn.index[static_cast<size_t>(p)];
      const Vec<D> rij = xi - Eigen::Map<const Vec<D>>(x + j * D);
      const Vec<D> g = view.gradient<D>(i, W.gradient<D>(rij), W.value(rij.norm()));
      const double Vj = m[j] / rho[j];
      gu.noalias() += Vj * relative(u + j * D, ui) * g.transpose();  // 2.82
      gv.noalias() += Vj * (Eigen::Map<const Vec<D>>(v + j * D) - vi) * g.transpose();  // 2.83
    }
    Eigen::Map<Mat<D>>(eps + i * D * D) = 0.5 * (gu + gu.transpose());
    rhoRate[i] = -rho[i] * gv.trace();  // continuity, Eq. 2.85 (first line)
  }
}

// ------------------------------------------------------------------------------------------------
// constitutive: SVK (2.71-2.74, 2.78) or the isotropic small-strain law (2.84)
// ------------------------------------------------------------------------------------------------
void ElasticSolidModule::constitutive(Simulation& sim) {
  // the damage commit at the strain of this evaluation, before the stress uses it (damage.cpp)
  if (anyDamage_ && commitAtEvaluation_ && !freezeDamage)
    dispatchDimension(sim.dimension(), [&](auto d) { commitDamageDim<decltype(d)::value>(sim); });
  dispatchDimension(sim.dimension(), [&](auto d) { constitutiveDim<decltype(d)::value>(sim); });
}

template <int D>
void ElasticSolidModule::constitutiveDim(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  double* sig = s.data(stress_);
  double* eps = s.data(strain_);
  const double* dmg = damage_.valid() ? s.data(damage_) : nullptr;
  if (formulation_ == Formulation::TotalLagrangian) {
    const double* F = s.data(defGrad_);
    double* P = s.data(piola_);
    double* rho = s.data(s.density());
#pragma omp parallel for schedule(static) if (n > 512)
    for (Index i = 0; i < n; ++i) {
      const int k = slotOf(mat[i]);
      if (k < 0) continue;
      const ElasticMaterial& e = mats_[static_cast<size_t>(k)];
      const Mat<D> Fi = Eigen::Map<const Mat<D>>(F + i * D * D);
      const Mat<D> E = 0.5 * (Fi.transpose() * Fi - Mat<D>::Identity());  // 2.71
      const Mat<D> S = dmg ? e.law.stress<D>(E, dmg[i])                     // 4.18a
                           : isotropicLaw<D>(E, e.lambda, e.mu);            // 2.73-2.74
      const Mat<D> Pi = Fi * S;                                             // P = F S
      const double J = Fi.determinant();                                    // 2.78
      Eigen::Map<Mat<D>>(eps + i * D * D) = E;
      Eigen::Map<Mat<D>>(P + i * D * D) = Pi;
      Eigen::Map<Mat<D>>(sig + i * D * D) = Pi * Fi.transpose() / J;        // Cauchy
      rho[i] = e.density / J;                                               // 2.79
    }
    return;
  }
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0) continue;
    const ElasticMaterial& e = mats_[static_cast<size_t>(k)];
    const Mat<D> epsi = Eigen::Map<const Mat<D>>(eps + i * D * D);
    Eigen::Map<Mat<D>>(sig + i * D * D) = dmg ? e.law.stress<D>(epsi, dmg[i])       // 4.18a
                                              : isotropicLaw<D>(epsi, e.lambda, e.mu);  // 2.84
  }
  if (s.ghostCount() > 0) s.refreshGhosts(stress_);
}

// ------------------------------------------------------------------------------------------------
// forces: internal forces (2.76 / 2.86 / 2.90), energy rate (2.77 / 2.87), artificial viscosity
// (2.64-2.65), damping, traction; work rates for the energy balance
// ------------------------------------------------------------------------------------------------
void ElasticSolidModule::forces(Simulation& sim) {
  dispatchDimension(sim.dimension(), [&](auto d) { forcesDim<decltype(d)::value>(sim); });
  if (hasGravity_) applyGravity(sim);
}

// Body force (solid: {gravity: [..]}, the self-weight of a plate): a += g on every solid
// particle; its power on the free particles is external work (solid_external_work). Clamped
// and prescribed particles have their acceleration reset by constraints().
void ElasticSolidModule::applyGravity(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const int d = sim.dimension();
  const std::int32_t* mat = s.data(s.material());
  const std::int32_t* motion = s.data(sim.motion);
  const double* v = s.data(s.velocity());
  const double* m = s.data(s.mass());
  double* acc = s.data(sim.acceleration);
  double* workRate = s.data(workRate_);
  const std::array<double, 3> g = gravity_;
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (slotOf(mat[i]) < 0) continue;
    double power = 0.0;
    for (int a = 0; a < d; ++a) {
      acc[i * d + a] += g[static_cast<size_t>(a)];
      power += m[i] * v[i * d + a] * g[static_cast<size_t>(a)];
    }
    if (motion[i] == kMotionFree) workRate[i * 3 + 1] += power;
  }
}

template <int D>
void ElasticSolidModule::forcesDim(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const std::int32_t* phase = s.data(s.phase());
  const std::int32_t* motion = s.data(sim.motion);
  const std::int32_t* bc = s.data(bc_);
  const double* x = s.data(s.position());
  const double* v = s.data(s.velocity());
  const double* m = s.data(s.mass());
  const double* rho = s.data(s.density());
  const double* u = s.data(disp_);
  const double* fb = s.data(bcForce_);
  double* acc = s.data(sim.acceleration);
  double* wRate = s.data(energyRate_);
  double* workRate = s.data(workRate_);
  double* xsphRate = xsph_.valid() ? s.data(xsph_) : nullptr;
  const Kernel& W = solidKernel(sim);
  const double h = W.h();
  const double t = sim.time;
  auto isMine = [&](Index j) { return phase[j] == kPhaseSolid && slotOf(mat[j]) >= 0; };
  // degradation g(D) of a particle's share of the hourglass stiffness (1 without damage)
  const double* dmg = damage_.valid() ? s.data(damage_) : nullptr;
  auto gOf = [&](const ElasticMaterial& em, Index j) { return dmg ? em.law.g(dmg[j]) : 1.0; };

  // Monaghan's artificial viscosity, Eqs. 2.64-2.65: the acceleration term -m_b Pi_ab grad.
  auto viscosity = [&](const ElasticMaterial& ea, const ElasticMaterial& eb, const Vec<D>& vab,
                       const Vec<D>& rab, double rhoa, double rhob) -> double {
    return artificialViscosityPi<D>(vab, rab, h, 0.5 * (ea.avAlpha + eb.avAlpha),
                                    0.5 * (ea.avBeta + eb.avBeta), ea.waveSpeed, eb.waveSpeed,
                                    rhoa, rhob);
  };

  if (formulation_ == Formulation::TotalLagrangian) {
    const std::int32_t* fam = famIds_.data();
    const std::int32_t* row = s.data(familyRow_);
    const std::int64_t* off = famOffset_.data();
    const double* G = famG_.data();
    const std::int32_t* revSlot = compactFamily_ ? famRevSlot_.data() : nullptr;
    const double* GR = compactFamily_ ? nullptr : famGR_.data();
    const double* P = s.data(piola_);
    const double* Fg = s.data(defGrad_);
    const double* X = s.data(refPos_);
    // separations of family members across a periodic face: minimum image (the family holds
    // particle ids, not images)
    const std::array<double, 3> L = period_;
    const bool periodic = L[0] > 0.0 || L[1] > 0.0 || L[2] > 0.0;
    // |d| < L/4: round(d / L) = 0 and the shift is 0, so the rounding is skipped (same values)
    auto minimumImage = [&](Vec<D> d) {
      if (periodic)
        for (int a = 0; a < D; ++a)
          if (L[static_cast<size_t>(a)] > 0.0 && std::abs(d[a]) >= 0.25 * L[static_cast<size_t>(a)])
            d[a] -= L[static_cast<size_t>(a)] * std::round(d[a] / L[static_cast<size_t>(a)]);
      return d;
    };
    // per-particle factors of the member loops, once per evaluation: V0 = m / rho0 and the
    // hourglass share alpha E g(D) (hourglassShare; the pair's stiffness is their mean)
    refreshReferenceVolumes(sim);
    const double* V0 = refVolume_.data();
    const Index* idx = idToIndex_.data();
    const double* hgK = nullptr;
    if (anyHourglass_) {
      if (hgShare_.size() < static_cast<size_t>(n)) hgShare_.resize(static_cast<size_t>(n));
      double* share = hgShare_.data();
#pragma omp parallel for schedule(static) if (n > 512)
      for (Index i = 0; i < n; ++i) {
        const int k = slotOf(mat[i]);
        if (k < 0) {
          share[i] = 0.0;
          continue;
        }
        const ElasticMaterial& e = mats_[static_cast<size_t>(k)];
        share[i] = hourglassShare(e, gOf(e, i));
      }
      hgK = share;
    }
    // Conservative hourglass control (docs/solid.md "Hourglass control"): the penalty energy
    //   Phi = 1/4 sum_a sum_b c_ab |r_ab|^2,  r_ab = x_ab - (F_a + F_b)/2 X_ab  (x_ab = x_b - x_a),
    //   c_ab = k_ab V_a V_b W0_ab / |X_ab|^2,  k_ab = (hourglass_a E_a g_a + hourglass_b E_b g_b)/2
    // (g = g(D), frozen over the step: hourglassPairStiffness; the energy the commit releases
    // from it is counted in damage.cpp),
    // vanishes for every linear and quadratic field. Its exact negative gradient is the direct
    // pair force sum_b c_ab r_ab plus, through the dependence of F_a on the family of a, the
    // momentum term of Eq. 2.76 with the stress -M_a/2 added to P_a,
    //   M_a = sum_b k_ab V_b W0_ab / |X_ab|^2 r_ab (x) X_ab.
    // First pass: P_a - M_a/2 and the direct force per unit reference volume, into hgScratch_;
    // the energy density phi_a (Phi = sum V0_a phi_a) into solid_hourglass_energy.
    const double* Pf = P;          // the stress the momentum equation reads
    const double* hgDirect = nullptr;
    if (anyHourglass_ && hourglassConservative_) {
      if (hgScratch_.size() < static_cast<size_t>(n) * (D * D + D))
        hgScratch_.resize(static_cast<size_t>(n) * (D * D + D));
      double* Q = hgScratch_.data();
      double* fd = Q + static_cast<size_t>(n) * D * D;
      double* phi = s.data(hgEnergy_);
      const double* hgW = famHgW_.empty() ? nullptr : famHgW_.data();
      const PairImage image(L.data(), D);
      // The member loop (hourglassMembers) with the factor W0_ab / |X_ab|^2 stored (kStored:
      // family_storage fast) or computed; the arrays passed once per particle (the loop inline had
      // reloaded them through the closures at every member). The same arithmetic as before.
      auto pass = [&](const auto K, const auto kStored) {
#pragma omp parallel for schedule(static) if (n > 512)
        for (Index i = 0; i < n; ++i) {
          const int k = slotOf(mat[i]);
          if (k < 0) {
            phi[i] = 0.0;
            continue;
          }
          Mat<D> M;
          Vec<D> direct;
          double e2;
          hourglassMembers<D, decltype(kStored)::value>(
              K, [](double a, double b) { return hourglassPairStiffness(a, b); }, image, i,
              off[row[i]], off[row[i] + 1], fam, idx, hgK, V0, hgW, X, x, Fg, M.data(),
              direct.data(), &e2);
          Eigen::Map<Mat<D>>(Q + i * D * D) = Eigen::Map<const Mat<D>>(P + i * D * D) - 0.5 * M;
          Eigen::Map<Vec<D>>(fd + i * D) = direct;
          phi[i] = 0.25 * e2;
        }
      };
      W.withFixedType<D>([&](const auto K) {  // the kernel type fixed for the member loop
        if (hgW)
          pass(K, std::true_type{});
        else
          pass(K, std::false_type{});
      });
      Pf = Q;
      hgDirect = fd;
    }
    const bool hgPairwise = anyHourglass_ && !hourglassConservative_;
    // A particle without artificial viscosity, pairwise hourglass spring or XSPH (the drainage
    // scenes' clay) takes forceMembers: the arrays as arguments, the reverse-gradient form a
    // template parameter, the same two Eigen expressions as the general loop below, so the same
    // sums bit for bit, without the per-member tests and reloads through the closures.
#pragma omp parallel for schedule(static) if (n > 512)
    for (Index i = 0; i < n; ++i) {
      const int k = slotOf(mat[i]);
      if (k < 0) continue;
      const ElasticMaterial& e = mats_[static_cast<size_t>(k)];
      const Mat<D> Pi = Eigen::Map<const Mat<D>>(Pf + i * D * D);
      const Mat<D> Fi = Eigen::Map<const Mat<D>>(Fg + i * D * D);
      const Vec<D> Xi = Eigen::Map<const Vec<D>>(X + i * D);
      Vec<D> fhg = Vec<D>::Zero();
      const Vec<D> vi = Eigen::Map<const Vec<D>>(v + i * D);
      const Vec<D> xi = Eigen::Map<const Vec<D>>(x + i * D);
      Vec<D> f = Vec<D>::Zero(), fav = Vec<D>::Zero(), dvx = Vec<D>::Zero();
      Mat<D> Fdot = Mat<D>::Zero();
      const bool av = e.avAlpha > 0.0 || e.avBeta > 0.0;
      const std::int64_t q0 = off[row[i]], q1 = off[row[i] + 1];
      const bool plain = !av && !(hgPairwise && e.hourglass > 0.0) && !(e.xsph > 0.0);
      if (plain && GR)
        forceMembers<D, true>(q0, q1, fam, idx, V0, G, GR, revSlot, off, row, Pf, v, Pi.data(),
                              vi.data(), f.data(), Fdot.data());
      else if (plain)
        forceMembers<D, false>(q0, q1, fam, idx, V0, G, GR, revSlot, off, row, Pf, v, Pi.data(),
                               vi.data(), f.data(), Fdot.data());
      else
      for (std::int64_t q = q0; q < q1; ++q) {
        const Index j = idx[fam[q]];
        const double Vj = V0[j];  // m_j / rho0_j
        const Vec<D> g = Eigen::Map<const Vec<D>>(G + q * D);
        const Vec<D> gr = Eigen::Map<const Vec<D>>(
            revSlot ? G + (off[row[j]] + revSlot[q]) * D : GR + q * D);
        const Mat<D> Pj = Eigen::Map<const Mat<D>>(Pf + j * D * D);
        f.noalias() += Vj * (Pi * g - Pj * gr);  // 2.76 (times m_a / V_a = rho0_a)
        const Vec<D> vji = Eigen::Map<const Vec<D>>(v + j * D) - vi;
        Fdot.noalias() += Vj * vji * g.transpose();  // 2.68
        if (av) {
          const ElasticMaterial& ej = mats_[static_cast<size_t>(slotOf(mat[j]))];
          const Vec<D> rij = minimumImage(Vec<D>(xi - Eigen::Map<const Vec<D>>(x + j * D)));
          const double Pi_ab = viscosity(e, ej, -vji, rij, rho[i], rho[j]);
          fav.noalias() -= m[j] * Pi_ab * 0.5 * (g - gr);  // antisymmetrised reference gradient
        }
        if (hgPairwise && e.hourglass > 0.0) {
          // Hourglass control (Ganzenmueller 2015): the part of the pair's current separation
          // that the particles' own F do not predict is pushed back along the pair, with a
          // spring of stiffness hourglass * E * g(D) * W0 / |X_ab|^2; zero for any linear field.
          const Vec<D> Xji = minimumImage(Vec<D>(Eigen::Map<const Vec<D>>(X + j * D) - Xi));
          const Vec<D> xji = minimumImage(Vec<D>(Eigen::Map<const Vec<D>>(x + j * D) - xi));
          const double dist = xji.norm();
          if (dist > 0.0) {
            const Vec<D> ev = xji / dist;
            const Mat<D> Fj = Eigen::Map<const Mat<D>>(Fg + j * D * D);
            const double dA = (Fi * Xji - xji).dot(ev);    // a's prediction error for b
            const double dB = (Fj * (-Xji) + xji).dot(-ev);  // b's prediction error for a
            const double r0 = Xji.norm();
            const double coef = hourglassPairStiffness(hgK[i], hgK[j]) * Vj * W.value(r0) / (r0 * r0);
            fhg.noalias() -= coef * 0.5 * (dA + dB) * ev;
          }
        }
        if (e.xsph > 0.0) {  // 2.66, over the reference family with the current distance
          const double w = W.value(minimumImage(Vec<D>(xi - Eigen::Map<const Vec<D>>(x + j * D))).norm());
          dvx.noalias() += m[j] * 2.0 * vji / (rho[i] + rho[j]) * w;
        }
      }
      if (hgDirect) fhg = Eigen::Map<const Vec<D>>(hgDirect + i * D);
      const Vec<D> a = (f + fhg) / e.density;
      // 2.77: dw/dt = P : dF/dt (per unit volume), with the material's stress P (not the
      // effective stress of the hourglass control, whose energy is solid_hourglass_energy)
      wRate[i] += (Eigen::Map<const Mat<D>>(P + i * D * D).cwiseProduct(Fdot)).sum();
      const Vec<D> extra = fav - e.damping * vi;
      if (xsphRate) Eigen::Map<Vec<D>>(xsphRate + i * D) += e.xsph * dvx;
      const Vec<D> fext = Eigen::Map<const Vec<D>>(fb + i * D) *
                          (bc[i] > 0 ? linearRamp(t, boundaries_[static_cast<size_t>(bc[i] - 1)].rampTime) : 0.0);
      for (int c = 0; c < D; ++c) acc[i * D + c] += a[c] + extra[c] + fext[c] / m[i];
      if (motion[i] == kMotionFree) workRate[i * 3 + 1] += vi.dot(fext);
      // Dissipation (viscosity, damping) on every moving particle: on an imposed-velocity
      // particle the agent's work (solid_boundary_work) includes balancing these forces, so
      // leaving them out there left the viscous work of the pairs with the driven layers
      // uncounted (2.2 % of the work in the softening bar, docs/solid.md "Energy bookkeeping").
      if (motion[i] != kMotionFixed) {
        workRate[i * 3 + 2] -= m[i] * vi.dot(extra);
        // the pairwise hourglass spring is not the gradient of an energy: its power is counted
        // with the dissipation, so the balance closes with either form
        if (hgPairwise) workRate[i * 3 + 2] -= m[i] / e.density * vi.dot(fhg);
      }
    }
    return;
  }

  // ---- small strain: current solid neighbours (filtered in kinematics) ----
  const double* sig = s.data(stress_);
  const NeighbourList& sn = solidNeighbours_;
  const CorrectionView view = corrFields_.view(s, Correction::Mixed, W);
  const bool displacementForm = formulation_ == Formulation::SmallStrainDisplacement;
  // u_a - u_b by minimum image along periodic axes (as in kinematics: u jumps by a period where
  // a particle has slid past half a period)
  double periodU[3] = {0.0, 0.0, 0.0};
  for (int a = 0; a < D; ++a)
    if (sim.domain.periodic[static_cast<size_t>(a)]) periodU[a] = sim.domain.length(a);
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (!isMine(i)) continue;
    const ElasticMaterial& e = mats_[static_cast<size_t>(slotOf(mat[i]))];
    const Mat<D> sigi = Eigen::Map<const Mat<D>>(sig + i * D * D);
    const Vec<D> vi = Eigen::Map<const Vec<D>>(v + i * D);
    const Vec<D> xi = Eigen::Map<const Vec<D>>(x + i * D);
    const Vec<D> ui = Eigen::Map<const Vec<D>>(u + i * D);
    Vec<D> f = Vec<D>::Zero(), fav = Vec<D>::Zero(), dvx = Vec<D>::Zero();
    Mat<D> L = Mat<D>::Zero();
    const bool av = e.avAlpha > 0.0 || e.avBeta > 0.0;
    for (auto p = sn.offset[static_cast<size_t>(i)]; p < sn.offset[static_cast<size_t>(i) + 1]; ++p) {
      const Index j = sn.index[static_cast<size_t>(p)];
      const ElasticMaterial& ej = mats_[static_cast<size_t>(slotOf(mat[j]))];
      const Vec<D> rij = xi - Eigen::Map<const Vec<D>>(x + j * D);
      const double r = rij.norm();
      const double Vj = m[j] / rho[j];
      const Vec<D> gradW = W.gradient<D>(rij);
      const double Wij = W.value(r);
      const Vec<D> gij = view.gradient<D>(i, gradW, Wij);
      const Vec<D> vji = Eigen::Map<const Vec<D>>(v + j * D) - vi;
      L.noalias() += Vj * vji * gij.transpose();  // 2.83
      if (displacementForm) {
        // Eqs. 2.88-2.90: rho a = mu lap(u) + (lambda + mu) grad(div u), with the
        // second derivatives of Eq. 2.89: sum_b V_b [(D+2) e_j e_k - delta_jk] (u_a - u_b) F_ab.
        Vec<D> uij = ui - Eigen::Map<const Vec<D>>(u + j * D);
        wrapPairDisplacement<D>(uij, periodU);
        const double lam = 0.5 * (e.lambda + ej.lambda), mu = 0.5 * (e.mu + ej.mu);
        f.noalias() += Vj * W.F(r) *
                       ((mu - lam) * uij + (lam + mu) * (D + 2) * rij * (rij.dot(uij) / (r * r)));
      } else {
        const Vec<D> gji = view.gradient<D>(j, Vec<D>(-gradW), Wij);
        const Mat<D> sigj = Eigen::Map<const Mat<D>>(sig + j * D * D);
        f.noalias() += Vj * (sigi * gij - sigj * gji);  // 2.86 (times rho_a)
      }
      if (av) {
        const double Pi_ab = viscosity(e, ej, -vji, rij, rho[i], rho[j]);
        fav.noalias() -= m[j] * Pi_ab * gradW;
      }
      if (e.xsph > 0.0) dvx.noalias() += m[j] * 2.0 * vji / (rho[i] + rho[j]) * Wij;  // 2.66
    }
    wRate[i] += rho[i] / e.density * (sigi.cwiseProduct(L)).sum();  // 2.87 per unit reference volume
    const Vec<D> a = f / rho[i];
    const Vec<D> extra = fav - e.damping * vi;
    if (xsphRate) Eigen::Map<Vec<D>>(xsphRate + i * D) += e.xsph * dvx;
    const Vec<D> fext = Eigen::Map<const Vec<D>>(fb + i * D) *
                        (bc[i] > 0 ? linearRamp(t, boundaries_[static_cast<size_t>(bc[i] - 1)].rampTime) : 0.0);
    for (int c = 0; c < D; ++c) acc[i * D + c] += a[c] + extra[c] + fext[c] / m[i];
    if (motion[i] == kMotionFree) workRate[i * 3 + 1] += vi.dot(fext);
    if (motion[i] != kMotionFixed) workRate[i * 3 + 2] -= m[i] * vi.dot(extra);  // as in TL
  }
}

// ------------------------------------------------------------------------------------------------
// constraints: clamped and prescribed particles, XSPH (2.66)
// ------------------------------------------------------------------------------------------------
void ElasticSolidModule::constraints(Simulation& sim) {
  dispatchDimension(sim.dimension(), [&](auto d) { constraintsDim<decltype(d)::value>(sim); });
}

template <int D>
void ElasticSolidModule::constraintsDim(Simulation& sim) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const std::int32_t* bc = s.data(bc_);
  double* v = s.data(s.velocity());
  const double* m = s.data(s.mass());
  double* acc = s.data(sim.acceleration);
  double* workRate = s.data(workRate_);
  const double t = sim.time;
  // the integrator's velocity state (libcore/integrator.cpp, registered at its first step)
  double* vInt = anyPartial_ && s.has("integrator_velocity") ? s.data(s.real("integrator_velocity"))
                                                             : nullptr;
#pragma omp parallel for schedule(static) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (bc[i] <= 0 || slotOf(mat[i]) < 0) continue;
    const Boundary& B = boundaries_[static_cast<size_t>(bc[i] - 1)];
    if (B.type == BoundaryType::Clamped || B.type == BoundaryType::Symmetry) {
      for (int c = 0; c < D; ++c) {
        acc[i * D + c] = 0.0;
        if (!B.mirror) v[i * D + c] = 0.0;
      }
    } else if (B.type == BoundaryType::Velocity || B.type == BoundaryType::Displacement) {
      // imposed velocity ramp, or the constant velocity of a displacement ramp
      const double r = B.type == BoundaryType::Velocity ? linearRamp(t, B.rampTime)
                                                        : linearRampRate(t, B.rampTime);
      const double rdot = B.type == BoundaryType::Velocity ? linearRampRate(t, B.rampTime) : 0.0;
      double power = 0.0;
      for (int c = 0; c < D; ++c) {
        if (!B.imposed[static_cast<size_t>(c)]) continue;  // free component (roller)
        const double target = B.value[static_cast<size_t>(c)] * r;
        // A free particle with imposed components: its integrator state (the staggered or
        // half-kicked velocity of Eqs. 2.47-2.48) takes the imposed value too, so that the
        // position follows the imposed velocity whatever the scheme.
        if (B.partial && vInt) vInt[i * D + c] = target;
        // the agent holding the particle supplies m (dv/dt - a_internal)
        power += target * m[i] * (B.value[static_cast<size_t>(c)] * rdot - acc[i * D + c]);
        v[i * D + c] = target;
        acc[i * D + c] = 0.0;
      }
      workRate[i * 3 + 0] += power;
    }
  }

}

// ------------------------------------------------------------------------------------------------
// time step (Eqs. 2.49-2.50) and diagnostics (energies, Eqs. 38-39 of Chapter 3)
// ------------------------------------------------------------------------------------------------
double ElasticSolidModule::elasticTimeStepLimit(const Simulation& sim) const {
  // Eq. 2.50, with the artificial viscosity's alpha term (Monaghan: c (1 + 1.2 alpha))
  double c = 0.0;
  for (const auto& e : mats_) c = std::max(c, e.waveSpeed * (1.0 + 1.2 * e.avAlpha));
  if (!(c > 0.0)) return std::numeric_limits<double>::infinity();
  double dt = solidKernel(sim).h() / c;
  // hourglass control: its fastest mode (omega^2 from initialise); binds only for large alpha
  // (measured: cantilever with alpha = 10 inverts at 0.6 x Eq. 2.50, runs at 0.5; this bound
  // gives 0.53 there, and is above Eq. 2.50 for alpha <= 3)
  if (hourglassOmega2_ > 0.0) dt = std::min(dt, 2.0 / std::sqrt(hourglassOmega2_));
  return courant * dt;
}

double ElasticSolidModule::deferredBytesPerParticle(
    const Simulation& sim, double neighbours, const std::vector<Index>& particlesPerMaterial) const {
  if (formulation_ != Formulation::TotalLagrangian) return 0.0;
  // The family size is bounded by the sites within the support on the particle lattice: the
  // sites at exactly the support radius fall in or out by round-off, so count them in (and the
  // site itself): 123 at support 3 dx in 3D, where the strict count `neighbours` is 92 (the
  // measured mean on the 64^3 Ketton image is ~100: pore walls have fewer). An upper bound for
  // lattice-placed solids.
  const int d = sim.dimension();
  const double s = sim.kernel.support() / sim.spacing;
  const int r = static_cast<int>(std::floor(s * (1.0 + 1e-9)));
  const double r2 = s * s * (1.0 + 1e-9);
  long inclusive = 0;
  for (int a = -r; a <= r; ++a)
    for (int b = (d > 1 ? -r : 0); b <= (d > 1 ? r : 0); ++b)
      for (int c = (d > 2 ? -r : 0); c <= (d > 2 ? r : 0); ++c)
        if (static_cast<double>(a * a + b * b + c * c) <= r2) ++inclusive;
  const double members = std::max({1.0, neighbours, static_cast<double>(inclusive)});
  // Held for the solid particles only (compressed rows): per member the id + g_ab, and g_ba
  // (family_storage fast) or its slot (compact); per solid particle the row offset; per
  // particle of the scene the solid_family_row field.
  double all = 0.0, mine = 0.0;
  for (size_t id = 0; id < particlesPerMaterial.size(); ++id) {
    all += static_cast<double>(particlesPerMaterial[id]);
    if (slotOf(static_cast<int>(id)) >= 0) mine += static_cast<double>(particlesPerMaterial[id]);
  }
  const double share = all > 0.0 ? mine / all : 1.0;
  // (fast with the conservative hourglass control: + W0_ab / |X_ab|^2, one double)
  const double perMember = compactFamily_
                               ? 2.0 * sizeof(std::int32_t) + d * sizeof(double)
                               : sizeof(std::int32_t) + 2.0 * d * sizeof(double) +
                                     (anyHourglass_ && hourglassConservative_ ? sizeof(double) : 0.0);
  // step_end damage commit: the copy of the solid positions and of the ids at the last F
  // (kinematics, the commit's reuse of F)
  const double reuse = anyDamage_ && !commitAtEvaluation_
                           ? share * d * sizeof(double) + sizeof(std::int32_t) : 0.0;
  return share * (members * perMember + sizeof(std::int64_t)) + sizeof(std::int32_t) + reuse;
}

std::uint64_t ElasticSolidModule::heldBytes() const {
  return famOffset_.size() * sizeof(std::int64_t) + famIds_.size() * sizeof(std::int32_t) +
         famRevSlot_.size() * sizeof(std::int32_t) +
         (famG_.size() + famGR_.size() + famHgW_.size() + fPositions_.capacity()) * sizeof(double) +
         fIds_.capacity() * sizeof(std::int32_t);
}

double ElasticSolidModule::timeStepLimit(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const int d = sim.dimension();
  const std::int32_t* mat = s.data(s.material());
  const double* v = s.data(s.velocity());
  const double* a = s.data(sim.acceleration);
  double vmax = 0.0, amax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : vmax, amax) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (slotOf(mat[i]) < 0) continue;
    double v2 = 0.0, a2 = 0.0;
    for (int c = 0; c < d; ++c) {
      v2 += v[i * d + c] * v[i * d + c];
      a2 += a[i * d + c] * a[i * d + c];
    }
    vmax = std::max(vmax, std::sqrt(v2));
    amax = std::max(amax, std::sqrt(a2));
  }
  const double h = solidKernel(sim).h();
  double dt = elasticTimeStepLimit(sim);
  if (vmax > 0.0) dt = std::min(dt, 0.25 * h / vmax);             // 2.49a
  double beta = 0.0;
  for (const auto& e : mats_) beta = std::max(beta, e.avBeta);
  if (beta > 0.0 && vmax > 0.0) {  // the beta term of 2.64: h / (c + 1.2 beta max|v|)
    double c = 0.0;
    for (const auto& e : mats_) c = std::max(c, e.waveSpeed * (1.0 + 1.2 * e.avAlpha));
    dt = std::min(dt, courant * h / (c + 1.2 * beta * vmax));
  }
  if (amax > 0.0) dt = std::min(dt, 0.25 * std::sqrt(h / amax));  // 2.49b
  return dt;
}

double ElasticSolidModule::elasticEnergy(const Simulation& sim) const {
  return dispatchDimension(sim.dimension(),
                           [&](auto d) { return elasticEnergyDim<decltype(d)::value>(sim); });
}

template <int D>
double ElasticSolidModule::elasticEnergyDim(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* m = s.data(s.mass());
  const double* eps = s.data(strain_);
  double e = 0.0;
  const std::int32_t* src = anyMirror_ ? s.data(mirror_) : nullptr;
  const double* dmg = damage_.valid() ? s.data(damage_) : nullptr;
#pragma omp parallel for schedule(static) reduction(+ : e) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0 || (src && src[i] > 0)) continue;  // mirror layers are images, not material
    const ElasticMaterial& em = mats_[static_cast<size_t>(k)];
    const Mat<D> E = Eigen::Map<const Mat<D>>(eps + i * D * D);
    // TL: strain = E_GL and S = C0 : E_GL, psi = 1/2 S : E (SVK, Eq. 26 of Chapter 3)
    if (dmg) {  // Eq. 4.17 (4.26a): g(D) psi+ + psi-
      e += m[i] / em.density * em.law.energy<D>(E, dmg[i]);
      continue;
    }
    const Mat<D> S = isotropicLaw<D>(E, em.lambda, em.mu);
    e += m[i] / em.density * 0.5 * S.cwiseProduct(E).sum();
  }
  return e;
}

double ElasticSolidModule::kineticEnergy(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const int d = sim.dimension();
  const std::int32_t* mat = s.data(s.material());
  const std::int32_t* mo = s.data(sim.motion);
  const double* v = s.data(s.velocity());
  const double* m = s.data(s.mass());
  double e = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : e) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (slotOf(mat[i]) < 0 || mo[i] == kMotionFixed) continue;
    double v2 = 0.0;
    for (int c = 0; c < d; ++c) v2 += v[i * d + c] * v[i * d + c];
    e += 0.5 * m[i] * v2;
  }
  return e;
}

double ElasticSolidModule::hourglassEnergy(const Simulation& sim) const {
  if (!hgEnergy_.valid()) return 0.0;
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* phi = s.data(hgEnergy_);
  const double* m = s.data(s.mass());
  const std::int32_t* src = anyMirror_ ? s.data(mirror_) : nullptr;
  double e = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : e) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0 || (src && src[i] > 0)) continue;  // mirror layers are images, not material
    e += m[i] / mats_[static_cast<size_t>(k)].density * phi[i];
  }
  return e;
}

double ElasticSolidModule::internalEnergy(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* w = s.data(energy_);
  const double* m = s.data(s.mass());
  const std::int32_t* src = anyMirror_ ? s.data(mirror_) : nullptr;
  double e = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : e) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0 || (src && src[i] > 0)) continue;
    e += m[i] / mats_[static_cast<size_t>(k)].density * w[i];  // Eq. 39b, V0 w
  }
  return e;
}

std::array<double, 3> ElasticSolidModule::work(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* w = s.data(work_);
  double a = 0.0, b = 0.0, c = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : a, b, c) if (n > 512)
  for (Index i = 0; i < n; ++i) {
    if (slotOf(mat[i]) < 0) continue;
    a += w[i * 3];
    b += w[i * 3 + 1];
    c += w[i * 3 + 2];
  }
  return {a, b, c};
}

void ElasticSolidModule::diagnostics(const Simulation& sim,
                                     std::vector<std::pair<std::string, double>>& columns) const {
  const double ke = kineticEnergy(sim), el = elasticEnergy(sim), in = internalEnergy(sim);
  const double hg = hourglassEnergy(sim);
  const auto w = work(sim);
  columns.emplace_back("solid_kinetic_energy", ke);
  columns.emplace_back("solid_elastic_energy", el);
  if (hgEnergy_.valid()) columns.emplace_back("solid_hourglass_energy", hg);
  columns.emplace_back("solid_internal_energy", in);
  columns.emplace_back("solid_boundary_work", w[0]);
  columns.emplace_back("solid_external_work", w[1]);
  columns.emplace_back("solid_dissipated_energy", w[2]);
  // constant in time when the bookkeeping closes: kinetic + elastic - work in + dissipated
  const double dd = anyDamage_ ? damageDissipation(sim) : 0.0;
  if (anyDamage_) {  // docs/damage.md: Eqs. 4.25-4.26b
    columns.emplace_back("solid_damage_dissipation", dd);
    columns.emplace_back("solid_damage_dissipation_yc", damageDissipationYc(sim));
    columns.emplace_back("solid_damage_clipped", static_cast<double>(clippedUpdates_));
    // Crack events for `reference: {at: first COLUMN >= VALUE}` (docs/damage.md "Fields,
    // columns, checks"): the largest D, and along each axis the fraction of the damageable
    // material's extent (reference positions, between particle centres) that the particles at
    // D >= 0.5 span: 1 when the damaged zone reaches two opposite faces (a crack through).
    const ParticleStore& s = sim.store;
    const int d = sim.dimension();
    const std::int32_t* mat = s.data(s.material());
    const double* D = s.data(damage_);
    const double* X = s.data(refPos_);
    const std::int32_t* src = anyMirror_ ? s.data(mirror_) : nullptr;
    double dmax = 0.0;
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    std::array<double, 3> dlo = lo, dhi = hi;
    for (Index i = 0; i < s.realCount(); ++i) {
      const int k = slotOf(mat[i]);
      if (k < 0 || (src && src[i] > 0) || !mats_[static_cast<size_t>(k)].law.damages()) continue;
      dmax = std::max(dmax, D[i]);
      for (int a = 0; a < d; ++a) {
        lo[a] = std::min(lo[a], X[i * d + a]);
        hi[a] = std::max(hi[a], X[i * d + a]);
        if (D[i] >= 0.5) {
          dlo[a] = std::min(dlo[a], X[i * d + a]);
          dhi[a] = std::max(dhi[a], X[i * d + a]);
        }
      }
    }
    columns.emplace_back("solid_damage_max", dmax);
    for (int a = 0; a < d; ++a)
      columns.emplace_back(std::string("solid_damage_span_") + "xyz"[a],
                           dhi[a] >= dlo[a] && hi[a] > lo[a] ? (dhi[a] - dlo[a]) / (hi[a] - lo[a]) : 0.0);
  }
  // The imposed displacement of each displacement boundary along each imposed component (the
  // ramp of Eq. 4.31's u_d: value x min(1, t / ramp_time)), e.g. solid_imposed_top_y.
  for (size_t b = 0; b < boundaries_.size(); ++b) {
    const Boundary& B = boundaries_[b];
    if (B.type != BoundaryType::Displacement) continue;
    std::string name = B.label.empty() ? "boundary_" + std::to_string(b) : B.label;
    for (char& c : name)  // a column name: no spaces or commas
      if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    for (int a = 0; a < sim.dimension(); ++a)
      if (B.imposed[static_cast<size_t>(a)])
        columns.emplace_back("solid_imposed_" + name + "_" + "xyz"[a],
                             B.value[static_cast<size_t>(a)] * linearRamp(sim.time, B.rampTime));
  }
  columns.emplace_back("solid_energy_balance", ke + el + hg - w[0] - w[1] + w[2] + dd);
}

void ElasticSolidModule::checkHealth(const Simulation& sim, const HealthLimits& limits,
                                     std::vector<HealthIssue>& issues) const {
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const int d = sim.dimension();
  const std::int32_t* mat = s.data(s.material());
  const double* v = s.data(s.velocity());
  // |v| / c with c the elastic wave speed of Eq. 2.50: a solid particle faster than a fraction
  // of its wave speed is a blow-up (or an impact the model cannot represent).
  MaxAt mach;
#pragma omp parallel for schedule(static) reduction(maxAt : mach)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0) continue;
    double v2 = 0.0;
    for (int c = 0; c < d; ++c) v2 += v[i * d + c] * v[i * d + c];
    const double ma = std::sqrt(v2) / mats_[static_cast<size_t>(k)].waveSpeed;
    if (ma > mach.value || (ma == mach.value && i < mach.particle)) mach = MaxAt{ma, i};
  }
  if (mach.particle >= 0 && !(mach.value <= limits.maxMach))
    issues.push_back({"max_mach", "velocity", mach.particle, mach.value, limits.maxMach,
                      "|v| / elastic wave speed of a solid particle: the solid has blown up"});
  if (anyDamage_) {
    // 0 <= D <= s_l and finite (the commit never lowers D nor passes s_l: a value outside is a
    // corrupted state)
    const double* dm = s.data(damage_);
    MaxAt bad;
#pragma omp parallel for schedule(static) reduction(maxAt : bad)
    for (Index i = 0; i < n; ++i) {
      const int k = slotOf(mat[i]);
      if (k < 0) continue;
      const double lim = mats_[static_cast<size_t>(k)].law.limit;
      const double excess = std::isfinite(dm[i]) ? std::max(dm[i] - lim, -dm[i]) : HUGE_VAL;
      if (excess > bad.value || (excess == bad.value && i < bad.particle)) bad = MaxAt{excess, i};
    }
    if (bad.particle >= 0 && bad.value > 0.0)
      issues.push_back({"damage", "damage", bad.particle, s.data(damage_)[bad.particle], 0.0,
                        "damage outside [0, s_l] or not finite: the damage state is corrupted"});
  }
  if (formulation_ != Formulation::TotalLagrangian || !defGrad_.valid()) return;
  // J = det F <= 0: the particle is inverted (rho = rho0 / J of Eq. 2.79 is meaningless).
  const double* F = s.data(defGrad_);
  MaxAt inverted;
#pragma omp parallel for schedule(static) reduction(maxAt : inverted)
  for (Index i = 0; i < n; ++i) {
    if (slotOf(mat[i]) < 0) continue;
    const double* f = F + i * d * d;
    double J = f[0];
    if (d == 2) J = f[0] * f[3] - f[1] * f[2];
    if (d == 3)
      J = f[0] * (f[4] * f[8] - f[5] * f[7]) - f[1] * (f[3] * f[8] - f[5] * f[6]) +
          f[2] * (f[3] * f[7] - f[4] * f[6]);
    if (-J > inverted.value || (-J == inverted.value && i < inverted.particle))
      inverted = MaxAt{-J, i};
  }
  if (inverted.particle >= 0 && inverted.value >= 0.0)
    issues.push_back({"jacobian", "deformation_gradient", inverted.particle, -inverted.value, 0.0,
                      "J = det F <= 0: the solid particle is inverted"});
}

bool ElasticSolidModule::energyAccount(const Simulation& sim, EnergyAccount& account) const {
  const double el = elasticEnergy(sim) + hourglassEnergy(sim);
  const auto w = work(sim);
  account.stored += el;
  account.storedRange += el;
  account.workIn += w[0] + w[1];
  account.dissipated += w[2];
  if (anyDamage_) account.dissipated += damageDissipation(sim);  // energy released by damage
  // A vibration at 1e-3 of the wave speed: growth below it is round-off, not a fault.
  const ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mat = s.data(s.material());
  const double* m = s.data(s.mass());
  double scale = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : scale)
  for (Index i = 0; i < n; ++i) {
    const int k = slotOf(mat[i]);
    if (k < 0) continue;
    const double c = 1e-3 * mats_[static_cast<size_t>(k)].waveSpeed;
    scale += 0.5 * m[i] * c * c;
  }
  account.untrackedScale += scale;
  return true;
}

}  // namespace poresph::solid

using poresph::solid::ElasticSolidModule;
PORESPH_REGISTER_MODULE(ElasticSolidModule, "solid")
