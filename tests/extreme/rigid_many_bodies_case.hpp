#pragma once
// Shared by the many-body extremes of the rigid module (issue 15: 1e3 bodies in one scene;
// tests/extreme/test_rigid_many_grains.cpp, test_rigid_many_bodies_long.cpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "libcore/simulation.hpp"

namespace poresph::test {

/// Smallest distance between two particles of different rigid bodies (2D; minimal image along the
/// periodic axes). A cell list of side >= 2 dx: exact below 2 dx (larger gaps read as >= 2 dx).
inline double minBodyGap2D(const Simulation& sim) {
  const ParticleStore& st = sim.store;
  const std::int32_t* body = st.data(st.integer("body"));
  const double* x = st.data(st.position());
  const Domain& dom = sim.domain;
  const Index n = st.realCount();
  int nc[2];
  double side[2], len[2];
  for (int a = 0; a < 2; ++a) {
    len[a] = dom.hi[static_cast<size_t>(a)] - dom.lo[static_cast<size_t>(a)];
    nc[a] = std::max(1, static_cast<int>(std::floor(len[a] / (2.0 * sim.spacing))));
    side[a] = len[a] / nc[a];
  }
  auto cellOf = [&](Index i, int a) {
    const int c = static_cast<int>(std::floor((x[2 * i + a] - dom.lo[static_cast<size_t>(a)]) / side[a]));
    return std::clamp(c, 0, nc[a] - 1);
  };
  std::vector<std::vector<Index>> cells(static_cast<size_t>(nc[0]) * nc[1]);
  for (Index i = 0; i < n; ++i)
    if (body[i] >= 0) cells[static_cast<size_t>(cellOf(i, 1)) * nc[0] + cellOf(i, 0)].push_back(i);
  double gap2 = 4.0 * sim.spacing * sim.spacing;
  for (Index i = 0; i < n; ++i) {
    if (body[i] < 0) continue;
    const int cx = cellOf(i, 0), cy = cellOf(i, 1);
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        int q[2] = {cx + ox, cy + oy};
        bool inside = true;
        for (int a = 0; a < 2; ++a) {
          if (q[a] >= 0 && q[a] < nc[a]) continue;
          if (dom.periodic[static_cast<size_t>(a)]) q[a] = (q[a] + nc[a]) % nc[a];
          else inside = false;
        }
        if (!inside) continue;
        for (Index j : cells[static_cast<size_t>(q[1]) * nc[0] + q[0]]) {
          if (body[j] == body[i]) continue;
          double r2 = 0.0;
          for (int a = 0; a < 2; ++a) {
            double d = x[2 * i + a] - x[2 * j + a];
            if (dom.periodic[static_cast<size_t>(a)]) d -= len[a] * std::round(d / len[a]);
            r2 += d * d;
          }
          gap2 = std::min(gap2, r2);
        }
      }
  }
  return std::sqrt(gap2);
}

}  // namespace poresph::test
