#pragma once
// Oscillating 2D droplet (fluid module validation, issue 5): the scene, the damped-oscillation
// fit and the reference (linear viscous normal mode of a drop in a periodic box), shared by
// tests/validation/test_fluid_oscillating_droplet.cpp and its `long` resolution study.
#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "libcore/phases.hpp"
#include "physics/fluid/fluid_setup.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::oscdrop {
namespace fs = poresph::fluidsetup;
constexpr double kPi = 3.14159265358979323846;
inline double env(const char* k, double d) { return std::getenv(k) ? std::atof(std::getenv(k)) : d; }
// Least-squares fit a(t) = c0 + e^{-beta t} (c1 cos(omega t) + c2 sin(omega t)): linear in c for
// given (omega, beta); a nested grid search over (omega, beta) minimises the residual.
struct Fit { double omega, beta, rms, amp; };
inline Fit fitDamped(const std::vector<double>& t, const std::vector<double>& a, double w0) {
  auto solve = [&](double w, double b, double* cOut) {
    double M[3][3] = {}, r[3] = {};
    for (size_t k = 0; k < t.size(); ++k) {
      const double e = std::exp(-b * t[k]), f[3] = {1.0, e * std::cos(w * t[k]), e * std::sin(w * t[k])};
      for (int i = 0; i < 3; ++i) {
        r[i] += f[i] * a[k];
        for (int j = 0; j < 3; ++j) M[i][j] += f[i] * f[j];
      }
    }
    // Cramer's rule (3x3)
    auto det = [](double A[3][3]) {
      return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
             A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    };
    const double D = det(M);
    double c[3];
    for (int q = 0; q < 3; ++q) {
      double A[3][3];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) A[i][j] = j == q ? r[i] : M[i][j];
      c[q] = det(A) / D;
    }
    double res = 0.0;
    for (size_t k = 0; k < t.size(); ++k) {
      const double e = std::exp(-b * t[k]);
      const double d = a[k] - c[0] - e * (c[1] * std::cos(w * t[k]) + c[2] * std::sin(w * t[k]));
      res += d * d;
    }
    if (cOut) for (int i = 0; i < 3; ++i) cOut[i] = c[i];
    return std::sqrt(res / static_cast<double>(t.size()));
  };
  double wLo = 0.3 * w0, wHi = 1.7 * w0, bLo = 0.0, bHi = 1.0 * w0, bestW = w0, bestB = 0.0;
  for (int level = 0; level < 6; ++level) {
    double best = 1e300;
    for (int i = 0; i <= 40; ++i)
      for (int j = 0; j <= 40; ++j) {
        const double w = wLo + (wHi - wLo) * i / 40.0, b = bLo + (bHi - bLo) * j / 40.0;
        const double r = solve(w, b, nullptr);
        if (r < best) best = r, bestW = w, bestB = b;
      }
    const double dw = (wHi - wLo) / 10.0, db = (bHi - bLo) / 10.0;
    wLo = bestW - dw, wHi = bestW + dw, bLo = std::max(0.0, bestB - db), bHi = bestB + db;
  }
  double c[3];
  const double rms = solve(bestW, bestB, c);
  return {bestW, bestB, rms, std::hypot(c[1], c[2])};
}
// ---------------------------------------------------------------------------------------------
// Reference: linear normal mode of a 2D viscous drop in a viscous outer fluid inside a box.
//
// (1) Inviscid, unbounded outer fluid: the potentials phi_in = A r^n cos(n th),
//     phi_out = -C r^-n cos(n th), the kinematic condition and the Laplace jump
//     gamma (n^2 - 1) zeta / R^2 give omega0^2 = (n^3 - n) gamma / ((rho_in + rho_out) R^3).
// (2) Box: by the drop's mirror symmetry the periodic box of side B is a free-slip square (the
//     cell faces are mirror lines). The outer potential with dphi/dr = cos(n th) on r = R and
//     dphi/dn = 0 on the square is solved by least squares in r^{+-m} cos(m th), m = n + 4j (the
//     square's symmetry); its cos(n th) part on r = R, -(R/n) F, replaces -(R/n) of the unbounded
//     case: omega^2 = (n^3 - n) gamma / ((rho_in + F rho_out) R^3). For a circular free-slip wall
//     at R_b: phi_out = -C (r^-n + R_b^-2n r^n) cos(n th), u_r(R) = n C R^{-n-1} (1 - q) and
//     phi_out(R) = -C R^-n (1 + q), q = (R/R_b)^{2n}, so F = (1 + q)/(1 - q); the square is
//     replaced by the circle with the same F (box 3R: F = 1.264, R_b = 1.711 R; 4R: 1.077, 2.281 R).
// (3) Viscosity: the unsteady Stokes normal mode e^{st}, stream function psi = f(r) sin(n th),
//     f_in = A r^n + B I_n(k_in r), f_out = C r^-n + D K_n(k_out r) + E r^n + G I_n(k_out r),
//     k^2 = s rho / mu; pressure p = -rho s phi from the harmonic parts. Conditions at r = R:
//     u_r, u_th continuous (f, f'), shear stress mu (-f'' + f'/r - n^2 f/r^2) continuous, normal
//     stress -p + 2 mu n (f'/r - f/r^2) jumps by -gamma (n^2 - 1) zeta / R^2 with s zeta = n f/R;
//     at r = R_b: f = 0 and no shear stress (free slip). s is the root of the 6x6 determinant
//     (complex secant iteration from the inviscid value); omega = Im s, beta = -Re s. The vorticity
//     layer at the interface (thickness sqrt(2 nu / omega)) lowers the frequency by much more than
//     the bulk damping beta_bulk = 4 nu / R^2 suggests: with equal fluids, mu = 0.01 Pa s, R = 1.5 mm
//     the period is 11.5 % longer than (1) in an unbounded fluid (checked against an independent
//     mpmath solution, and for a drop in vacuum beta -> 4 nu / R^2).
namespace ref {
using cd = std::complex<double>;
// I_n(z) e^{-z}: (1/pi) int_0^pi e^{z (cos t - 1)} cos(n t) dt (periodic trapezoid, spectral).
inline cd besselIScaled(int n, cd z) {
  const int N = 400;
  cd s = 0.0;
  for (int k = 0; k <= N; ++k) {
    const double t = kPi * k / N, w = (k == 0 || k == N) ? 0.5 : 1.0;
    s += w * std::exp(z * (std::cos(t) - 1.0)) * std::cos(n * t);
  }
  return s / static_cast<double>(N);
}
// K_n(z) e^{z}: int_0^inf e^{-z (cosh t - 1)} cosh(n t) dt, Re z > 0 (even integrand, trapezoid).
inline cd besselKScaled(int n, cd z) {
  const double dt = 0.005;
  cd s = 0.5;
  for (int k = 1; k < 200000; ++k) {
    const double t = k * dt, e = std::cosh(t) - 1.0;
    if (z.real() * e > 60.0) break;
    s += std::exp(-z * e) * std::cosh(n * t);
  }
  return s * dt;
}
// f, f', f'' (in r) of I_n(k r) e^{-k r0} or K_n(k r) e^{k r0}.
inline std::array<cd, 3> bessel(bool isI, int n, cd k, double r, double r0) {
  const cd z = k * r;
  cd f, f1;
  if (isI) {
    const cd sc = std::exp(k * (r - r0));
    f = besselIScaled(n, z) * sc;
    f1 = (besselIScaled(n + 1, z) * sc + (double(n) / z) * f) * k;
  } else {
    const cd sc = std::exp(-k * (r - r0));
    f = besselKScaled(n, z) * sc;
    f1 = (-besselKScaled(n + 1, z) * sc + (double(n) / z) * f) * k;
  }
  const cd f2 = (1.0 + double(n * n) / (z * z)) * f * (k * k) - f1 / r;
  return {f, f1, f2};
}

// Added-mass factor F of the outer fluid for mode n in a free-slip square of half-side bh (R = 1).
inline double squareBoxFactor(int n, double bh) {
  const int M = 12, P = 200;
  Eigen::MatrixXd A(2 * P, 2 * M);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(2 * P);
  for (int p = 0; p < P; ++p) {
    const double t = 0.25 * kPi * p / (P - 1);
    for (int j = 0; j < M; ++j) {
      const double m = n + 4 * j;
      A(p, j) = -m * std::cos(m * t);  // d/dr r^-m at r = 1
      A(p, M + j) = m * std::cos(m * t);
    }
    b(p) = std::cos(n * t);
    const double y = bh * p / (P - 1), r = std::hypot(bh, y), th = std::atan2(y, bh);
    for (int j = 0; j < 2 * M; ++j) {
      const double m = n + 4 * (j % M), e = j < M ? -m : m;
      const double dr = e * std::pow(r, e - 1) * std::cos(m * th), dth = -m * std::pow(r, e) * std::sin(m * th);
      A(P + p, j) = std::cos(th) * dr - std::sin(th) / r * dth;  // d/dx on the face x = bh
    }
  }
  Eigen::VectorXd sc(2 * M);
  for (int j = 0; j < 2 * M; ++j) {
    sc(j) = A.col(j).cwiseAbs().maxCoeff();
    A.col(j) /= sc(j);
  }
  Eigen::VectorXd c = A.colPivHouseholderQr().solve(b);
  c = c.cwiseQuotient(sc);
  return -(c(0) + c(M)) * n;
}

struct Mode { double omega, beta, omegaInviscid, boxFactor; };
// Mode n of a drop (R, rho1, mu1) in (rho2, mu2) with surface tension gamma, in a periodic square
// box of side B (B <= 0: unbounded). Dimensionless inside (R = rho1 = gamma = 1).
inline Mode viscousMode(int n, double R, double rho1, double mu1, double rho2, double mu2, double gamma, double B) {
  const double tc = std::sqrt(rho1 * R * R * R / gamma), r2 = rho2 / rho1;
  const double m1 = mu1 * tc / (rho1 * R * R), m2 = mu2 * tc / (rho1 * R * R);  // Ohnesorge numbers
  const bool box = B > 0.0;
  const double F = box ? squareBoxFactor(n, 0.5 * B / R) : 1.0;
  const double q = (F - 1.0) / (F + 1.0), Rb = box ? std::pow(q, -1.0 / (2 * n)) : 0.0;
  const double w0 = std::sqrt((n * n * n - n) / (1.0 + F * r2));
  const int N = box ? 6 : 4;
  auto det = [&](cd s) {
    const cd k1 = std::sqrt(s / m1), k2 = std::sqrt(s * r2 / m2);
    Eigen::MatrixXcd A = Eigen::MatrixXcd::Zero(N, N);
    auto tau = [&](const std::array<cd, 3>& f, double r) { return -f[2] + f[1] / r - double(n * n) * f[0] / (r * r); };
    auto durr = [&](const std::array<cd, 3>& f, double r) { return double(n) * (f[1] / r - f[0] / (r * r)); };
    auto harm = [&](double e, double r) {
      return std::array<cd, 3>{std::pow(r, e), e * std::pow(r, e - 1), e * (e - 1) * std::pow(r, e - 2)};
    };
    // columns: A r^n, B I(k1 r), C r^-n, D K(k2 r), [E r^n, G I(k2 r)]; phi: +r^n, -r^-n, +r^n
    std::vector<std::array<cd, 3>> atR = {harm(n, 1), bessel(true, n, k1, 1, 1), harm(-n, 1),
                                          bessel(false, n, k2, 1, 1)};
    std::vector<double> phi = {1, 0, -1, 0};
    if (box) {
      atR.push_back(harm(n, 1));
      atR.push_back(bessel(true, n, k2, 1, Rb));
      phi.push_back(1);
      phi.push_back(0);
    }
    for (int j = 0; j < N; ++j) {
      const bool in = j < 2;
      const double sg = in ? 1.0 : -1.0, mu = in ? m1 : m2, rho = in ? 1.0 : r2;
      const auto& f = atR[static_cast<size_t>(j)];
      A(0, j) = sg * f[0];
      A(1, j) = sg * f[1];
      A(2, j) = sg * mu * tau(f, 1.0);
      A(3, j) = sg * (rho * s * phi[static_cast<size_t>(j)] + 2.0 * mu * durr(f, 1.0));
      if (in) A(3, j) += double((n * n - 1) * n) * f[0] / s;
    }
    if (box) {
      const std::array<cd, 3> atB[4] = {harm(-n, Rb), bessel(false, n, k2, Rb, 1), harm(n, Rb),
                                        bessel(true, n, k2, Rb, Rb)};
      for (int j = 0; j < 4; ++j) {
        A(4, 2 + j) = atB[j][0];
        A(5, 2 + j) = tau(atB[j], Rb);
      }
    }
    return A.determinant();
  };
  cd s0(-2.0 * (m1 + m2), 0.95 * w0), s1(-4.0 * (m1 + m2), 0.9 * w0);
  cd d0 = det(s0), d1 = det(s1);
  for (int it = 0; it < 100 && std::abs(s1 - s0) > 1e-13 * std::abs(s1); ++it) {
    const cd s2 = s1 - d1 * (s1 - s0) / (d1 - d0);
    s0 = s1, d0 = d1, s1 = s2, d1 = det(s1);
  }
  return {s1.imag() / tc, -s1.real() / tc, w0 / tc, F};
}
}  // namespace ref

struct DropletRun {
  double R, omega, beta, rms, amp, a0, wall;
  long long steps;
};

// Runs the oscillating droplet and fits the mode-2 signal (see the header).
// extraKeys: extra keys of the fluid section (", key: value"); by default OSC_EXTRA.
inline DropletRun runDroplet(double rdx, double boxR, double mu, double pb, double eps, double c, double periods,
                      double tRef, const char* extraKeys = nullptr) {
  test::Stopwatch clock;
  Simulation sim(2);
  const double R0 = 1.5e-3, dx = R0 / rdx, B = boxR * R0, gamma = env("OSC_GAMMA", 0.05);
  sim.spacing = dx;
  sim.kernel = Kernel(KernelType::QuinticSpline, 2, dx);
  sim.domain.lo = {0, 0, 0};
  sim.domain.hi = {B, B, 0};
  sim.domain.periodic = {true, true, false};
  char buf[300];
  std::snprintf(buf, sizeof buf, "{density: 1000, sound_speed: %g, viscosity: %g, colour: 1, background_pressure: %g}", c, mu, pb);
  const int liq = fs::addMaterial(sim, "liquid", "fluid", buf);
  std::snprintf(buf, sizeof buf, "{density: 1000, sound_speed: %g, viscosity: %g, colour: -1, background_pressure: %g}", c, mu, pb);
  const int gas = fs::addMaterial(sim, "gas", "fluid", buf);
  // OSC_EXTRA: extra keys of the fluid section (", key: value", manual studies)
  const char* extra = extraKeys ? extraKeys : std::getenv("OSC_EXTRA") ? std::getenv("OSC_EXTRA") : "";
  std::snprintf(buf, sizeof buf, "{surface_tension: %g%s}", gamma, extra);
  FluidModule* fluid = fs::addFluidModule(sim, buf);
  auto inside = [&](const double* x) {
    const double X = x[0] - 0.5 * B, Y = x[1] - 0.5 * B;
    return std::hypot(X, Y) < R0 * (1.0 + eps * std::cos(2.0 * std::atan2(Y, X)));
  };
  const Index nLiq = fs::addLattice(sim, {0, 0}, {B, B}, liq, inside);
  fs::addLattice(sim, {0, 0}, {B, B}, gas, [&](const double* x) { return !inside(x); });
  fluid->initialise(sim);
  // Study hook OSC_U0 (m/s): start with the mode-2 potential flow u_r = U0 (r/R) cos 2th,
  // u_th = -U0 (r/R) sin 2th inside, U0 (R/r)^3 (cos 2th, sin 2th) outside (with OSC_GAMMA ~ 0 it
  // shows whether anything but surface tension pulls the shape back).
  if (const double U0 = env("OSC_U0", 0.0); U0 != 0.0) {
    double* x = sim.store.data(sim.store.position());
    double* v = sim.store.data(sim.store.velocity());
    for (Index i = 0; i < sim.store.realCount(); ++i) {
      const double X = x[2 * i] - 0.5 * B, Y = x[2 * i + 1] - 0.5 * B, r = std::hypot(X, Y), th = std::atan2(Y, X);
      const double f = r < R0 ? r / R0 : std::pow(R0 / r, 3), sg = r < R0 ? -1.0 : 1.0;
      const double ur = U0 * f * std::cos(2 * th), ut = sg * U0 * f * std::sin(2 * th);
      v[2 * i] = ur * std::cos(th) - ut * std::sin(th);
      v[2 * i + 1] = ur * std::sin(th) + ut * std::cos(th);
    }
  }
  DropletRun out{};
  out.R = std::sqrt(static_cast<double>(nLiq) * dx * dx / kPi);  // equal-area radius
  auto amplitude = [&]() {
    const auto& st = sim.store;
    const double* x = st.data(st.position());
    const double* col = st.data(fluid->colour);
    double cx = 0, cy = 0, n = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (col[i] > 0) cx += x[2 * i], cy += x[2 * i + 1], n += 1;
    cx /= n;
    cy /= n;
    double a = 0, b = 0;
    for (Index i = 0; i < st.realCount(); ++i)
      if (col[i] > 0) {
        const double X = x[2 * i] - cx, Y = x[2 * i + 1] - cy;
        a += X * X - Y * Y;
        b += X * X + Y * Y;
      }
    return a / b;
  };
  const std::string dump = std::getenv("OSC_DUMP") ? std::getenv("OSC_DUMP") : "";
  FILE* fa = dump.empty() ? nullptr : std::fopen((dump + "_a.txt").c_str(), "w");
  int snap = 0;
  fs::Stepper stepper;
  std::vector<double> ts, as;
  out.a0 = amplitude();
  while (sim.time < periods * tRef) {
    stepper.step(sim);
    const double a = amplitude();
    if (sim.time > 0.1 * tRef) ts.push_back(sim.time), as.push_back(a);
    if (fa && sim.step % 20 == 0) std::fprintf(fa, "%.6e %.6e\n", sim.time, a);
    if (!dump.empty() && sim.time >= snap * 0.25 * tRef) {
      FILE* g = std::fopen((dump + "_s" + std::to_string(snap) + ".txt").c_str(), "w");
      const auto& st = sim.store;
      const double* x = st.data(st.position());
      const double* col = st.data(fluid->colour);
      const double* p = st.data(fluid->pressure);
      std::fprintf(g, "# t %.6e\n", sim.time);
      for (Index i = 0; i < st.realCount(); ++i) std::fprintf(g, "%.6e %.6e %g %.5e\n", x[2 * i], x[2 * i + 1], col[i], p[i]);
      std::fclose(g);
      ++snap;
    }
  }
  if (fa) std::fclose(fa);
  const Fit f = fitDamped(ts, as, 2 * kPi / tRef);
  out.omega = f.omega;
  out.beta = f.beta;
  out.rms = f.rms;
  out.amp = f.amp;
  out.steps = static_cast<long long>(sim.step);
  out.wall = clock.seconds();
  return out;
}

}  // namespace poresph::oscdrop
