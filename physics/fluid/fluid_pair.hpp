#pragma once
// The terms of a fluid-fluid pair (a, b), written once for the fluid module's two pair loops:
// the gather loop over a full neighbour list (fluid_module.cpp, side a only) and the symmetric
// loop over a half list (fluid_half.cpp, both sides of the pair from one evaluation). Side b's
// terms are side a's expressions with a and b swapped and r_ba = -r_ab, grad_b W_ba = -grad_a W_ab,
// v_ba = -v_ab (exact negations), so each side gets bit for bit what the gather loop gives it.
//   pressure    -m_b (p_a/rho_a^2 + p_b/rho_b^2) grad W        (Eq. 5.2b; p/rho^2 precomputed)
//               or Hu & Adams: -(V_a^2 + V_b^2)/m_a p~_ab grad W, p~ density-weighted
//   viscous     f_ab mu_ab V_b F / rho_a v_ab                   (Eq. 5.4, f_ab the lattice factor)
//               or Hu & Adams: f_ab (V_a^2 + V_b^2)/m_a mu_ab/2 F v_ab
//   artificial  -m_b Pi_ab grad W                               (Eqs. 2.64-2.65, Pi_ab = Pi_ba)
//   diffusion   2 V_b (rho_a - rho_b) F                         (Molteni-Colagrossi)
//   XSPH        2 m_b / (rho_a + rho_b) W (v_b - v_a)           (Eq. 2.66)
// The continuity term is libcore's continuityTerm (Eq. 5.1a or the mass form).
#include "libcore/artificial_viscosity.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// One particle of a fluid-fluid pair as its terms see it.
struct FluidPairParticle {
  double m = 0.0, rho = 0.0, V = 0.0;  ///< mass, density, volume m / rho
  double p = 0.0, pRho2 = 0.0;         ///< pressure and (p - p_ref) / rho^2 (Eq. 5.2b)
  double soundSpeed = 0.0;             ///< for the artificial viscosity
};

struct FluidFluidOptions {
  bool huAdams = false;    ///< Hu & Adams pressure form instead of Eq. 5.2b
  double pOff = 0.0;       ///< pressure reference subtracted in the Hu-Adams pressure
  double alpha = 0.0;      ///< artificial viscosity (0: off)
  double h = 0.0;          ///< smoothing length
};

/// Accelerations of one side from the pair, by term (the gather loop sums them separately).
template <int D>
struct FluidFluidAccel {
  Vec<D> pressure = Vec<D>::Zero(), viscous = Vec<D>::Zero(), artificial = Vec<D>::Zero();
};

/// The pair terms of a (and of b when kBoth): r = x_a - x_b, gradW = F r, vab = v_a - v_b,
/// muBar the mean viscosity (Eq. 5.4), fab the pair's lattice normalisation factor.
template <int D, bool kBoth>
inline void fluidFluidPair(const Vec<D>& r, const Vec<D>& gradW, double F, const Vec<D>& vab,
                           const FluidPairParticle& a, const FluidPairParticle& b, double muBar,
                           double fab, const FluidFluidOptions& o, FluidFluidAccel<D>& ta,
                           FluidFluidAccel<D>& tb) {
  if (o.huAdams) {
    const double pt = (b.rho * (a.p - o.pOff) + a.rho * (b.p - o.pOff)) / (a.rho + b.rho);
    const double sq = a.V * a.V + b.V * b.V;
    const double vvA = sq / a.m;
    ta.pressure = -(vvA * pt) * gradW;
    ta.viscous = (fab * vvA * 0.5 * muBar * F) * vab;
    if (kBoth) {
      const double vvB = sq / b.m;
      tb.pressure = (vvB * pt) * gradW;
      tb.viscous = -(fab * vvB * 0.5 * muBar * F) * vab;
    }
  } else {
    const double ps = a.pRho2 + b.pRho2;
    ta.pressure = -(b.m * ps) * gradW;  // Eq. 5.2b
    if (kBoth) tb.pressure = (a.m * ps) * gradW;
    if (muBar != 0.0) {  // Eq. 5.4 (nothing for an inviscid pair)
      ta.viscous = (fab * muBar * b.V * F / a.rho) * vab;
      if (kBoth) tb.viscous = -(fab * muBar * a.V * F / b.rho) * vab;
    }
  }
  if (o.alpha > 0.0) {  // Eq. 2.64
    const double Pi = artificialViscosityPi<D>(vab, r, o.h, o.alpha, 0.0, a.soundSpeed,
                                               b.soundSpeed, a.rho, b.rho);
    ta.artificial = -(b.m * Pi) * gradW;
    if (kBoth) tb.artificial = (a.m * Pi) * gradW;
  }
}

/// Molteni-Colagrossi density diffusion of a from b (within one material).
inline double densityDiffusionTerm(double Vb, double rhoa, double rhob, double F) {
  return 2.0 * Vb * (rhoa - rhob) * F;
}

/// XSPH (Eq. 2.66) of a from b (within one material); W = W(|r_ab|).
template <int D>
inline Vec<D> xsphTerm(double mb, double rhoa, double rhob, double W, const Vec<D>& vb,
                       const Vec<D>& va) {
  return (2.0 * mb / (rhoa + rhob) * W) * (vb - va);
}

/// The wall side of a fluid-wall pair (Adami et al. 2012 fixed boundary: extrapolated pressure,
/// no-slip velocity, the wall's own volume and velocity), built from the module's store pointers
/// `f` (FluidModule::Fields) for wall particle k; `wallRho` the wall density for the fluid of the
/// pair when precomputed (null: computed per pair). Used by the gather and the symmetric loops.
template <int D, class Fields>
inline BoundaryPairSide<D> wallPairSide(const Fields& f, Index k, const double* vol, const double* wallRho,
                                        const Vec<D>& vk) {
  BoundaryPairSide<D> s;
  s.p = f.p[k];
  s.volume = vol[k];
  s.rho = wallRho ? wallRho[k] : 0.0;
  s.v = vk;
  for (int a = 0; a < D; ++a) s.vNoSlip[a] = f.vw[k * D + a];
  return s;
}

}  // namespace poresph
