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

 private:
  // w(q): dimensionless shape; W = norm_ * w(q) with norm_ = sigma_d / h^d.
  double shape(double q) const {
    switch (type_) {
      case KernelType::CubicSpline:  // Eq. 2.11
        if (q < 1.0) return 2.0 / 3.0 - q * q + 0.5 * q * q * q;
        if (q < 2.0) { const double t = 2.0 - q; return t * t * t / 6.0; }
        return 0.0;
      case KernelType::Gaussian:  // Eq. 2.10, truncated
        return q < qMax_ ? std::exp(-q * q) : 0.0;
      case KernelType::WendlandC2:
        if (q < 2.0) {
          const double t = 1.0 - 0.5 * q;
          if (dim_ == 1) return t * t * t * (1.5 * q + 1.0);
          return t * t * t * t * (2.0 * q + 1.0);
        }
        return 0.0;
      case KernelType::QuinticSpline: {
        if (q >= 3.0) return 0.0;
        const double a = 3.0 - q, b = 2.0 - q, c = 1.0 - q;
        double w = a * a * a * a * a;
        if (q < 2.0) w -= 6.0 * b * b * b * b * b;
        if (q < 1.0) w += 15.0 * c * c * c * c * c;
        return w;
      }
    }
    return 0.0;
  }
  // (1/q) dw/dq, finite at q = 0.
  double shapeDerivativeOverQ(double q) const {
    switch (type_) {
      case KernelType::CubicSpline:
        if (q < 1.0) return -2.0 + 1.5 * q;
        if (q < 2.0) { const double t = 2.0 - q; return -0.5 * t * t / q; }
        return 0.0;
      case KernelType::Gaussian:
        return q < qMax_ ? -2.0 * std::exp(-q * q) : 0.0;
      case KernelType::WendlandC2:
        if (q < 2.0) {
          const double t = 1.0 - 0.5 * q;
          if (dim_ == 1) return -3.0 * t * t;
          return -5.0 * t * t * t;
        }
        return 0.0;
      case KernelType::QuinticSpline: {
        if (q >= 3.0) return 0.0;
        if (q < 1e-8) return -120.0;  // limit of w'(q)/q = w''(0)
        const double a = 3.0 - q, b = 2.0 - q, c = 1.0 - q;
        double d = -5.0 * a * a * a * a;
        if (q < 2.0) d += 30.0 * b * b * b * b;
        if (q < 1.0) d -= 75.0 * c * c * c * c;
        return d / q;
      }
    }
    return 0.0;
  }

  KernelType type_ = KernelType::CubicSpline;
  int dim_ = 3;
  double h_ = 1.0;
  double invH_ = 1.0;
  double norm_ = 1.0;
  double support_ = 2.0;
  double qMax_ = 2.0;
};

}  // namespace poresph
