// Geometry builders: exact particle counts of boxes, discs, spheres, segments, overrides and
// subtractions on the global lattice lo + (i + 1/2) dx; periodic clipping.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <tuple>

#include "libcore/geometry.hpp"

using namespace poresph;

namespace {

Domain makeDomain(int dim, std::array<double, 3> lo, std::array<double, 3> hi,
                  std::array<bool, 3> periodic = {false, false, false}) {
  Domain d;
  d.dimension = dim;
  d.lo = lo;
  d.hi = hi;
  d.periodic = periodic;
  return d;
}

Region box(std::array<double, 3> lo, std::array<double, 3> hi, int material = 0) {
  Region r;
  r.shape = Region::Shape::Box;
  r.lo = lo;
  r.hi = hi;
  r.material = material;
  return r;
}

Region sphere(std::array<double, 3> c, double radius, int material = 0) {
  Region r;
  r.shape = Region::Shape::Sphere;
  r.centre = c;
  r.radius = radius;
  r.material = material;
  return r;
}

// Lattice sites (odd half-integers in units of dx/2 around a centre on a lattice corner) inside
// a radius of R = rOverHalfDx * dx / 2: (2i+1)^2 + ... <= rOverHalfDx^2, counted with integers.
long oddSitesWithin(int dim, long rOverHalfDx) {
  long n = 0;
  const long m = rOverHalfDx;  // |2i+1| <= m
  for (long i = -m; i <= m; ++i)
    for (long j = (dim > 1 ? -m : 0); j <= (dim > 1 ? m : 0); ++j)
      for (long k = (dim > 2 ? -m : 0); k <= (dim > 2 ? m : 0); ++k) {
        const long a = 2 * i + 1, b = dim > 1 ? 2 * j + 1 : 0, c = dim > 2 ? 2 * k + 1 : 0;
        if (std::abs(a) > m || std::abs(b) > m || std::abs(c) > m) continue;
        if (a * a + b * b + c * c <= rOverHalfDx * rOverHalfDx) ++n;
      }
  return n;
}

}  // namespace

TEST(Geometry, BoxCounts1D2D3D) {
  {
    const Domain d = makeDomain(1, {0, 0, 0}, {1, 0, 0});
    const LatticeFill f = fillLattice({box({0, 0, 0}, {1, 0, 0})}, d, 0.01);
    EXPECT_EQ(f.count(), 100);
    EXPECT_NEAR(f.position.front(), 0.005, 1e-15);
    EXPECT_NEAR(f.position.back(), 0.995, 1e-12);
  }
  {
    const Domain d = makeDomain(2, {0, 0, 0}, {1, 0.5, 0});
    const LatticeFill f = fillLattice({box({0, 0, 0}, {1, 0.5, 0})}, d, 0.1);
    EXPECT_EQ(f.count(), 50);
    ASSERT_EQ(f.position.size(), 100u);
    // x fastest: the second site is one dx further along x.
    EXPECT_NEAR(f.position[2] - f.position[0], 0.1, 1e-14);
    EXPECT_NEAR(f.position[1], 0.05, 1e-15);
  }
  {
    const Domain d = makeDomain(3, {0, 0, 0}, {0.3, 0.2, 0.5});
    const LatticeFill f = fillLattice({box({0, 0, 0}, {0.3, 0.2, 0.5})}, d, 0.01);
    EXPECT_EQ(f.count(), 30 * 20 * 50);
  }
}

TEST(Geometry, SitesAreUniqueAndInsideTheBox) {
  const Domain d = makeDomain(3, {-1, -1, -1}, {1, 1, 1});
  const LatticeFill f = fillLattice({box({-0.2, 0.1, -0.35}, {0.3, 0.4, 0.05})}, d, 0.05);
  EXPECT_EQ(f.count(), 10 * 6 * 8);
  std::set<std::tuple<long, long, long>> seen;
  for (Index k = 0; k < f.count(); ++k) {
    const double* x = &f.position[static_cast<size_t>(3 * k)];
    EXPECT_GT(x[0], -0.2);
    EXPECT_LT(x[0], 0.3);
    EXPECT_GT(x[2], -0.35);
    EXPECT_LT(x[2], 0.05);
    seen.insert({std::lround(x[0] / 0.025), std::lround(x[1] / 0.025), std::lround(x[2] / 0.025)});
  }
  EXPECT_EQ(static_cast<Index>(seen.size()), f.count());
}

TEST(Geometry, DiscSphereAndSegmentCountsMatchIntegerCounts) {
  // Centres on lattice corners, radius 0.1 with dx = 0.01: radius = 20 half-spacings.
  const double dx = 0.01;
  {
    const Domain d = makeDomain(2, {0, 0, 0}, {1, 1, 0});
    const LatticeFill f = fillLattice({sphere({0.5, 0.5, 0}, 0.1)}, d, dx);
    const long expected = oddSitesWithin(2, 20);
    EXPECT_EQ(f.count(), expected);
    // and the area is pi R^2 within 2 %
    EXPECT_NEAR(static_cast<double>(f.count()) * dx * dx, M_PI * 0.01, 0.02 * M_PI * 0.01);
  }
  {
    const Domain d = makeDomain(3, {0, 0, 0}, {1, 1, 1});
    const LatticeFill f = fillLattice({sphere({0.5, 0.5, 0.5}, 0.1)}, d, dx);
    EXPECT_EQ(f.count(), oddSitesWithin(3, 20));
    EXPECT_NEAR(static_cast<double>(f.count()) * dx * dx * dx, 4.0 / 3.0 * M_PI * 1e-3,
                0.02 * 4.0 / 3.0 * M_PI * 1e-3);
  }
  {
    const Domain d = makeDomain(1, {0, 0, 0}, {1, 0, 0});
    const LatticeFill f = fillLattice({sphere({0.5, 0, 0}, 0.1)}, d, dx);
    EXPECT_EQ(f.count(), 20);
  }
}

TEST(Geometry, LaterRegionsOverrideAndNoneSubtracts) {
  const Domain d = makeDomain(2, {0, 0, 0}, {1, 1, 0});
  std::vector<Region> r = {box({0, 0, 0}, {1, 1, 0}, 0), box({0.5, 0, 0}, {1, 1, 0}, 1),
                           sphere({0.5, 0.5, 0}, 0.2, -1)};
  const LatticeFill f = fillLattice(r, d, 0.05);
  long disc = oddSitesWithin(2, 8);  // radius 0.2 = 8 half-spacings
  EXPECT_EQ(f.count(), 400 - disc);
  long inRegion[3] = {0, 0, 0};
  for (Index k = 0; k < f.count(); ++k) {
    const int reg = f.region[static_cast<size_t>(k)];
    ASSERT_GE(reg, 0);
    ASSERT_LE(reg, 1);
    ++inRegion[reg];
    EXPECT_EQ(reg, f.position[static_cast<size_t>(2 * k)] > 0.5 ? 1 : 0);
  }
  EXPECT_EQ(inRegion[0], 200 - disc / 2);
  EXPECT_EQ(inRegion[1], 200 - disc / 2);
  // A region added after the subtraction fills the hole again.
  r.push_back(sphere({0.5, 0.5, 0}, 0.1, 0));
  EXPECT_EQ(fillLattice(r, d, 0.05).count(), 400 - disc + oddSitesWithin(2, 4));
}

TEST(Geometry, WallLayersOutsideTheDomainLineUpWithTheLattice) {
  // Non-periodic y: three wall layers below y = 0 and above y = 0.2.
  const Domain d = makeDomain(2, {0, 0, 0}, {0.4, 0.2, 0}, {true, false, false});
  const std::vector<Region> r = {box({0, -0.03, 0}, {0.4, 0, 0}, 1), box({0, 0, 0}, {0.4, 0.2, 0}, 0),
                                 box({0, 0.2, 0}, {0.4, 0.23, 0}, 1)};
  const LatticeFill f = fillLattice(r, d, 0.01);
  EXPECT_EQ(f.count(), 40 * (3 + 20 + 3));
  long walls = 0;
  double ymin = 1e9;
  for (Index k = 0; k < f.count(); ++k) {
    walls += f.region[static_cast<size_t>(k)] != 1 ? 1 : 0;  // regions 0 and 2 are walls
    ymin = std::min(ymin, f.position[static_cast<size_t>(2 * k + 1)]);
  }
  EXPECT_EQ(walls, 40 * 6);
  EXPECT_NEAR(ymin, -0.025, 1e-12);
}

TEST(Geometry, PeriodicAxesAreClippedToTheDomain) {
  const Domain d = makeDomain(2, {0, 0, 0}, {0.4, 0.2, 0}, {true, false, false});
  // The box reaches past both periodic faces; only the 40 columns inside [0, 0.4) exist.
  const LatticeFill f = fillLattice({box({-0.1, 0, 0}, {0.5, 0.2, 0})}, d, 0.01);
  EXPECT_EQ(f.count(), 40 * 20);
  for (Index k = 0; k < f.count(); ++k) {
    EXPECT_GE(f.position[static_cast<size_t>(2 * k)], 0.0);
    EXPECT_LT(f.position[static_cast<size_t>(2 * k)], 0.4);
  }
}

TEST(Geometry, PeriodicLengthMustBeWholeSpacings) {
  const Domain d = makeDomain(2, {0, 0, 0}, {0.405, 0.2, 0}, {true, false, false});
  try {
    fillLattice({box({0, 0, 0}, {0.405, 0.2, 0})}, d, 0.01);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("axis x"), std::string::npos) << m;
    EXPECT_NE(m.find("0.405"), std::string::npos) << m;
    EXPECT_NE(m.find("0.01"), std::string::npos) << m;
  }
}

TEST(Geometry, OnlySubtractingRegionsGiveNoSite) {
  const Domain d = makeDomain(2, {0, 0, 0}, {1, 1, 0});
  EXPECT_EQ(fillLattice({sphere({0.5, 0.5, 0}, 0.2, -1)}, d, 0.05).count(), 0);
}
