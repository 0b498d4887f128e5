// Unit tests of the smoothing kernels (libcore/kernel.hpp): cubic spline (thesis Eq. 2.11),
// truncated Gaussian (Eq. 2.10), Wendland C2 and quintic spline, in 1D, 2D and 3D.
//
// Checked against closed forms: normalisation (radial quadrature to 1e-12 and lattice sums
// sum_j W(x_j) dx^d to 1e-6), zero first moment, the gradient moment
// sum_j V_j (x_j - x_i) (x) grad_i W_ij = I, dW/dr and grad W against central differences,
// F(r) = W'(r)/r (Eq. 2.38) finite at r = 0, W = 0 beyond the support, continuity at the
// piece boundaries, and h-scaling W(r, h) = h^-d w(r/h).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "libcore/kernel.hpp"

using namespace poresph;

namespace {

constexpr double kPi = 3.14159265358979323846;
const KernelType kAll[] = {KernelType::CubicSpline, KernelType::Gaussian, KernelType::WendlandC2,
                           KernelType::QuinticSpline};

std::string label(KernelType t, int d) { return kernelTypeName(t) + " " + std::to_string(d) + "D"; }

// Radii (in units of h) where the piecewise definition changes.
std::vector<double> breakpoints(KernelType t) {
  switch (t) {
    case KernelType::CubicSpline: return {1.0, 2.0};
    case KernelType::Gaussian: return {2.0 * std::sqrt(2.0)};
    case KernelType::WendlandC2: return {2.0};
    case KernelType::QuinticSpline: return {1.0, 2.0, 3.0};
  }
  return {};
}

// 8-point Gauss-Legendre on [a, b]: exact for polynomials up to degree 15.
double gaussLegendre(double a, double b, const std::function<double(double)>& f) {
  static const double xs[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                               0.9602898564975363};
  static const double ws[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                               0.1012285362903763};
  const double c = 0.5 * (a + b), r = 0.5 * (b - a);
  double s = 0.0;
  for (int k = 0; k < 4; ++k) s += ws[k] * (f(c + r * xs[k]) + f(c - r * xs[k]));
  return s * r;
}

// Integral of W over R^d via the radial integral, split at the breakpoints (sub-intervals so
// that the Gaussian is integrated to round-off too).
double radialIntegral(const Kernel& k) {
  const int d = k.dimension();
  const double surface = d == 1 ? 2.0 : d == 2 ? 2.0 * kPi : 4.0 * kPi;  // area of unit sphere
  std::vector<double> edges{0.0};
  for (double b : breakpoints(k.type())) edges.push_back(b * k.h());
  double total = 0.0;
  for (size_t e = 0; e + 1 < edges.size(); ++e) {
    const int sub = 64;
    for (int s = 0; s < sub; ++s) {
      const double a = edges[e] + (edges[e + 1] - edges[e]) * s / sub;
      const double b = edges[e] + (edges[e + 1] - edges[e]) * (s + 1) / sub;
      total += gaussLegendre(a, b, [&](double r) { return std::pow(r, d - 1) * k.value(r); });
    }
  }
  return surface * total;
}

// Calls f(x, y, z) on the lattice (i + o) * dx (o = offset in cells) covering the support.
template <class F>
void lattice(const Kernel& k, double dx, const double offset[3], F&& f) {
  const int d = k.dimension();
  const int n = static_cast<int>(std::ceil(k.support() / dx)) + 2;
  const int ny = d > 1 ? n : 0, nz = d > 2 ? n : 0;
  for (int a = -n; a <= n; ++a)
    for (int b = -ny; b <= ny; ++b)
      for (int c = -nz; c <= nz; ++c) {
        const double x = (a + offset[0]) * dx, y = d > 1 ? (b + offset[1]) * dx : 0.0,
                     z = d > 2 ? (c + offset[2]) * dx : 0.0;
        f(x, y, z);
      }
}

double latticeSum(const Kernel& k, double dx, const double offset[3]) {
  double s = 0.0;
  lattice(k, dx, offset, [&](double x, double y, double z) {
    s += k.value(std::sqrt(x * x + y * y + z * z));
  });
  return s * std::pow(dx, k.dimension());
}

// Points per h of the lattices: fine enough for 1e-6 with the smooth kernels (measured errors
// are 1e-7 .. 1e-9 at these spacings), coarse enough to run in milliseconds.
int pointsPerH(int d) { return d == 3 ? 12 : d == 2 ? 20 : 80; }

}  // namespace

TEST(Kernel, ClosedFormValues) {
  // Eq. 2.11 with M = 1, 15/(7 pi), 3/(2 pi): W(0) = 2M/3 h^-d, W(h) = M/6 h^-d.
  const double h = 0.37;
  const double M[3] = {1.0, 15.0 / (7.0 * kPi), 3.0 / (2.0 * kPi)};
  for (int d = 1; d <= 3; ++d) {
    const Kernel k(KernelType::CubicSpline, d, h);
    const double hd = std::pow(h, d);
    EXPECT_NEAR(k.value(0.0), 2.0 / 3.0 * M[d - 1] / hd, 1e-14 / hd);
    EXPECT_NEAR(k.value(h), M[d - 1] / 6.0 / hd, 1e-14 / hd);
    EXPECT_NEAR(k.value(1.5 * h), M[d - 1] * 0.125 / 6.0 / hd, 1e-14 / hd);
    EXPECT_DOUBLE_EQ(k.support(), 2.0 * h);
  }
  // Gaussian: the thesis' support 2 sqrt(2) h; before renormalisation W(0) = (h sqrt(pi))^-d.
  for (int d = 1; d <= 3; ++d) {
    const Kernel k(KernelType::Gaussian, d, h);
    EXPECT_DOUBLE_EQ(k.support(), 2.0 * std::sqrt(2.0) * h);
    const double untruncated = std::pow(h * std::sqrt(kPi), -d);
    // The truncation removes < 0.2 % of the mass, so the renormalised peak is slightly higher.
    EXPECT_GT(k.value(0.0), untruncated);
    EXPECT_LT(k.value(0.0), untruncated * 1.002);
    EXPECT_NEAR(k.value(0.5 * h) / k.value(0.0), std::exp(-0.25), 1e-14);
  }
  // Quintic spline in 3D: W(0) = (3^5 - 6 2^5 + 15) / (120 pi h^3) = 66 / (120 pi h^3).
  EXPECT_NEAR(Kernel(KernelType::QuinticSpline, 3, 1.0).value(0.0), 66.0 / (120.0 * kPi), 1e-15);
  // Wendland C2 in 2D/3D: W(0) = 7/(4 pi h^2), 21/(16 pi h^3).
  EXPECT_NEAR(Kernel(KernelType::WendlandC2, 2, 1.0).value(0.0), 7.0 / (4.0 * kPi), 1e-15);
  EXPECT_NEAR(Kernel(KernelType::WendlandC2, 3, 1.0).value(0.0), 21.0 / (16.0 * kPi), 1e-15);
  EXPECT_DOUBLE_EQ(Kernel(KernelType::QuinticSpline, 2, 0.5).support(), 1.5);
}

TEST(Kernel, NormalisationByRadialQuadrature) {
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const Kernel k(t, d, 0.7);
      EXPECT_NEAR(radialIntegral(k), 1.0, 1e-12) << label(t, d);
    }
}

TEST(Kernel, NormalisationOnAFineLattice) {
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const double h = 1.3e-3;  // SI: a pore-scale smoothing length
      const Kernel k(t, d, h);
      const double dx = h / pointsPerH(d);
      if (t != KernelType::Gaussian) {
        const double centred[3] = {0.0, 0.0, 0.0}, shifted[3] = {0.31, 0.17, 0.43};
        EXPECT_NEAR(latticeSum(k, dx, centred), 1.0, 1e-6) << label(t, d);
        EXPECT_NEAR(latticeSum(k, dx, shifted), 1.0, 1e-6) << label(t, d);
      } else {
        // The truncated Gaussian jumps by W(2 sqrt 2 h) at its edge, so a single lattice sum has
        // an O(1e-6) quasi-random error from the points near the edge. The mean over lattice
        // offsets is an unbiased estimate of the integral: average 16 offsets (R2 sequence).
        double mean = 0.0;
        const int nOff = 16;
        for (int s = 1; s <= nOff; ++s) {
          const double g = 1.22074408460575947536;  // plastic number, R3 sequence
          const double off[3] = {std::fmod(s / g, 1.0), std::fmod(s / (g * g), 1.0),
                                 std::fmod(s / (g * g * g), 1.0)};
          mean += latticeSum(k, dx, off) / nOff;
        }
        EXPECT_NEAR(mean, 1.0, 1e-6) << label(t, d);
      }
    }
}

TEST(Kernel, ZeroFirstMomentAndUnitGradientMoment) {
  // On a lattice shifted off the particle (no symmetry of the points about it):
  //   sum_j V_j (x_j - x_i) W_ij = 0, sum_j V_j grad_i W_ij = 0,
  //   sum_j V_j (x_j - x_i) (x) grad_i W_ij = I (the continuous identity, by parts).
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const double h = 2.0;
      const Kernel k(t, d, h);
      const double dx = h / pointsPerH(d), V = std::pow(dx, d);
      const double off[3] = {0.31, 0.17, 0.43};
      Eigen::Vector3d m1 = Eigen::Vector3d::Zero(), g = Eigen::Vector3d::Zero();
      Eigen::Matrix3d gm = Eigen::Matrix3d::Zero();
      lattice(k, dx, off, [&](double x, double y, double z) {
        const Eigen::Vector3d xj(x, y, z);  // x_j - x_i with x_i = 0
        const double r = xj.norm();
        m1 += V * xj * k.value(r);
        const Eigen::Vector3d gradI = -xj * k.F(r);  // grad_i W_ij = (x_i - x_j) F(r_ij)
        g += V * gradI;
        gm += V * xj * gradI.transpose();
      });
      // The truncated Gaussian misses the edge term of the integration by parts (see the next
      // test): its diagonal is 1 - S_d cut^d W(cut-) / d instead of 1.
      double diag = 1.0, tolGrad = 1e-5;
      if (t == KernelType::Gaussian) {
        const double cut = k.support(), S = d == 1 ? 2.0 : d == 2 ? 2.0 * kPi : 4.0 * kPi;
        diag -= S * std::pow(cut, d) * k.value(cut * (1.0 - 1e-15)) / d;
        tolGrad = 1e-4;
      }
      // The Gaussian's edge jump leaves an O(1e-5) lattice error in the odd moments too.
      const double tolOdd = t == KernelType::Gaussian ? 1e-4 : 1e-6;
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(m1[a], 0.0, tolOdd * h) << label(t, d) << " axis " << a;
        EXPECT_NEAR(g[a], 0.0, tolOdd / h) << label(t, d) << " axis " << a;
        for (int b = 0; b < 3; ++b) {
          const double expect = (a == b && a < d) ? diag : 0.0;
          EXPECT_NEAR(gm(a, b), expect, tolGrad) << label(t, d) << " (" << a << "," << b << ")";
        }
      }
    }
}

TEST(Kernel, GaussianGradientMomentMissesExactlyTheEdgeTerm) {
  // By parts, with the jump of the truncated Gaussian at the cut radius c:
  //   int x_a x_b W'(r)/r dV = delta_ab / d * int r W'(r) dV
  //                          = delta_ab / d * (S_d c^d W(c-) - d int W dV)
  // so sum_j V_j x_j (x) grad_i W_ij = I (1 - S_d c^d W(c-) / d). Checked to 5e-5, i.e. 5 % of
  // the edge term.
  for (int d = 1; d <= 3; ++d) {
    const double h = 1.0;
    const Kernel k(KernelType::Gaussian, d, h);
    const double cut = k.support(), S = d == 1 ? 2.0 : d == 2 ? 2.0 * kPi : 4.0 * kPi;
    const double expect = 1.0 - S * std::pow(cut, d) * k.value(cut * (1.0 - 1e-15)) / d;
    const double dx = h / 24.0, V = std::pow(dx, d);
    const int nOff = 8;
    double mean = 0.0;
    for (int s = 1; s <= nOff; ++s) {
      const double g = 1.22074408460575947536;
      const double off[3] = {std::fmod(s / g, 1.0), std::fmod(s / (g * g), 1.0),
                             std::fmod(s / (g * g * g), 1.0)};
      double m = 0.0;
      lattice(k, dx, off, [&](double x, double y, double z) {
        m += V * x * x * k.F(std::sqrt(x * x + y * y + z * z));  // -x (x) grad_i W, xx part
      });
      mean += m / nOff;
    }
    EXPECT_NEAR(-mean, expect, 5e-5) << d << "D";
    EXPECT_LT(expect, 1.0 - 1e-4) << "the edge term is not negligible";
  }
}

TEST(Kernel, DerivativeMatchesCentralDifferences) {
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const double h = 0.01;
      const Kernel k(t, d, h);
      const double scale = std::abs(k.value(0.0)) / h;  // typical |W'|
      const double eps = 1e-6 * h;
      for (int s = 1; s < 400; ++s) {
        const double r = k.support() * s / 400.0;
        bool nearBreak = false;
        for (double b : breakpoints(t)) nearBreak |= std::abs(r - b * h) < 2 * eps;
        if (nearBreak) continue;
        const double fd = (k.value(r + eps) - k.value(r - eps)) / (2 * eps);
        ASSERT_NEAR(k.derivative(r), fd, 1e-7 * scale) << label(t, d) << " r/h = " << r / h;
        // F = W'/r (Eq. 2.38).
        ASSERT_NEAR(k.F(r) * r, k.derivative(r), 1e-12 * scale) << label(t, d);
        // Kernels decrease monotonically and are non-negative.
        ASSERT_LE(k.derivative(r), 0.0) << label(t, d);
        ASSERT_GE(k.value(r), 0.0) << label(t, d);
      }
    }
}

TEST(Kernel, GradientMatchesCentralDifferences) {
  for (KernelType t : kAll) {
    const double h = 0.05, eps = 1e-6 * h;
    {
      const Kernel k(t, 3, h);
      const double scale = k.value(0.0) / h;
      for (const Vec<3>& r : {Vec<3>(0.3 * h, -0.2 * h, 0.5 * h), Vec<3>(-1.1 * h, 0.4 * h, 0.7 * h),
                              Vec<3>(0.0, 0.0, 1.7 * h), Vec<3>(0.9 * h, 0.9 * h, -0.9 * h)}) {
        const Vec<3> g = k.gradient<3>(r);
        for (int a = 0; a < 3; ++a) {
          Vec<3> rp = r, rm = r;
          rp[a] += eps;
          rm[a] -= eps;
          const double fd = (k.value(rp.norm()) - k.value(rm.norm())) / (2 * eps);
          EXPECT_NEAR(g[a], fd, 1e-7 * scale) << label(t, 3) << " axis " << a;
        }
      }
    }
    {
      const Kernel k(t, 2, h);
      const double scale = k.value(0.0) / h;
      const Vec<2> r(0.6 * h, -1.2 * h);
      const Vec<2> g = k.gradient<2>(r);
      for (int a = 0; a < 2; ++a) {
        Vec<2> rp = r, rm = r;
        rp[a] += eps;
        rm[a] -= eps;
        EXPECT_NEAR(g[a], (k.value(rp.norm()) - k.value(rm.norm())) / (2 * eps), 1e-7 * scale);
      }
    }
    {
      const Kernel k(t, 1, h);
      const double scale = k.value(0.0) / h;
      const Vec<1> r(-0.8 * h);
      const double fd =
          (k.value(std::abs(r[0] + eps)) - k.value(std::abs(r[0] - eps))) / (2 * eps);
      EXPECT_NEAR(k.gradient<1>(r)[0], fd, 1e-7 * scale);
    }
    // Antisymmetry grad_a W_ab = -grad_b W_ba and zero at r = 0.
    const Kernel k(t, 3, h);
    const Vec<3> r(0.2 * h, 0.3 * h, -0.4 * h);
    EXPECT_EQ(k.gradient<3>(r), -k.gradient<3>(Vec<3>(-r)));
    EXPECT_EQ(k.gradient<3>(Vec<3>::Zero()), Vec<3>::Zero());
  }
}

TEST(Kernel, FFiniteAtTheOrigin) {
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const double h = 0.02;
      const Kernel k(t, d, h);
      const double f0 = k.F(0.0);
      ASSERT_TRUE(std::isfinite(f0)) << label(t, d);
      EXPECT_LT(f0, 0.0) << label(t, d);
      EXPECT_EQ(k.derivative(0.0), 0.0) << label(t, d);
      // F is continuous at 0: F(0) = lim W''(r) (W' is odd and smooth at 0 for all four).
      for (double q : {1e-9, 1e-7, 1e-5}) {
        EXPECT_NEAR(k.F(q * h), f0, 1e-4 * std::abs(f0) + 1e-3 * q * std::abs(f0)) << label(t, d);
        EXPECT_TRUE(std::isfinite(k.F(q * h)));
      }
    }
  // Closed forms: cubic spline F(0) = -2 M / h^(d+2) (w'(q)/q -> -2); Gaussian -2 sigma / h^(d+2).
  EXPECT_NEAR(Kernel(KernelType::CubicSpline, 3, 1.0).F(0.0), -2.0 * 3.0 / (2.0 * kPi), 1e-14);
  EXPECT_NEAR(Kernel(KernelType::CubicSpline, 1, 2.0).F(0.0), -2.0 / 8.0, 1e-14);
  EXPECT_NEAR(Kernel(KernelType::QuinticSpline, 3, 1.0).F(0.0), -120.0 / (120.0 * kPi), 1e-12);
}

TEST(Kernel, ZeroBeyondTheSupport) {
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const double h = 3e-4;
      const Kernel k(t, d, h);
      EXPECT_DOUBLE_EQ(k.support(), kernelSupportFactor(t) * h);
      // At r = support exactly, q = r/h may round to just below the cut: W is then ~1e-48 w(0).
      EXPECT_LE(k.value(k.support()), 1e-30 * k.value(0.0)) << label(t, d);
      for (double f : {1.0 + 1e-12, 1.001, 1.5, 10.0, 1e6}) {
        const double r = k.support() * f;
        EXPECT_EQ(k.value(r), 0.0) << label(t, d) << " r/support = " << f;
        EXPECT_EQ(k.derivative(r), 0.0) << label(t, d);
        EXPECT_EQ(k.F(r), 0.0) << label(t, d);
      }
      EXPECT_GT(k.value(k.support() * (1.0 - 1e-6)), 0.0) << label(t, d);
    }
}

TEST(Kernel, ContinuousAtThePieceBoundaries) {
  // Value and first derivative are continuous at every breakpoint (the cubic and quintic splines
  // are C2, the Wendland C2 too). The truncated Gaussian is the exception: it jumps by exactly
  // W(cut-) = sigma exp(-8) / h^d at the cut (thesis: support 2 sqrt(2) h).
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const double h = 0.1;
      const Kernel k(t, d, h);
      const double w0 = k.value(0.0), eps = 1e-9 * h;
      for (double b : breakpoints(t)) {
        const double r = b * h;
        const double wl = k.value(r - eps), wr = k.value(r + eps);
        const double dl = k.derivative(r - eps), dr = k.derivative(r + eps);
        if (t == KernelType::Gaussian) {
          EXPECT_NEAR(wl - wr, k.value(0.0) * std::exp(-8.0), 1e-6 * wl) << label(t, d);
          EXPECT_EQ(wr, 0.0);
          continue;
        }
        EXPECT_NEAR(wl, wr, 1e-8 * w0) << label(t, d) << " at q = " << b;
        EXPECT_NEAR(dl, dr, 1e-7 * w0 / h) << label(t, d) << " at q = " << b;
        // Second derivative continuous as well (finite differences across the break).
        const double e2 = 1e-4 * h;
        const double d2l = (k.derivative(r - e2) - k.derivative(r - 2 * e2)) / e2;
        const double d2r = (k.derivative(r + 2 * e2) - k.derivative(r + e2)) / e2;
        EXPECT_NEAR(d2l, d2r, 1e-2 * w0 / (h * h)) << label(t, d) << " at q = " << b;
      }
    }
}

TEST(Kernel, ScalesWithH) {
  // W(r, h) = h^-d w(r / h): doubling h and r divides W by 2^d, W' by 2^(d+1), F by 2^(d+2).
  for (KernelType t : kAll)
    for (int d = 1; d <= 3; ++d) {
      const Kernel k1(t, d, 1.0), k2(t, d, 2.0);
      for (double r : {0.0, 0.4, 1.3, 1.9, 2.5}) {
        const double s = std::pow(2.0, d);
        EXPECT_NEAR(k2.value(2 * r), k1.value(r) / s, 1e-14) << label(t, d);
        EXPECT_NEAR(k2.derivative(2 * r), k1.derivative(r) / (2 * s), 1e-14) << label(t, d);
        EXPECT_NEAR(k2.F(2 * r), k1.F(r) / (4 * s), 1e-14) << label(t, d);
      }
    }
}

TEST(Kernel, NamesAndBadInput) {
  for (KernelType t : kAll) EXPECT_EQ(parseKernelType(kernelTypeName(t)), t);
  EXPECT_THROW(parseKernelType("cubic"), InputError);
  EXPECT_THROW(Kernel(KernelType::CubicSpline, 3, 0.0), InputError);
  EXPECT_THROW(Kernel(KernelType::CubicSpline, 3, -1.0), InputError);
  EXPECT_THROW(Kernel(KernelType::CubicSpline, 3, std::nan("")), InputError);
  EXPECT_THROW(Kernel(KernelType::CubicSpline, 3, INFINITY), InputError);
  EXPECT_THROW(Kernel(KernelType::CubicSpline, 4, 1.0), InputError);
  EXPECT_THROW(Kernel(KernelType::CubicSpline, 0, 1.0), InputError);
}
