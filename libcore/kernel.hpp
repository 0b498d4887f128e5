#pragma once
// Smoothing kernels W(r, h), their radial derivative dW/dr and F(r) = (1/r) dW/dr, so that
// grad_a W_ab = r_ab F(r_ab) (thesis Eqs. 2.36-2.38).
//
// Kernels: cubic B-spline (Eq. 2.11, support 2h), Gaussian (Eq. 2.10, truncated at 2 sqrt(2) h as
// in the thesis and renormalised over the truncated support so that it integrates to one),
// Wendland C2 (support 2h) and the quintic spline of Morris (support 3h).
#include <cmath>
#include <string>

#include "libcore/types.hpp"

namespace poresph {

enum class KernelType { CubicSpline, Gaussian, WendlandC2, QuinticSpline };

/// Parses "cubic_spline", "gaussian", "wendland_c2", "quintic_spline"; throws InputError.
KernelType parseKernelType(const std::string& name);
std::string kernelTypeName(KernelType t);
/// Support radius in units of h.
double kernelSupportFactor(KernelType t);

class Kernel {
 public:
  Kernel() = default;
  Kernel(KernelType type, int dimension, double h);

  KernelType type() const { return type_; }
  int dimension() const { return dim_; }
  double h() const { return h_; }
  /// Radius beyond which W = 0 (kappa h in Eq. 2.8).
  double support() const { return support_; }

  /// W(r, h).
  double value(double r) const {
    const double q = r * invH_;
    return norm_ * shape(q);
  }
  /// dW/dr.
  double derivative(double r) const {
    const double q = r * invH_;
    return norm_ * invH_ * q * shapeDerivativeOverQ(q);
  }
  /// F(r) = (1/r) dW/dr (Eq. 2.38); finite at r = 0.
  double F(double r) const {
    const double q = r * invH_;
    return norm_ * invH_ * invH_ * shapeDerivativeOverQ(q);
  }
  /// grad_a W_ab for r_ab = r_a - r_b (Eq. 2.36).
  template <int D>
  Vec<D> gradient(const Vec<D>& rab) const {
    return rab * F(rab.norm());
  }
  /// Calls f(FixedKernel<type, D>) with this kernel's type fixed at compile time, so that a
  /// pair loop written as a generic lambda pays one switch per loop instead of one per pair.
  /// D must be this kernel's dimension. The values equal value() and F() bit for bit.
  template <int D, class Fn>
  decltype(auto) withFixedType(Fn&& f) const;

 private:
  template <KernelType K, int D>
  friend struct FixedKernel;
  // w(q): dimensionless shape; W = norm_ * w(q) with norm_ = sigma_d / h^d.
  double shape(double q) const;
  // (1/q) dw/dq, finite at q = 0.
  double shapeDerivativeOverQ(double q) const;

  KernelType type_ = KernelType::CubicSpline;
  int dim_ = 3;
  double h_ = 1.0;
  double invH_ = 1.0;
  double norm_ = 1.0;
  double support_ = 2.0;
  double qMax_ = 2.0;
};

/// The dimensionless shapes w(q) and (1/q) dw/dq with the kernel type fixed at compile time
/// (D matters only for Wendland's 1D form). Written once: Kernel's run-time switch calls them.
template <KernelType K, int D>
struct KernelShape {
  static double w(double q, double qMax) {
    if constexpr (K == KernelType::CubicSpline) {  // Eq. 2.11
      (void)qMax;
      if (q < 1.0) return 2.0 / 3.0 - q * q + 0.5 * q * q * q;
      if (q < 2.0) { const double t = 2.0 - q; return t * t * t / 6.0; }
      return 0.0;
    } else if constexpr (K == KernelType::Gaussian) {  // Eq. 2.10, truncated
      return q < qMax ? std::exp(-q * q) : 0.0;
    } else if constexpr (K == KernelType::WendlandC2) {
      (void)qMax;
      if (q < 2.0) {
        const double t = 1.0 - 0.5 * q;
        if (D == 1) return t * t * t * (1.5 * q + 1.0);
        return t * t * t * t * (2.0 * q + 1.0);
      }
      return 0.0;
    } else {
      (void)qMax;
      if (q >= 3.0) return 0.0;
      const double a = 3.0 - q, b = 2.0 - q, c = 1.0 - q;
      double w = a * a * a * a * a;
      if (q < 2.0) w -= 6.0 * b * b * b * b * b;
      if (q < 1.0) w += 15.0 * c * c * c * c * c;
      return w;
    }
  }
  static double dOverQ(double q, double qMax) {
    if constexpr (K == KernelType::CubicSpline || K == KernelType::WendlandC2) {
      return dOverQBlend<double>(q, qMax);
    } else if constexpr (K == KernelType::Gaussian) {
      return q < qMax ? -2.0 * std::exp(-q * q) : 0.0;
    } else {
      (void)qMax;
      if (q >= 3.0) return 0.0;
      if (q < 1e-8) return -120.0;  // limit of w'(q)/q = w''(0)
      const double a = 3.0 - q, b = 2.0 - q, c = 1.0 - q;
      double d = -5.0 * a * a * a * a;
      if (q < 2.0) d += 30.0 * b * b * b * b;
      if (q < 1.0) d -= 75.0 * c * c * c * c;
      return d / q;
    }
  }
  /// (1/q) dw/dq for Real = double or float, the one expression of the cubic spline (Eq. 2.11)
  /// and Wendland C2 derivative that every caller uses (dOverQ above is this in double). Branch-
  /// free: both rings are computed and blended with 0/1 weights (x * 1 + y * 0 = x exactly for
  /// finite y) and the comparisons are the quiet ones (__builtin_isless), so that a loop over
  /// pairs calling it vectorises under GCC's default -ftrapping-math (the fluid-fluid block of
  /// physics/fluid/fluid_half.cpp). The Gaussian and quintic kernels go through dOverQ (scalar).
  template <class Real>
  static Real dOverQBlend(Real q, double qMax) {
    if constexpr (K == KernelType::CubicSpline) {
      (void)qMax;
      const Real t = Real(2) - q;
      const Real inner = Real(-2) + Real(1.5) * q;
      // the outer ring is used for q >= 1 only: a floor keeps its value finite for q -> 0
      const Real qSafe = __builtin_isgreater(q, Real(0.5)) ? q : Real(0.5);
      const Real outer = Real(-0.5) * t * t / qSafe;
      const Real wIn = static_cast<Real>(__builtin_isless(q, Real(1)));
      const Real wOut = static_cast<Real>(__builtin_isless(q, Real(2))) - wIn;
      return wIn * inner + wOut * outer;
    } else if constexpr (K == KernelType::WendlandC2) {
      (void)qMax;
      const Real t = Real(1) - Real(0.5) * q;
      const Real v = D == 1 ? Real(-3) * t * t : Real(-5) * t * t * t;
      return v * static_cast<Real>(__builtin_isless(q, Real(2)));
    } else {
      return static_cast<Real>(dOverQ(static_cast<double>(q), qMax));
    }
  }
};

/// A kernel with its type fixed at compile time (Kernel::withFixedType): value() and F() equal
/// Kernel's bit for bit.
template <KernelType K, int D>
struct FixedKernel {
  double invH = 1.0, norm = 1.0, qMax = 2.0, support = 2.0;
  explicit FixedKernel(const Kernel& k)
      : invH(k.invH_), norm(k.norm_), qMax(k.qMax_), support(k.support_) {}
  double value(double r) const { return norm * KernelShape<K, D>::w(r * invH, qMax); }
  double F(double r) const {
    const double q = r * invH;
    return norm * invH * invH * KernelShape<K, D>::dOverQ(q, qMax);
  }
};

inline double Kernel::shape(double q) const {
  switch (type_) {
    case KernelType::CubicSpline: return KernelShape<KernelType::CubicSpline, 3>::w(q, qMax_);
    case KernelType::Gaussian: return KernelShape<KernelType::Gaussian, 3>::w(q, qMax_);
    case KernelType::WendlandC2:
      return dim_ == 1 ? KernelShape<KernelType::WendlandC2, 1>::w(q, qMax_)
                       : KernelShape<KernelType::WendlandC2, 3>::w(q, qMax_);
    case KernelType::QuinticSpline: return KernelShape<KernelType::QuinticSpline, 3>::w(q, qMax_);
  }
  return 0.0;
}

inline double Kernel::shapeDerivativeOverQ(double q) const {
  switch (type_) {
    case KernelType::CubicSpline: return KernelShape<KernelType::CubicSpline, 3>::dOverQ(q, qMax_);
    case KernelType::Gaussian: return KernelShape<KernelType::Gaussian, 3>::dOverQ(q, qMax_);
    case KernelType::WendlandC2:
      return dim_ == 1 ? KernelShape<KernelType::WendlandC2, 1>::dOverQ(q, qMax_)
                       : KernelShape<KernelType::WendlandC2, 3>::dOverQ(q, qMax_);
    case KernelType::QuinticSpline:
      return KernelShape<KernelType::QuinticSpline, 3>::dOverQ(q, qMax_);
  }
  return 0.0;
}

template <int D, class Fn>
decltype(auto) Kernel::withFixedType(Fn&& f) const {
  if (D != dim_) throw std::logic_error("Kernel::withFixedType: dimension differs from the kernel's");
  switch (type_) {
    case KernelType::Gaussian: return f(FixedKernel<KernelType::Gaussian, D>(*this));
    case KernelType::WendlandC2: return f(FixedKernel<KernelType::WendlandC2, D>(*this));
    case KernelType::QuinticSpline: return f(FixedKernel<KernelType::QuinticSpline, D>(*this));
    case KernelType::CubicSpline: break;
  }
  return f(FixedKernel<KernelType::CubicSpline, D>(*this));
}

}  // namespace poresph
