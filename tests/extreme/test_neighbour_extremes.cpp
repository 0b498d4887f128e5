// Extreme inputs of the neighbour search (label `extreme`): a tiny radius in a huge box (the
// cell count must stay capped, no memory blow-up), every particle in one cell, coincident
// particles, and non-finite positions (NaN / Inf must throw, not be binned silently).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "libcore/neighbour_search.hpp"
#include "libcore/particle_store.hpp"

using namespace poresph;

namespace {

// Brute-force pair count (self excluded) with the search's arithmetic.
std::int64_t brutePairs(const std::vector<double>& x, int d, double radius) {
  const Index n = static_cast<Index>(x.size()) / d;
  std::int64_t c = 0;
  for (Index i = 0; i < n; ++i)
    for (Index j = 0; j < n; ++j) {
      if (i == j) continue;
      double r2 = 0.0;
      for (int a = 0; a < d; ++a) {
        const double dx = x[i * d + a] - x[j * d + a];
        r2 += dx * dx;
      }
      c += r2 < radius * radius;
    }
  return c;
}

}  // namespace

TEST(NeighbourExtremes, TinyRadiusInAHugeBox) {
  // Clusters of 4 particles 1e-12 m apart, spread over a 1e3 m box: box / radius = 4e14 per
  // axis, i.e. 6e43 cells of one radius in 3D. The cell count must stay ~2 per particle and
  // the pairs inside each cluster must all be found.
  for (int d = 1; d <= 3; ++d) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-500.0, 500.0);
    const int clusters = 500;
    const double radius = 2.5e-12, spacing = 1e-12;
    std::vector<double> x;
    for (int c = 0; c < clusters; ++c) {
      double centre[3];
      for (int a = 0; a < d; ++a) centre[a] = u(rng);
      for (int k = 0; k < 4; ++k)
        for (int a = 0; a < d; ++a) x.push_back(centre[a] + (a == 0 ? k * spacing : 0.0));
    }
    const Index n = static_cast<Index>(x.size()) / d;
    NeighbourSearch search;
    NeighbourList list;
    search.build(x.data(), d, n, n, radius, list);
    EXPECT_LE(search.cellCount(), 2 * n + 64) << d << "D";
    EXPECT_LT(search.bytes(), std::size_t(64) << 20) << d << "D: search memory blew up";
    // In each cluster of 4 on a line with spacing 1e-12 (positions ~1e2 m, resolved to ~1e-13 m):
    // pairs at 1 and 2 spacings are within 2.5e-12, at 3 spacings they are not.
    const std::int64_t expect = brutePairs(x, d, radius);
    EXPECT_EQ(list.pairCount(), expect) << d << "D";
    EXPECT_EQ(expect, clusters * 10) << "4 particles on a line: 2*(3+2) = 10 ordered pairs";
    // Same with an absurd ratio (2e300 box, 1e-100 radius): still bounded and correct (no pairs
    // between the spread particles, the duplicates at the origin pair up).
    std::vector<double> y{1e300, -1e300, 0.0, 0.0};
    if (d > 1) y = std::vector<double>(static_cast<size_t>(4 * d), 0.0), y[0] = 1e300, y[d] = -1e300;
    search.build(y.data(), d, 4, 4, 1e-100, list);
    EXPECT_LE(search.cellCount(), 2 * 4 + 64);
    EXPECT_EQ(list.pairCount(), 2) << d << "D";  // particles 2 and 3 coincide
  }
}

TEST(NeighbourExtremes, AllParticlesInOneCell) {
  // 1500 particles inside a ball of radius r/10: every particle is a neighbour of every other.
  for (int d = 1; d <= 3; ++d) {
    std::mt19937_64 rng(2);
    std::uniform_real_distribution<double> u(-0.05, 0.05);
    const Index n = 1500;
    std::vector<double> x(static_cast<size_t>(n * d));
    for (auto& v : x) v = 3.0 + u(rng) / std::sqrt(static_cast<double>(d));
    NeighbourSearch search;
    NeighbourList list;
    search.build(x.data(), d, n, n, 1.0, list);
    EXPECT_LE(search.cellCount(), 2 * n + 64);
    ASSERT_EQ(list.pairCount(), n * (n - 1)) << d << "D";
    for (Index i = 0; i < n; ++i) {
      std::vector<std::uint32_t> l(list.index.begin() + list.offset[i],
                                   list.index.begin() + list.offset[i + 1]);
      std::sort(l.begin(), l.end());
      ASSERT_EQ(static_cast<Index>(l.size()), n - 1);
      for (Index k = 0; k < n - 1; ++k) ASSERT_EQ(l[k], static_cast<std::uint32_t>(k < i ? k : k + 1));
    }
  }
}

TEST(NeighbourExtremes, AllParticlesAtOnePoint) {
  // Zero-extent bounding box: one cell, all pairs at r = 0.
  const Index n = 300;
  std::vector<double> x(static_cast<size_t>(3 * n), 0.25);
  NeighbourSearch search;
  NeighbourList list;
  search.build(x.data(), 3, n, n, 1e-3, list);
  EXPECT_EQ(search.cellCount(), 1);
  EXPECT_EQ(list.pairCount(), n * (n - 1));
}

TEST(NeighbourExtremes, NonFinitePositionThrows) {
  for (int d = 1; d <= 3; ++d)
    for (double bad : {std::numeric_limits<double>::quiet_NaN(),
                       std::numeric_limits<double>::infinity(),
                       -std::numeric_limits<double>::infinity()}) {
      std::vector<double> x(static_cast<size_t>(100 * d), 0.0);
      for (size_t k = 0; k < x.size(); ++k) x[k] = 0.01 * static_cast<double>(k);
      x[static_cast<size_t>(37 * d + d - 1)] = bad;  // last axis of particle 37
      NeighbourSearch search;
      NeighbourList list;
      try {
        search.build(x.data(), d, 100, 100, 0.05, list);
        ADD_FAILURE() << d << "D: no exception for a non-finite position";
      } catch (const NumericalError& e) {
        EXPECT_NE(std::string(e.what()).find("particle 37"), std::string::npos) << e.what();
      }
      std::vector<Index> order;
      EXPECT_THROW(search.cellOrder(x.data(), d, 100, 0.05, order), NumericalError);
      // A NaN among the trailing (ghost) particles is caught as well.
      x.assign(static_cast<size_t>(100 * d), 0.5);
      x.back() = bad;
      EXPECT_THROW(search.build(x.data(), d, 50, 100, 0.05, list), NumericalError);
    }
  // Positions spanning more than the largest double (1e308 - (-1e308) overflows).
  std::vector<double> x{1.5e308, -1.5e308};
  NeighbourSearch search;
  NeighbourList list;
  EXPECT_THROW(search.build(x.data(), 1, 2, 2, 1.0, list), NumericalError);
}

TEST(NeighbourExtremes, NonFiniteRadiusAndBadCountsThrow) {
  std::vector<double> x{0.0, 0.1, 0.2};
  NeighbourSearch search;
  NeighbourList list;
  EXPECT_THROW(search.build(x.data(), 1, 3, 3, std::nan(""), list), std::logic_error);
  EXPECT_THROW(search.build(x.data(), 1, 3, 3, INFINITY, list), std::logic_error);
  // A radius whose square underflows to zero would silently find no pair at all.
  EXPECT_THROW(search.build(x.data(), 1, 3, 3, 1e-300, list), std::logic_error);
  EXPECT_THROW(search.build(x.data(), 1, 4, 3, 0.1, list), std::logic_error);
  EXPECT_THROW(search.build(x.data(), 1, -1, 3, 0.1, list), std::logic_error);
}

TEST(NeighbourExtremes, LargeOffsetCoordinates) {
  // A lattice far from the origin (1e5 m): the round-off of the coordinates (~1e-11 m) is far
  // below the spacing, the search must still match the brute force exactly.
  std::vector<double> x;
  const double dx = 1e-4, off = 1e5;
  for (int k = 0; k < 8; ++k)
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        x.push_back(off + i * dx);
        x.push_back(-off + j * dx);
        x.push_back(off + k * dx);
      }
  NeighbourSearch search;
  NeighbourList list;
  for (double r : {1.0 * dx, 1.5 * dx, 2.0 * dx, 2.6 * dx}) {
    search.build(x.data(), 3, 512, 512, r, list);
    EXPECT_EQ(list.pairCount(), brutePairs(x, 3, r)) << "r/dx = " << r / dx;
  }
}
