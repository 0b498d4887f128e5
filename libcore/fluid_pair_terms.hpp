#pragma once
// The pair terms of a fluid particle a with a neighbour b, written once and called by every
// module that applies them: the fluid module (fluid-fluid, fluid-wall) and the coupling module
// (fluid-solid, on both particles of the pair). A boundary neighbour (wall, solid, rigid) is
// seen through the extrapolated pressure p_b and no-slip velocity v~_b of Adami et al. (2012)
// that the fluid module writes in its constitutive stage (fields `pressure`, `wall_velocity`),
// with the density the fluid a would have at p_b and the neighbour's own volume V_b.
//
//   pressure     m_b (p_a / rho_a^2 + p_b / rho_b^2) grad W            (Eq. 5.2b)
//                or Hu & Adams: (V_a^2 + V_b^2) / m_a p~_ab grad W
//   viscous      mu_ab V_b F / rho_a v_ab, mu_ab harmonic or arithmetic (Eq. 5.4), times the
//                lattice normalisation factor of the pair (see FluidPairSettings)
//   artificial   -m_b Pi_ab grad W, Pi_ab = -alpha c_ab mu_ab / rho_ab   (Eq. 2.64, linear term)
//   continuity   V_b (v_a - v_b) . grad W                                (Eq. 5.1a, "volume")
//                or (m_b / rho_a) (v_a - v_b) . grad W  ("mass": rho_a times the sum is
//                sum_b m_b v_ab . grad W, the energy-consistent partner of Eq. 5.2b)
// grad W = F(r) r with r = x_a - x_b (BoundaryModel: how p_b and the continuity velocity are
// taken). The force on a is m_a times the acceleration returned;
// the coupling module applies minus that force to b (evaluated with the boundary side's pressure
// offset, FluidPairSettings::reactionPressureOffset: the same force unless
// `pressure_reference: solid_gauge`).
#include "libcore/artificial_viscosity.hpp"
#include "libcore/fluid_properties.hpp"
#include "libcore/kernel.hpp"
#include "libcore/module.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// How a fluid sees a boundary neighbour's pressure and velocity in the pressure and continuity
/// terms (the viscous term always uses the no-slip velocity v~_b):
///  - Extrapolated (Adami et al. 2012): p_b and rho_b = rho(p_b) extrapolated from the fluid with
///    the hydrostatic term; continuity with the boundary's own velocity. Exact hydrostatics at a
///    fixed wall, but the pair does work that no energy accounts for: not for moving solids.
///  - Mirror: the boundary acts as the mirror image of particle a (p_b = p_a, rho_b = rho_a,
///    normal velocity reflected: v_a - v~_b = 2 (v_a - v_b) in the continuity sum). The pressure
///    pair force -2 V_a V_b p_a grad W does exactly the work that the compression energy of a
///    takes up, so fluid + solid conserve energy; the traction on the solid is still p n (the
///    pair sum of grad W over a flat interface is A / 2).
enum class BoundaryModel { Extrapolated, Mirror };

/// Which continuity pair term goes with the pressure term (scene key `fluid: {continuity_form}`):
///  - Volume (Eq. 5.1a, the default): drho_a/dt = rho_a sum_b V_b v_ab . grad W_ab.
///  - Mass: drho_a/dt = sum_b m_b v_ab . grad W_ab. With the momentum form 5.2b the power of the
///    pressure forces is then exactly minus the rate of the compression energy sum_a m_a e(rho_a)
///    (de/drho = p/rho^2), so an inviscid fluid conserves kinetic + compression energy up to the
///    time integrator's error. With 5.1a the pair leaves the power
///    1/2 sum_ab m_a m_b (v_ab . grad W)(1/rho_b - 1/rho_a)(p_a/rho_a - p_b/rho_b) (docs/fluid.md,
///    "Energy-consistent continuity"). Across a density jump (gas-water) the mass form sums the
///    heavy side's masses into the light side's density rate: use it for one-fluid scenes.
enum class ContinuityForm { Volume, Mass };

/// The continuity contribution of neighbour b to particle a, as a divergence: rho_a times the
/// sum over b of it is drho_a/dt. vabGradW = (v_a - v_b) . grad_a W_ab; V_b = m_b / rho_b.
/// One expression for every pair class that runs continuity (fluid-fluid, fluid-wall,
/// fluid-solid, fluid-rigid).
inline double continuityTerm(ContinuityForm form, double rhoa, double mb, double Vb,
                             double vabGradW) {
  return form == ContinuityForm::Mass ? (mb / rhoa) * vabGradW  // sum m_b v_ab . grad W / rho_a
                                      : Vb * vabGradW;           // Eq. 5.1a
}

struct FluidPairSettings {
  bool huAdams = false;       ///< Hu & Adams (2006) pressure form instead of Eq. 5.2b
  bool harmonicMean = true;   ///< harmonic mean of the viscosities (Eq. 5.4)
  double artificialViscosity = 0.0;  ///< alpha of Eq. 2.64
  double h = 0.0;             ///< smoothing length
  /// Constant subtracted from both pressures in the pressure term only (the fluid module's
  /// `pressure_reference: background`, issue 14): a uniform pressure then exerts exactly no
  /// force on any particle arrangement (with Eq. 5.2b or Hu-Adams a background pressure acting
  /// on a disordered neighbourhood is a spurious elastic stiffness). 0 = off (the default).
  double pressureOffset = 0.0;
  /// Continuity pair term (ContinuityForm above); the fluid module's `continuity_form`.
  ContinuityForm continuity = ContinuityForm::Volume;
  /// The offset subtracted in the force that the BOUNDARY particle of a fluid-solid /
  /// fluid-rigid pair receives (FluidBoundaryForce::reaction): pressureOffset with `none` and
  /// `background`; the background pressure with `pressure_reference: solid_gauge`, where the
  /// fluid's side uses the absolute pressure (pressureOffset 0) so that the walls always push,
  /// and the solid and the plates are loaded by p - p_b only (issue 16, docs/fluid.md "The
  /// solid-only gauge"). The pair's two forces then differ by the pair's p_b term.
  double reactionPressureOffset = 0.0;
};

/// The fluid particle a of the pair.
template <int D>
struct FluidPairSide {
  double m = 0.0, rho = 0.0, p = 0.0;
  const FluidProperties* props = nullptr;
  Vec<D> v = Vec<D>::Zero();
};

/// A boundary neighbour b: extrapolated pressure, no-slip velocity, own volume and velocity.
template <int D>
struct BoundaryPairSide {
  double p = 0.0, volume = 0.0;
  /// densityOf(a's fluid, p) when the caller has it (computed once per boundary particle);
  /// 0: computed here, per pair (the same value).
  double rho = 0.0;
  Vec<D> v = Vec<D>::Zero(), vNoSlip = Vec<D>::Zero();
};

/// Accelerations of a from one neighbour, split by term (the viscous one without the
/// normalisation factor), and the continuity contribution.
template <int D>
struct FluidPairResult {
  Vec<D> pressure = Vec<D>::Zero(), viscous = Vec<D>::Zero(), artificial = Vec<D>::Zero();
  double divergence = 0.0;  ///< continuityTerm: rho_a times it is the density rate of a from b
};

/// Pair terms of fluid a with boundary b; r = x_a - x_b, F = kernel F(|r|) (grad W = F r).
template <int D>
FluidPairResult<D> fluidBoundaryPair(const Vec<D>& r, double F, const FluidPairSide<D>& a,
                                     const BoundaryPairSide<D>& b, const FluidPairSettings& s,
                                     BoundaryModel model = BoundaryModel::Extrapolated) {
  FluidPairResult<D> out;
  const Vec<D> gradW = F * r;
  const FluidProperties& fa = *a.props;
  const bool mirror = model == BoundaryModel::Mirror;
  const double pb = mirror ? a.p : b.p;
  const double rhob = mirror ? a.rho : (b.rho > 0.0 ? b.rho : densityOf(fa, b.p));  // the fluid a at the boundary's p
  const double mb = rhob * b.volume;
  const double mua = fa.viscosity, mub = mua;
  const double muBar =
      mua + mub > 0.0 ? (s.harmonicMean ? 4.0 * mua * mub / (mua + mub) : mua + mub) : 0.0;
  const Vec<D> vab = a.v - b.vNoSlip;
  const double pa0 = a.p - s.pressureOffset, pb0 = pb - s.pressureOffset;  // force pressures
  if (s.huAdams) {
    const double Va = a.m / a.rho;
    const double pt = (rhob * pa0 + a.rho * pb0) / (a.rho + rhob);
    const double vv = (Va * Va + b.volume * b.volume) / a.m;
    out.pressure = -(vv * pt) * gradW;
    out.viscous = (vv * 0.5 * muBar * F) * vab;
  } else {
    out.pressure = -(mb * (pa0 / (a.rho * a.rho) + pb0 / (rhob * rhob))) * gradW;  // 5.2b
    out.viscous = (muBar * b.volume * F / a.rho) * vab;                            // 5.4
  }
  // Continuity (5.1a or the mass form, continuityTerm) with the boundary's own velocity
  // (Extrapolated) or the mirrored one (Mirror: rho_b = rho_a, so both forms coincide). The
  // boundary's mass in the mass form is m_b = rho_b V_b, as in the pressure term.
  out.divergence = (mirror ? 2.0 : 1.0) *
                   continuityTerm(s.continuity, a.rho, mb, b.volume, (a.v - b.v).dot(gradW));
  if (s.artificialViscosity > 0.0) {
    const double Pi = artificialViscosityPi<D>(a.v - b.v, r, s.h, s.artificialViscosity, 0.0,
                                            fa.soundSpeed, fa.soundSpeed, a.rho, rhob);
    out.artificial = -(mb * Pi) * gradW;
  }
  return out;
}

/// The force of boundary particle b on fluid particle a, read from the store's arrays: m_a times
/// the shared pair terms above (pressure, viscous times the fluid's per-pair normalisation
/// factor, artificial viscosity), and the continuity contribution in `divergence`. One accessor
/// for every module that owns a fluid-boundary pair class (coupling: fluid-solid, rigid:
/// fluid-rigid). Both sides of a pair call it with the fluid particle first, so the two
/// evaluations are identical and the pair forces cancel to round-off.
template <int D>
struct FluidBoundaryForce {
  const double* x = nullptr;         ///< positions
  const double* v = nullptr;         ///< velocities
  const double* m = nullptr;         ///< masses
  const double* rho = nullptr;       ///< densities
  const double* p = nullptr;         ///< pressures (the boundary's extrapolated one for b)
  const double* vNoSlip = nullptr;   ///< the boundary's no-slip velocity
  const double* viscousFactor = nullptr;  ///< the fluid's normalisation (nullptr: 1)
  const std::int32_t* material = nullptr;
  const Material* materials = nullptr;
  const Kernel* kernel = nullptr;
  FluidPairSettings settings;
  BoundaryModel model = BoundaryModel::Mirror;

  Vec<D> operator()(Index a, Index b, double& divergence) const {
    return evaluate(a, b, divergence, settings);
  }

  /// The same force of b on the fluid particle a with the pressure offset that the boundary side
  /// uses (settings.reactionPressureOffset): the boundary particle b receives minus this. Equal
  /// to operator() bit for bit when the two offsets are equal (`none`, `background`).
  Vec<D> reaction(Index a, Index b, double& divergence) const {
    FluidPairSettings s = settings;
    s.pressureOffset = settings.reactionPressureOffset;
    return evaluate(a, b, divergence, s);
  }

  Vec<D> evaluate(Index a, Index b, double& divergence, const FluidPairSettings& pairSettings) const {
    Vec<D> r;
    for (int c = 0; c < D; ++c) r[c] = x[a * D + c] - x[b * D + c];
    const double F = kernel->F(r.norm());
    divergence = 0.0;
    if (F == 0.0) return Vec<D>::Zero();
    FluidPairSide<D> fa;
    fa.m = m[a];
    fa.rho = rho[a];
    fa.p = p[a];
    fa.props = &materials[static_cast<size_t>(material[a])].fluid;
    BoundaryPairSide<D> sb;
    sb.p = p[b];
    sb.volume = m[b] / rho[b];
    for (int c = 0; c < D; ++c) {
      fa.v[c] = v[a * D + c];
      sb.v[c] = v[b * D + c];
      sb.vNoSlip[c] = vNoSlip[b * D + c];
    }
    const FluidPairResult<D> t = fluidBoundaryPair<D>(r, F, fa, sb, pairSettings, model);
    divergence = t.divergence;
    const double factor = viscousFactor ? viscousFactor[a] : 1.0;
    return m[a] * (t.pressure + factor * t.viscous + t.artificial);
  }

  /// The force on fluid particle a from all its neighbours of phase `boundaryPhase`, and their
  /// continuity sum (Eq. 5.1a or the mass form: add rho_a times it to the density rate) in
  /// `divergence`.
  template <class NeighbourList>
  Vec<D> onFluid(Index a, const NeighbourList& nl, const std::int32_t* phase,
                 std::int32_t boundaryPhase, double& divergence) const {
    Vec<D> f = Vec<D>::Zero();
    divergence = 0.0;
    for (auto k = nl.offset[a]; k < nl.offset[a + 1]; ++k) {
      const Index b = nl.index[static_cast<size_t>(k)];
      if (phase[b] != boundaryPhase) continue;
      double div = 0.0;
      f += (*this)(a, b, div);
      divergence += div;
    }
    return f;
  }
};

}  // namespace poresph
