#pragma once
// The terms of a fluid-fluid pair (a, b), written once for the fluid module's two pair loops:
// the gather loop over a full neighbour list (fluid_module.cpp, side a only) and the symmetric
// loop over a half list (fluid_half.cpp, both sides of the pair from one evaluation). Side b's
// terms are side a's expressions with a and b swapped and r_ba = -r_ab, grad_b W_ba = -grad_a W_ab,
// v_ba = -v_ab (exact negations), so each side gets bit for bit what the gather loop gives it.
//   pressure    -m_b (p_a/rho_a^2 + p_b/rho_b^2) grad W        (Eq. 5.2b; p/rho^2 precomputed)
//               or Hu & Adams: -(V_a^2 + V_b^2)/m_a p~_ab grad W, p~ density-weighted
//               or Eq. 5.2a: -m_b (p_a + p_b)/(rho_a rho_b) grad W = -V_b (p_a + p_b)/rho_a grad W
//               (`pressure_gradient: volume`, the energy-consistent partner of Eq. 5.1a)
//               (p - p_ref in all three: `pressure_reference: background`)
//   viscous     f_ab mu_ab V_b F / rho_a v_ab                   (Eq. 5.4, f_ab the lattice factor)
//               or Hu & Adams: f_ab (V_a^2 + V_b^2)/m_a mu_ab/2 F v_ab
//   artificial  -m_b Pi_ab grad W                               (Eqs. 2.64-2.65, Pi_ab = Pi_ba)
//   diffusion   2 V_b (rho_a - rho_b) F                         (Molteni-Colagrossi)
//   XSPH        2 m_b / (rho_a + rho_b) W (v_b - v_a)           (Eq. 2.66)
// The continuity term is libcore's continuityTerm (Eq. 5.1a or the mass form).
#include <type_traits>

#include "libcore/artificial_viscosity.hpp"
#include "libcore/fluid_pair_terms.hpp"
#include "libcore/kernel.hpp"
#include "libcore/types.hpp"

namespace poresph {

/// One particle of a fluid-fluid pair as its terms see it (Real: double, or float for the
/// single-precision pair arithmetic of `pair_precision: float`).
template <class Real>
struct FluidPairParticleT {
  Real m = 0, rho = 0, V = 0;  ///< mass, density, volume m / rho
  Real p = 0, pRho2 = 0;       ///< pressure and (p - p_ref) / rho^2 (Eq. 5.2b)
  Real soundSpeed = 0;         ///< for the artificial viscosity
};
using FluidPairParticle = FluidPairParticleT<double>;

/// The pressure gradient of the fluid-fluid pairs (fluid key `pressure_gradient`):
///  - Symmetric (`symmetric`): Eq. 5.2b, a_a = -sum_b m_b (p_a/rho_a^2 + p_b/rho_b^2)
///    grad W_ab. With `continuity_form: mass` energy-consistent; with Eq. 5.1a it leaves the power
///    1/2 sum m_a m_b (v_ab . grad W)(1/rho_b - 1/rho_a)(p_a/rho_a - p_b/rho_b).
///  - HuAdams (`hu_adams`): Hu & Adams (2006), a_a = -(1/m_a) sum_b (V_a^2 + V_b^2) p~_ab grad W_ab,
///    p~_ab = (rho_b p_a + rho_a p_b)/(rho_a + rho_b).
///  - Volume (`volume`, the default since b84d7bb): the thesis' Eq. 5.2a, grad p_a = sum_b V_b (p_a + p_b) grad W_ab, i.e.
///    a_a = -sum_b m_b (p_a + p_b)/(rho_a rho_b) grad W_ab (pair force -m_a m_b (p_a + p_b)/
///    (rho_a rho_b) grad W, antisymmetric). With the continuity Eq. 5.1a (drho_a/dt = rho_a sum_b
///    V_b v_ab . grad W) the rate of the compression energy sum m_a e(rho_a), de/drho = p/rho^2,
///    is 1/2 sum_ab m_a m_b (p_a + p_b)/(rho_a rho_b) v_ab . grad W, exactly minus the power of
///    these forces: kinetic + compression energy is conserved pair by pair. Weighted by the
///    neighbour's volume, not its mass, so that at rest between fluids of unequal density the
///    sum cancels as for a single fluid (docs/drainage.md "A lighter gas in the throat").
/// Each form uses p - p_ref (p_ref the background pressure with `pressure_reference: background`,
/// else 0); with p_ref the conserved energy is sum m (e(rho) + p_ref / rho) + kinetic.
enum class FluidPressureForm { Symmetric, HuAdams, Volume };

struct FluidFluidOptions {
  FluidPressureForm form = FluidPressureForm::Symmetric;  ///< pressure gradient of the pairs
  double pOff = 0.0;       ///< pressure reference subtracted in the pressure (Hu-Adams, Eq. 5.2a;
                           ///< Eq. 5.2b has it in its precomputed (p - p_ref)/rho^2)
  double alpha = 0.0;      ///< artificial viscosity (0: off)
  double h = 0.0;          ///< smoothing length
};

/// Accelerations of one side from the pair, by term (the gather loop sums them separately).
template <int D>
struct FluidFluidAccel {
  Vec<D> pressure = Vec<D>::Zero(), viscous = Vec<D>::Zero(), artificial = Vec<D>::Zero();
};

// The kernel derivative and the artificial viscosity of the vectorised block of fluid_half.cpp
// are libcore's branch-free forms (KernelShape::dOverQBlend, artificialViscosityPiBlend), the
// same expressions every other caller uses; GCC 12 at -O3 vectorises the block in float for SSE2
// (4 lanes) and in float and double for AVX2 (8 / 4 lanes, the AVX2 copy of fluid_half.cpp);
// SSE2 double stays scalar (no conversion of a 64-bit mask to double).

/// The coefficients of a fluid-fluid pair's accelerations: side a gets pressureA grad W +
/// viscousA v_ab + artificialA grad W, side b pressureB grad W + viscousB v_ab + artificialB grad W
/// (grad W = grad_a W_ab = F r_ab). The one implementation of the terms listed at the top of this
/// file, branch-free (selects) so that the block loop of fluid_half.cpp vectorises, for Real =
/// double or float; fluidFluidPair below (the gather loop and the scalar half loop) calls it with
/// double. vr = v_ab . r_ab, F the kernel's F(|r_ab|), r2 = |r_ab|^2. kArtificial = false
/// (artificial_viscosity 0, the default) leaves out Eq. 2.64, whose Pi is then exactly 0: the
/// scalar loops call it so (two divisions per pair that eae9733 had made unconditional: 14 % of
/// the 2D two-phase step, docs/performance.md); the vectorised block keeps the one branch-free form.
template <class Real>
struct FluidFluidCoefficients {
  Real pressureA, viscousA, artificialA, pressureB, viscousB, artificialB;
};
template <class Real, FluidPressureForm kForm, bool kArtificial = true>
inline FluidFluidCoefficients<Real> fluidFluidCoefficients(
    Real F, Real vr, Real r2, const FluidPairParticleT<Real>& a, const FluidPairParticleT<Real>& b,
    Real muBar, Real fab, Real pOff, Real alpha, Real h) {
  FluidFluidCoefficients<Real> c;
  if constexpr (kForm == FluidPressureForm::HuAdams) {
    const Real pt = (b.rho * (a.p - pOff) + a.rho * (b.p - pOff)) / (a.rho + b.rho);
    const Real sq = a.V * a.V + b.V * b.V;
    const Real vvA = sq / a.m, vvB = sq / b.m;
    c.pressureA = -(vvA * pt);
    c.viscousA = fab * vvA * Real(0.5) * muBar * F;
    c.pressureB = vvB * pt;
    c.viscousB = -(fab * vvB * Real(0.5) * muBar * F);
  } else {
    if constexpr (kForm == FluidPressureForm::Volume) {
      // Eq. 5.2a: (p_a + p_b)/(rho_a rho_b), times m_b for a and m_a for b, so that the two
      // forces m_a a_a and m_b a_b are equal and opposite bit for bit.
      const Real ps = ((a.p - pOff) + (b.p - pOff)) / (a.rho * b.rho);
      c.pressureA = -(b.m * ps);
      c.pressureB = a.m * ps;
    } else {
      const Real ps = a.pRho2 + b.pRho2;
      c.pressureA = -(b.m * ps);  // Eq. 5.2b
      c.pressureB = a.m * ps;
    }
    c.viscousA = fab * muBar * b.V * F / a.rho;  // Eq. 5.4 (0 for an inviscid pair)
    c.viscousB = -(fab * muBar * a.V * F / b.rho);
  }
  // Eq. 2.64 (alpha = 0: Pi = 0)
  if constexpr (kArtificial) {
    const Real Pi = artificialViscosityPiBlend<Real>(vr, r2, h, alpha, Real(0), a.soundSpeed,
                                                     b.soundSpeed, a.rho, b.rho);
    c.artificialA = -(b.m * Pi);
    c.artificialB = a.m * Pi;
  } else {
    c.artificialA = c.artificialB = Real(0);
  }
  return c;
}

/// Forced inlining of the per-pair function of the scalar pair loops. With three pressure forms
/// (bed210c added Eq. 5.2a) times the artificial-viscosity switch, fluidFluidPair grew past GCC
/// 12's inlining limits and was called out of line from the gather loop (fluid_module.cpp) and
/// the half list's scalar path (fluid_half.cpp): arguments and results through memory on every
/// pair, +14 % instructions of the 2D two-phase step (oscillating drop, callgrind; docs/
/// performance.md). Inlining does not change the arithmetic of the default build (baseline
/// x86-64, no FMA to contract into), so the results are bit for bit those of the call.
#if defined(__GNUC__)
#define PORESPH_PAIR_INLINE inline __attribute__((always_inline))
#else
#define PORESPH_PAIR_INLINE inline
#endif

/// The pair terms of a (and of b when kBoth) as vectors: r = x_a - x_b, gradW = F r, vab = v_a -
/// v_b, muBar the mean viscosity (Eq. 5.4), fab the pair's lattice normalisation factor.
template <int D, bool kBoth>
PORESPH_PAIR_INLINE void fluidFluidPair(const Vec<D>& r, const Vec<D>& gradW, double F, const Vec<D>& vab,
                           const FluidPairParticle& a, const FluidPairParticle& b, double muBar,
                           double fab, const FluidFluidOptions& o, FluidFluidAccel<D>& ta,
                           FluidFluidAccel<D>& tb) {
  const double vr = vab.dot(r), r2 = r.squaredNorm();
  // alpha = 0: no Pi (it is exactly 0 then, and the sums it feeds stay +0 either way, so the
  // result is bit for bit that of the branch-free form)
  const bool av = o.alpha > 0.0;
  auto coefficients = [&](auto form) {
    constexpr FluidPressureForm kForm = decltype(form)::value;
    return av ? fluidFluidCoefficients<double, kForm, true>(F, vr, r2, a, b, muBar, fab, o.pOff, o.alpha, o.h)
              : fluidFluidCoefficients<double, kForm, false>(F, vr, r2, a, b, muBar, fab, o.pOff, o.alpha, o.h);
  };
  using F0 = std::integral_constant<FluidPressureForm, FluidPressureForm::Symmetric>;
  using F1 = std::integral_constant<FluidPressureForm, FluidPressureForm::HuAdams>;
  using F2 = std::integral_constant<FluidPressureForm, FluidPressureForm::Volume>;
  const FluidFluidCoefficients<double> c = o.form == FluidPressureForm::HuAdams  ? coefficients(F1{})
                                           : o.form == FluidPressureForm::Volume ? coefficients(F2{})
                                                                                 : coefficients(F0{});
  ta.pressure = c.pressureA * gradW;
  ta.viscous = c.viscousA * vab;
  ta.artificial = c.artificialA * gradW;
  if (kBoth) {
    tb.pressure = c.pressureB * gradW;
    tb.viscous = c.viscousB * vab;
    tb.artificial = c.artificialB * gradW;
  }
}

/// The continuity term of fluid a from a neighbour b of another fluid with the interface
/// velocity of the linearised (acoustic) Riemann problem between them in place of v_b (fluid key
/// `continuity_interface: acoustic`; Zhang, Hu & Adams 2017, Rezavand, Zhang & Hu 2020):
/// v* = (Z_a v_a + Z_b v_b)/(Z_a + Z_b), Z = rho0 c0 the acoustic impedance, and the term of Eq.
/// 5.1a taken over the half pair a - interface, 2 V_b (v_a - v*) . grad W = w_ab V_b v_ab . grad W
/// with w_ab = 2 Z_b / (Z_a + Z_b). Equal impedances give w = 1, Eq. 5.1a exactly; w_ab + w_ba = 2.
/// At water/gas density ratio 1000 with equal B = rho0 c0^2 (Z_w / Z_g = 31.6) the water takes
/// 0.06 of the gas neighbours' approach velocity, the gas 1.94 of the water's: for the water the
/// light gas is nearly a free surface, for the gas the water nearly a wall (docs/drainage.md).
inline double interfaceContinuityWeight(double Za, double Zb) { return 2.0 * Zb / (Za + Zb); }

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

/// V = m / rho of particle k, computed where a pair loop reads it instead of held per particle
/// (issue 17, memory: 8 B per particle; the same IEEE quotient, so the same bits).
struct Volumes {
  const double* m = nullptr;
  const double* rho = nullptr;
  double operator[](Index k) const { return m[k] / rho[k]; }
};

/// The wall side of a fluid-wall pair (Adami et al. 2012 fixed boundary: extrapolated pressure,
/// no-slip velocity, the wall's own volume and velocity), built from the module's store pointers
/// `f` (FluidModule::Fields) for wall particle k; `wallRho` the wall density for the fluid of the
/// pair when precomputed (null: computed per pair). Used by the gather and the symmetric loops.
template <int D, class Fields>
inline BoundaryPairSide<D> wallPairSide(const Fields& f, Index k, const Volumes& vol, const double* wallRho,
                                        const Vec<D>& vk) {
  BoundaryPairSide<D> s;
  s.p = f.p[k];
  s.volume = vol[k];
  s.rho = wallRho ? wallRho[k] : 0.0;
  s.v = vk;
  // Without wall_velocity (inviscid fluids: the viscous term that reads it is zero) the
  // boundary's own velocity.
  for (int a = 0; a < D; ++a) s.vNoSlip[a] = f.vw ? f.vw[k * D + a] : vk[a];
  return s;
}

}  // namespace poresph
