#pragma once
// Monaghan's artificial viscosity, thesis Eqs. 2.64-2.65, written once for every module (fluid,
// solid, coupling). The acceleration of particle a from neighbour b is -m_b Pi_ab grad_a W_ab.
#include "libcore/types.hpp"

namespace poresph {

/// Pi_ab = (alpha c_ab nu_ab + beta nu_ab^2) / rho_ab for approaching pairs (v_ab . r_ab < 0),
/// 0 otherwise, with nu_ab = -h v_ab . r_ab / (|r_ab|^2 + 0.01 h^2) (Eq. 2.65), c_ab and rho_ab
/// the means of the two particles' sound speeds and densities (Eq. 2.64), from vr = v_ab . r_ab
/// and r2 = |r_ab|^2, for Real = double or float. The one expression of Eqs. 2.64-2.65: branch-
/// free (the receding case is a 0 factor, the quiet comparison __builtin_isless) so that the
/// fluid-fluid block of physics/fluid/fluid_half.cpp vectorises; the vector form below calls it.
template <class Real>
inline Real artificialViscosityPiBlend(Real vr, Real r2, Real h, Real alpha, Real beta, Real ca,
                                       Real cb, Real rhoa, Real rhob) {
  const Real nu = -h * vr / (r2 + Real(0.01) * h * h);                                      // 2.65
  const Real pi = (alpha * Real(0.5) * (ca + cb) * nu + beta * nu * nu) / (Real(0.5) * (rhoa + rhob));  // 2.64
  return pi * static_cast<Real>(__builtin_isless(vr, Real(0)));
}

/// Pi_ab of Eqs. 2.64-2.65 from the pair's v_ab = v_a - v_b and r_ab = x_a - x_b.
template <int D>
inline double artificialViscosityPi(const Vec<D>& vab, const Vec<D>& rab, double h, double alpha,
                                    double beta, double ca, double cb, double rhoa,
                                    double rhob) {
  return artificialViscosityPiBlend<double>(vab.dot(rab), rab.squaredNorm(), h, alpha, beta, ca,
                                            cb, rhoa, rhob);
}

}  // namespace poresph
