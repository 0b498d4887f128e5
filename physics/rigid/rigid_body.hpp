#pragma once
// State and Newton-Euler update of one rigid body (thesis Appendix A, Eqs. A.4-A.5, A.7-A.14),
// independent of the particle store (physics/rigid/rigid_module.cpp places the particles).
//
// State: mass M, centre of mass X (A.7), velocity V, orientation q (unit quaternion, body frame ->
// world frame; replaces the three successive rotations of A.15-A.16), principal moments of inertia
// Ib (A.8 diagonalised: the body frame is the principal frame in 3D, the initial world frame in
// 2D) and the angular momentum L in the world frame. The angular velocity is
// omega = R Ib^{-1} R^T L.
//
// One step (kick-drift-kick, the velocity-Verlet / leapfrog form of A.11-A.14):
//   V += dt/2 F_a / M,  L += dt/2 T_a            (forces at the start of the step)
//   X += dt V,          free rotation over dt     (drift)
//   V += dt/2 F_b / M,  L += dt/2 T_b            (forces evaluated during the step)
// The free rotation is the implicit midpoint rule of Euler's equations in the body frame,
//   L_b' = L_b + dt (L_m x omega_m),  L_m = (L_b + L_b') / 2,  omega_m = Ib^{-1} L_m,
// with q' = q (1, omega_m dt / 2) / |.| (the Cayley rotation that maps L_b' back onto L_b).
// It conserves the world angular momentum and the rotational energy 1/2 L_b . Ib^{-1} L_b exactly
// (both are quadratic invariants of the midpoint rule; only the fixed-point iteration's
// tolerance remains), which A.15-A.16 with rotations about three axes in turn do not.
#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <cmath>

namespace poresph::rigid {

using V3 = Eigen::Vector3d;
using M3 = Eigen::Matrix3d;

struct BodyState {
  int dimension = 3;
  double mass = 0.0;
  V3 X = V3::Zero(), V = V3::Zero();
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  V3 Ib = V3::Ones();  ///< principal moments (3D); 2D: only Ib.z() (about the normal) is used
  V3 L = V3::Zero();   ///< angular momentum, world frame (2D: only L.z())

  M3 R() const { return q.toRotationMatrix(); }
  /// Angular velocity in the world frame.
  V3 omega() const {
    if (dimension == 2) return V3(0.0, 0.0, L.z() / Ib.z());
    const M3 r = R();
    const V3 lb = r.transpose() * L;
    return r * lb.cwiseQuotient(Ib);
  }
  /// Inertia tensor in the world frame, R Ib R^T (3D; 2D: diag(0, 0, Ib.z)).
  M3 inertiaWorld() const {
    if (dimension == 2) {
      M3 i = M3::Zero();
      i(2, 2) = Ib.z();
      return i;
    }
    const M3 r = R();
    return r * Ib.asDiagonal() * r.transpose();
  }
  /// Rotational kinetic energy 1/2 omega . L.
  double rotationalEnergy() const { return 0.5 * omega().dot(L); }
  /// Angular acceleration (A.5a): I^{-1} (T - omega x I omega) = I^{-1} T - ... with L = I omega.
  V3 angularAcceleration(const V3& T) const {
    if (dimension == 2) return V3(0.0, 0.0, T.z() / Ib.z());
    const M3 r = R();
    const V3 w = omega();
    const V3 rhs = r.transpose() * (T - w.cross(L));
    return r * rhs.cwiseQuotient(Ib);
  }

  /// Torque-free rotation over dt (implicit midpoint in the body frame, see the file comment).
  /// Returns the number of fixed-point iterations used.
  int rotateFree(double dt) {
    if (dimension == 2) {
      const double angle = dt * L.z() / Ib.z();
      q = (q * Eigen::Quaterniond(Eigen::AngleAxisd(angle, V3::UnitZ()))).normalized();
      return 0;
    }
    const M3 r = R();
    const V3 lb = r.transpose() * L;
    const double scale = lb.norm();
    if (!(scale > 0.0)) return 0;
    V3 l1 = lb, wm = V3::Zero();
    int it = 0;
    for (; it < 100; ++it) {
      const V3 lm = 0.5 * (lb + l1);
      wm = lm.cwiseQuotient(Ib);
      const V3 next = lb + dt * lm.cross(wm);
      const double change = (next - l1).norm();
      l1 = next;
      if (change <= 1e-16 * scale) break;
    }
    wm = (0.5 * (lb + l1)).cwiseQuotient(Ib);
    const V3 half = 0.5 * dt * wm;
    const Eigen::Quaterniond s(1.0, half.x(), half.y(), half.z());
    q = (q * s.normalized()).normalized();
    return it + 1;
  }
};

/// Jacobi's closed form of the intermediate-axis flip (tennis-racket / Dzhanibekov effect) of a
/// free body with principal moments I1 < I2 < I3, angular momentum L and energy E with
/// L^2 > 2 E I2 (Landau & Lifshitz, Mechanics, Sec. 37): omega_2 = C sn(tau, k) changes sign
/// every half period, i.e. every 2 K(k) / lambda, with
///   lambda = sqrt((I3 - I2)(L^2 - 2 E I1) / (I1 I2 I3)),
///   k^2 = (I2 - I1)(2 E I3 - L^2) / ((I3 - I2)(L^2 - 2 E I1)).
/// (For L^2 < 2 E I2 exchange I1 and I3.) Returns the time between two sign changes.
inline double flipHalfPeriod(double I1, double I2, double I3, double L2, double E2) {
  if (L2 < E2 * I2) std::swap(I1, I3);  // E2 = 2 E
  const double lambda = std::sqrt((I3 - I2) * (L2 - E2 * I1) / (I1 * I2 * I3));
  const double k2 = (I2 - I1) * (E2 * I3 - L2) / ((I3 - I2) * (L2 - E2 * I1));
  return 2.0 * std::comp_ellint_1(std::sqrt(k2)) / lambda;
}

}  // namespace poresph::rigid
