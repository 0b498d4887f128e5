#include "libcore/kernel.hpp"

#include <cmath>

namespace poresph {

namespace {
constexpr double kPi = 3.14159265358979323846;
const double kGaussianCut = 2.0 * std::sqrt(2.0);  // thesis Sec. 2.1.1: lambda = 2 sqrt(2) h
}  // namespace

KernelType parseKernelType(const std::string& name) {
  if (name == "cubic_spline") return KernelType::CubicSpline;
  if (name == "gaussian") return KernelType::Gaussian;
  if (name == "wendland_c2") return KernelType::WendlandC2;
  if (name == "quintic_spline") return KernelType::QuinticSpline;
  throw InputError("unknown kernel '" + name +
                   "' (expected cubic_spline, gaussian, wendland_c2 or quintic_spline)");
}

std::string kernelTypeName(KernelType t) {
  switch (t) {
    case KernelType::CubicSpline: return "cubic_spline";
    case KernelType::Gaussian: return "gaussian";
    case KernelType::WendlandC2: return "wendland_c2";
    case KernelType::QuinticSpline: return "quintic_spline";
  }
  return "?";
}

double kernelSupportFactor(KernelType t) {
  switch (t) {
    case KernelType::CubicSpline: return 2.0;
    case KernelType::Gaussian: return kGaussianCut;
    case KernelType::WendlandC2: return 2.0;
    case KernelType::QuinticSpline: return 3.0;
  }
  return 2.0;
}

Kernel::Kernel(KernelType type, int dimension, double h)
    : type_(type), dim_(dimension), h_(h), invH_(1.0 / h) {
  if (!(h > 0.0) || !std::isfinite(h))
    throw InputError("kernel: smoothing length h must be positive and finite, got " +
                     std::to_string(h));
  if (dimension < 1 || dimension > 3)
    throw InputError("kernel: dimension must be 1, 2 or 3");
  qMax_ = kernelSupportFactor(type);
  support_ = qMax_ * h;
  double sigma = 1.0;  // normalisation of the dimensionless shape in d dimensions
  switch (type) {
    case KernelType::CubicSpline:  // M of Eq. 2.11
      sigma = dimension == 1 ? 1.0 : dimension == 2 ? 15.0 / (7.0 * kPi) : 3.0 / (2.0 * kPi);
      break;
    case KernelType::Gaussian: {
      // Eq. 2.10 has sigma = pi^(-d/2) for the untruncated kernel; renormalise over |q| < qMax.
      const double qm = qMax_, e = std::exp(-qm * qm);
      double integral = 0.0;
      if (dimension == 1) integral = std::sqrt(kPi) * std::erf(qm);
      if (dimension == 2) integral = kPi * (1.0 - e);
      if (dimension == 3)
        integral = 4.0 * kPi * (0.25 * std::sqrt(kPi) * std::erf(qm) - 0.5 * qm * e);
      sigma = 1.0 / integral;
      break;
    }
    case KernelType::WendlandC2:
      sigma = dimension == 1 ? 5.0 / 8.0 : dimension == 2 ? 7.0 / (4.0 * kPi) : 21.0 / (16.0 * kPi);
      break;
    case KernelType::QuinticSpline:
      // Morris (1996): 1/120, 7/(478 pi), 1/(120 pi). The 3/(359 pi) found in some texts is off
      // by 0.28 % (the integral of the 3D shape is exactly 120 pi; tests/unit/test_kernel.cpp).
      sigma = dimension == 1 ? 1.0 / 120.0 : dimension == 2 ? 7.0 / (478.0 * kPi) : 1.0 / (120.0 * kPi);
      break;
  }
  norm_ = sigma * std::pow(invH_, dimension);
}

}  // namespace poresph
