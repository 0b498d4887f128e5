#pragma once
// Reading a 2D drop's interface for contact-angle tests (sessile drops on flat, tilted and curved
// walls): the midpoints of liquid-gas particle pairs closer than 1.5 dx, and the algebraic (Kasa)
// circle through them. The Kasa residual |p - c|^2 - r^2 is invariant under rotations and
// translations, so the fit may be made in the world frame or in a wall's frame alike.
#include <Eigen/Dense>
#include <cmath>
#include <cstdint>
#include <vector>

#include "libcore/simulation.hpp"

namespace poresph::test {

/// Midpoints (world frame) of the liquid-gas pairs closer than 1.5 dx (materials `liquid`, `gas`)
/// from a fresh neighbour list of the 2D scene.
inline std::vector<Eigen::Vector2d> liquidGasMidpoints(Simulation& sim, int liquid, int gas, double dx) {
  sim.updateNeighbours();
  const auto& st = sim.store;
  const double* x = st.data(st.position());
  const std::int32_t* mt = st.data(st.material());
  const auto& nl = sim.neighbours;
  std::vector<Eigen::Vector2d> pts;
  for (Index i = 0; i < st.realCount(); ++i) {
    if (mt[i] != liquid) continue;
    for (auto k = nl.offset[static_cast<size_t>(i)]; k < nl.offset[static_cast<size_t>(i) + 1]; ++k) {
      const Index j = nl.index[static_cast<size_t>(k)];
      if (mt[j] != gas) continue;
      const Eigen::Vector2d a(x[2 * i], x[2 * i + 1]), b(x[2 * j], x[2 * j + 1]);
      if ((a - b).norm() <= 1.5 * dx) pts.push_back(0.5 * (a + b));
    }
  }
  return pts;
}

struct FittedCircle {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double radius = 0.0;
};

/// Algebraic (Kasa) least-squares circle: x^2 + y^2 + a x + b y + c = 0 (at least 3 points).
inline FittedCircle kasaCircle(const std::vector<Eigen::Vector2d>& pts) {
  const int n = static_cast<int>(pts.size());
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd rhs(n);
  for (int k = 0; k < n; ++k) {
    const auto& p = pts[static_cast<size_t>(k)];
    A.row(k) << p.x(), p.y(), 1.0;
    rhs[k] = -p.squaredNorm();
  }
  const Eigen::Vector3d s = A.colPivHouseholderQr().solve(rhs);
  FittedCircle c;
  c.centre = Eigen::Vector2d(-0.5 * s[0], -0.5 * s[1]);
  c.radius = std::sqrt(c.centre.squaredNorm() - s[2]);
  return c;
}

}  // namespace poresph::test
