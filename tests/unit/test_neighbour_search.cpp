// Unit tests of the cell-list neighbour search (libcore/neighbour_search.hpp) together with the
// periodic halo (libcore/halo.hpp): the lists must hold exactly the pairs a brute-force search
// finds, in 1D, 2D and 3D, periodic on some, all or no axes, for non-cubic boxes, particles on
// cell faces and domain faces, duplicated positions, and periodic boxes shorter than two
// supports (several images of one particle within the radius).
//
// A neighbour is identified by (source particle, periodic image vector n): a ghost maps back to
// its source with ghostSources() and n = round((x_ghost - x_source) / L) per periodic axis. The
// brute force loops over all real particles and every image n that can be within the radius,
// so it does not depend on the halo being complete.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <string>
#include <tuple>
#include <vector>

#include "libcore/halo.hpp"
#include "libcore/neighbour_search.hpp"
#include "libcore/particle_store.hpp"

using namespace poresph;

namespace {

using Neighbour = std::array<Index, 4>;  // source id, image n_x, n_y, n_z
using Lists = std::vector<std::vector<Neighbour>>;

Domain makeDomain(int d, std::array<double, 3> lo, std::array<double, 3> hi,
                  std::array<bool, 3> periodic) {
  Domain dom;
  dom.dimension = d;
  dom.lo = lo;
  dom.hi = hi;
  dom.periodic = periodic;
  return dom;
}

// Fills the store with the given positions (D per particle).
ParticleStore makeStore(int d, const std::vector<double>& x) {
  ParticleStore s(d);
  s.addParticles(static_cast<Index>(x.size()) / d);
  std::copy(x.begin(), x.end(), s.data(s.position()));
  return s;
}

// Lists from the cell search (after the halo), as sorted (source, image) per real particle.
Lists searchLists(ParticleStore& s, const Domain& dom, double radius, NeighbourList* raw = nullptr,
                  NeighbourSearch* searchOut = nullptr) {
  PeriodicHalo halo;
  halo.build(s, dom, radius);
  NeighbourSearch search;
  NeighbourList list;
  const int d = s.dimension();
  search.build(s.data(s.position()), d, s.realCount(), s.size(), radius, list);
  const double* x = s.data(s.position());
  Lists out(static_cast<size_t>(s.realCount()));
  EXPECT_EQ(list.realCount(), s.realCount());
  for (Index i = 0; i < s.realCount(); ++i) {
    for (std::int64_t k = list.offset[i]; k < list.offset[i + 1]; ++k) {
      const Index j = list.index[static_cast<size_t>(k)];
      EXPECT_NE(j, i) << "self in the list of " << i;
      EXPECT_LT(j, s.size());
      Neighbour nb{j, 0, 0, 0};
      if (j >= s.realCount()) {
        const Index src = s.ghostSources()[static_cast<size_t>(j - s.realCount())];
        nb[0] = src;
        for (int a = 0; a < d; ++a)
          if (dom.periodic[a])
            nb[1 + a] = std::llround((x[j * d + a] - x[src * d + a]) / dom.length(a));
      }
      out[static_cast<size_t>(i)].push_back(nb);
    }
    std::sort(out[static_cast<size_t>(i)].begin(), out[static_cast<size_t>(i)].end());
  }
  if (raw) *raw = list;
  if (searchOut) *searchOut = search;
  return out;
}

// Brute force over all pairs of real particles and all images n along periodic axes.
// The image position is x_j + n L computed as the halo does (x_j + (+-L)) for |n| = 1, so that
// distances on the radius are decided by the same floating-point numbers.
Lists bruteLists(const ParticleStore& s, const Domain& dom, double radius) {
  const int d = s.dimension();
  const double* x = s.data(s.position());
  const Index n = s.realCount();
  const double r2max = radius * radius;
  // Image n along a periodic axis of length L can be within the radius only if
  // |n| L - L < radius (two particles of the box are less than L apart): |n| <= ceil(r / L).
  int range[3] = {0, 0, 0};
  for (int a = 0; a < d; ++a)
    range[a] = dom.periodic[a] ? static_cast<int>(std::ceil(radius / dom.length(a))) : 0;
  Lists out(static_cast<size_t>(n));
#pragma omp parallel for schedule(dynamic, 16)
  for (Index i = 0; i < n; ++i) {
    auto& li = out[static_cast<size_t>(i)];
    for (Index j = 0; j < n; ++j)
      for (int n0 = -range[0]; n0 <= range[0]; ++n0)
        for (int n1 = -range[1]; n1 <= range[1]; ++n1)
          for (int n2 = -range[2]; n2 <= range[2]; ++n2) {
            if (j == i && n0 == 0 && n1 == 0 && n2 == 0) continue;
            const int img[3] = {n0, n1, n2};
            double r2 = 0.0;
            for (int a = 0; a < d; ++a) {
              double xj = x[j * d + a];
              if (img[a] != 0) {
                const double len = dom.length(a);
                for (int m = 0; m < std::abs(img[a]); ++m) xj += img[a] > 0 ? len : -len;
              }
              const double dx = x[i * d + a] - xj;
              r2 += dx * dx;
            }
            if (r2 < r2max) li.push_back(Neighbour{j, n0, n1, n2});
          }
    std::sort(li.begin(), li.end());
  }
  return out;
}

std::int64_t countPairs(const Lists& l) {
  std::int64_t c = 0;
  for (const auto& v : l) c += static_cast<std::int64_t>(v.size());
  return c;
}

void expectSameLists(const Lists& got, const Lists& want, const std::string& what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  Index bad = 0;
  for (size_t i = 0; i < got.size(); ++i)
    if (got[i] != want[i]) {
      if (++bad <= 3) {
        std::string g, w;
        for (const auto& nb : got[i]) g += " " + std::to_string(nb[0]);
        for (const auto& nb : want[i]) w += " " + std::to_string(nb[0]);
        ADD_FAILURE() << what << ": particle " << i << " search:" << g << " | brute:" << w;
      }
    }
  EXPECT_EQ(bad, 0) << what << ": particles whose lists differ";
}

std::vector<double> randomCloud(int d, Index n, const Domain& dom, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<double> x(static_cast<size_t>(n * d));
  for (Index i = 0; i < n; ++i)
    for (int a = 0; a < d; ++a) {
      std::uniform_real_distribution<double> u(dom.lo[a], dom.hi[a]);
      x[static_cast<size_t>(i * d + a)] = u(rng);
    }
  return x;
}

// Runs search and brute force on a cloud and compares; returns the number of pairs.
std::int64_t checkCloud(int d, const std::vector<double>& x, const Domain& dom, double radius,
                        const std::string& what) {
  ParticleStore s = makeStore(d, x);
  const Lists got = searchLists(s, dom, radius);
  const Lists want = bruteLists(s, dom, radius);  // positions after the halo's wrap
  expectSameLists(got, want, what);
  return countPairs(want);
}

}  // namespace

TEST(NeighbourSearch, RandomCloudsMatchBruteForce3D) {
  const double r = 0.11;
  const std::array<std::array<bool, 3>, 4> periodicity{
      {{false, false, false}, {true, true, true}, {true, false, true}, {false, true, false}}};
  for (size_t p = 0; p < periodicity.size(); ++p) {
    // Non-cubic box, offset from the origin.
    const Domain dom = makeDomain(3, {-0.3, 0.1, 1.0}, {0.5, 0.55, 2.2}, periodicity[p]);
    const auto x = randomCloud(3, 1200, dom, 11 + p);
    const auto pairs = checkCloud(3, x, dom, r, "3D periodicity case " + std::to_string(p));
    EXPECT_GT(pairs, 1200 * 4) << "too few pairs for a meaningful test";
  }
}

TEST(NeighbourSearch, RandomCloudsMatchBruteForce2D) {
  const double r = 0.07;
  const std::array<std::array<bool, 3>, 4> periodicity{
      {{false, false, false}, {true, true, false}, {true, false, false}, {false, true, false}}};
  for (size_t p = 0; p < periodicity.size(); ++p) {
    const Domain dom = makeDomain(2, {0.0, -1.0, 0.0}, {1.0, -0.6, 0.0}, periodicity[p]);
    const auto x = randomCloud(2, 1500, dom, 100 + p);
    const auto pairs = checkCloud(2, x, dom, r, "2D periodicity case " + std::to_string(p));
    EXPECT_GT(pairs, 1500 * 10);
  }
}

TEST(NeighbourSearch, RandomCloudsMatchBruteForce1D) {
  for (bool periodic : {false, true}) {
    const Domain dom = makeDomain(1, {2.0, 0, 0}, {3.0, 0, 0}, {periodic, false, false});
    const auto x = randomCloud(1, 800, dom, 7);
    const auto pairs = checkCloud(1, x, dom, 0.013, periodic ? "1D periodic" : "1D");
    EXPECT_GT(pairs, 800 * 10);
  }
}

TEST(NeighbourSearch, LatticeOnCellFacesAndDomainFaces) {
  // Spacing dx = radius / 2 starting at the box face: every particle lies on a cell face of the
  // search (cells are >= radius and start at the lowest particle), and pairs at exactly the
  // radius (excluded: the search is strict) occur everywhere. Particles on both domain faces.
  for (int d = 1; d <= 3; ++d)
    for (bool periodic : {false, true}) {
      const double r = 0.1, dx = 0.05;
      const int m = d == 3 ? 10 : 20;  // points per axis
      Domain dom = makeDomain(d, {0, 0, 0}, {m * dx, m * dx, m * dx}, {periodic, periodic, false});
      if (!periodic) dom.hi = {(m - 1) * dx, (m - 1) * dx, (m - 1) * dx};  // points on hi too
      std::vector<double> x;
      const int my = d > 1 ? m : 1, mz = d > 2 ? m : 1;
      for (int k = 0; k < mz; ++k)
        for (int j = 0; j < my; ++j)
          for (int i = 0; i < m; ++i) {
            x.push_back(i * dx);
            if (d > 1) x.push_back(j * dx);
            if (d > 2) x.push_back(k * dx);
          }
      checkCloud(d, x, dom, r,
                 "lattice " + std::to_string(d) + "D" + (periodic ? " periodic" : ""));
      // Same lattice, radius just above the spacing multiples: pairs at dx and 2 dx included.
      checkCloud(d, x, dom, r * (1 + 1e-9), "lattice, radius 2dx+");
    }
}

TEST(NeighbourSearch, ParticlesOnCellFacesOfTheRandomCloud) {
  // Random cloud with a third of the coordinates snapped to multiples of the radius (cell faces
  // when the lowest particle sits at 0) and some particles on the periodic faces lo and hi.
  const double r = 0.1;
  for (bool periodic : {false, true}) {
    const Domain dom = makeDomain(3, {0, 0, 0}, {1.0, 0.6, 0.8}, {periodic, periodic, periodic});
    auto x = randomCloud(3, 1000, dom, 5);
    std::mt19937 rng(3);
    for (size_t k = 0; k < x.size(); ++k) {
      const int a = static_cast<int>(k % 3);
      if (rng() % 3 == 0) x[k] = std::round(x[k] / r) * r;
      if (x[k] > dom.hi[a]) x[k] = dom.hi[a];
    }
    x[0] = x[1] = x[2] = 0.0;  // a corner at lo (and so a cell corner)
    x[3] = 1.0, x[4] = 0.6, x[5] = 0.8;  // the opposite corner: wrapped to lo when periodic
    checkCloud(3, x, dom, r, periodic ? "snapped periodic" : "snapped");
  }
}

TEST(NeighbourSearch, DuplicatedPositions) {
  // Coincident particles are neighbours of each other (r = 0 < radius), never of themselves.
  for (int d = 1; d <= 3; ++d) {
    const Domain dom = makeDomain(d, {0, 0, 0}, {1, 1, 1}, {true, false, false});
    auto x = randomCloud(d, 300, dom, 9);
    std::vector<double> dup(x.begin(), x.begin() + 50 * d);  // 50 particles three times
    x.insert(x.end(), dup.begin(), dup.end());
    x.insert(x.end(), dup.begin(), dup.end());
    for (int k = 0; k < 5; ++k)  // five particles on one point
      for (int a = 0; a < d; ++a) x.push_back(0.5);
    checkCloud(d, x, dom, 0.08, "duplicates " + std::to_string(d) + "D");
    ParticleStore s = makeStore(d, x);
    const Lists got = searchLists(s, dom, 0.08);
    // Particle 0 sees its two copies 300 and 350.
    int copies = 0;
    for (const auto& nb : got[0]) copies += (nb[0] == 300 || nb[0] == 350) && nb[1] == 0;
    EXPECT_EQ(copies, 2);
  }
}

TEST(NeighbourSearch, PeriodicBoxShorterThanTwoSupports) {
  // L in [radius, 2 radius): one particle may see a neighbour and one or two of its images, and
  // its own images. The brute force counts every image within the radius.
  const double r = 0.1;
  for (int d = 1; d <= 3; ++d) {
    for (double L : {1.0 * r, 1.3 * r, 1.99 * r}) {
      const Domain dom = makeDomain(d, {0, 0, 0}, {L, L * 1.7, L}, {true, true, true});
      const auto x = randomCloud(d, d == 3 ? 60 : 150, dom, 21);
      const auto pairs = checkCloud(d, x, dom, r, "short box " + std::to_string(d) + "D L/r=" +
                                                      std::to_string(L / r));
      EXPECT_GT(pairs, 0);
    }
    // Only some axes short, the others long and non-periodic.
    const Domain dom = makeDomain(d, {0, 0, 0}, {1.5 * r, 1.0, 0.7}, {true, false, false});
    checkCloud(d, randomCloud(d, 400, dom, 22), dom, r, "short x only");
  }
  // A periodic length below the radius would need images of images (and a particle would see
  // its own images): the halo refuses it.
  ParticleStore s(1);
  s.addParticles(1);
  PeriodicHalo halo;
  EXPECT_THROW(halo.build(s, makeDomain(1, {0, 0, 0}, {0.06, 0, 0}, {true, false, false}), r),
               InputError);
}

TEST(NeighbourSearch, SameListsWhateverTheThreadCount) {
  const Domain dom = makeDomain(3, {0, 0, 0}, {1, 1, 1}, {true, true, true});
  const auto x = randomCloud(3, 3000, dom, 77);
  ParticleStore s = makeStore(3, x);
  PeriodicHalo halo;
  halo.build(s, dom, 0.1);
  NeighbourSearch search;
  NeighbourList one, two, three;
  const int before = omp_get_max_threads();
  omp_set_num_threads(1);
  search.build(s.data(s.position()), 3, s.realCount(), s.size(), 0.1, one);
  omp_set_num_threads(2);
  search.build(s.data(s.position()), 3, s.realCount(), s.size(), 0.1, two);
  omp_set_num_threads(3);
  search.build(s.data(s.position()), 3, s.realCount(), s.size(), 0.1, three);
  omp_set_num_threads(before);
  EXPECT_EQ(one.offset, two.offset);
  EXPECT_EQ(one.index, two.index);
  EXPECT_EQ(one.offset, three.offset);
  EXPECT_EQ(one.index, three.index);
  EXPECT_GT(one.pairCount(), 0);
}

TEST(NeighbourSearch, ReusedSearchAndListStayCorrect) {
  // One search object and one list reused for clouds of different sizes, dimensions and radii.
  NeighbourSearch search;
  NeighbourList list;
  for (int round = 0; round < 4; ++round) {
    const int d = 1 + round % 3;
    const Index n = round % 2 ? 300 : 1200;
    const double r = round % 2 ? 0.2 : 0.09;
    const Domain dom = makeDomain(d, {0, 0, 0}, {1, 1, 1}, {false, false, false});
    ParticleStore s = makeStore(d, randomCloud(d, n, dom, 40 + round));
    search.build(s.data(s.position()), d, n, n, r, list);
    ASSERT_EQ(list.realCount(), n);
    const Lists want = bruteLists(s, dom, r);
    Lists got(static_cast<size_t>(n));
    for (Index i = 0; i < n; ++i) {
      for (auto k = list.offset[i]; k < list.offset[i + 1]; ++k)
        got[i].push_back(Neighbour{list.index[k], 0, 0, 0});
      std::sort(got[i].begin(), got[i].end());
    }
    expectSameLists(got, want, "reuse round " + std::to_string(round));
    EXPECT_EQ(list.pairCount(), countPairs(want));
  }
}

TEST(NeighbourSearch, OnlyRealParticlesGetLists) {
  // nReal < nTotal without a halo: the trailing particles are candidates only.
  const Domain dom = makeDomain(2, {0, 0, 0}, {1, 1, 0}, {false, false, false});
  const auto x = randomCloud(2, 500, dom, 8);
  NeighbourSearch search;
  NeighbourList list;
  search.build(x.data(), 2, 200, 500, 0.1, list);
  EXPECT_EQ(list.realCount(), 200);
  std::int64_t brute = 0;
  for (Index i = 0; i < 200; ++i)
    for (Index j = 0; j < 500; ++j) {
      if (i == j) continue;
      const double dx = x[2 * i] - x[2 * j], dy = x[2 * i + 1] - x[2 * j + 1];
      brute += dx * dx + dy * dy < 0.01;
    }
  EXPECT_EQ(list.pairCount(), brute);
  EXPECT_GT(list.bytes(), 0u);
}

TEST(NeighbourSearch, CellOrderIsAPermutationSortedByCell) {
  const Domain dom = makeDomain(3, {0, 0, 0}, {1, 0.5, 0.7}, {false, false, false});
  const auto x = randomCloud(3, 2000, dom, 4);
  ParticleStore s = makeStore(3, x);
  const Lists before = bruteLists(s, dom, 0.1);
  NeighbourSearch search;
  std::vector<Index> order;
  search.cellOrder(s.data(s.position()), 3, s.realCount(), 0.1, order);
  ASSERT_EQ(order.size(), 2000u);
  std::vector<Index> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (Index k = 0; k < 2000; ++k) ASSERT_EQ(sorted[k], k);
  // Cell keys (x fastest) do not decrease along the order.
  // (The search's cells start at the lowest particle, so compare with that origin.)
  double lo[3] = {1e9, 1e9, 1e9};
  for (Index i = 0; i < 2000; ++i)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], x[3 * i + a]);
  auto key2 = [&](Index i) {
    const double* p = x.data() + 3 * i;
    return std::make_tuple(static_cast<Index>((p[2] - lo[2]) / 0.1),
                           static_cast<Index>((p[1] - lo[1]) / 0.1),
                           static_cast<Index>((p[0] - lo[0]) / 0.1));
  };
  for (Index k = 1; k < 2000; ++k) ASSERT_LE(key2(order[k - 1]), key2(order[k])) << k;
  // After the permutation, the same pairs (by particle id) are found.
  s.permute(order);
  NeighbourList list;
  search.build(s.data(s.position()), 3, 2000, 2000, 0.1, list);
  EXPECT_EQ(list.pairCount(), countPairs(before));
  const std::int32_t* id = s.data(s.id());
  for (Index i = 0; i < 2000; ++i) {
    std::vector<Index> got;
    for (auto k = list.offset[i]; k < list.offset[i + 1]; ++k) got.push_back(id[list.index[k]]);
    std::sort(got.begin(), got.end());
    std::vector<Index> want;
    for (const auto& nb : before[static_cast<size_t>(id[i])]) want.push_back(nb[0]);
    ASSERT_EQ(got, want) << "particle id " << id[i];
  }
}

TEST(NeighbourSearch, BadArguments) {
  NeighbourSearch search;
  NeighbourList list;
  const std::vector<double> x{0.0, 1.0};
  EXPECT_THROW(search.build(x.data(), 1, 2, 2, 0.0, list), std::logic_error);
  EXPECT_THROW(search.build(x.data(), 1, 2, 2, -1.0, list), std::logic_error);
  EXPECT_THROW(search.build(x.data(), 4, 2, 2, 1.0, list), InputError);
  // No particles: empty lists.
  search.build(x.data(), 1, 0, 0, 1.0, list);
  EXPECT_EQ(list.realCount(), 0);
  EXPECT_EQ(list.pairCount(), 0);
}

TEST(NeighbourSearch, RepeatedBuildsMatchAFreshSearchAndStopAllocating) {
  // The search writes the list in place, one region per thread sized from the previous build;
  // a growing list falls back to per-thread buffers. Whatever the path, every build must equal
  // the build of a fresh search object, and a steady cloud must not reallocate the list.
  const Domain dom = makeDomain(3, {0, 0, 0}, {1, 0.8, 0.6}, {false, false, false});
  std::vector<double> x = randomCloud(3, 4000, dom, 91);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> jitter(0.0, 0.01);
  NeighbourSearch search;
  NeighbourList list;
  const int before = omp_get_max_threads();
  for (int round = 0; round < 12; ++round) {
    omp_set_num_threads(round < 6 ? 2 : 3);
    // Rounds 0-3 move the particles (the list length changes), later rounds clump them
    // (the list grows: overflow path) or keep them (steady state).
    if (round < 4)
      for (auto& v : x) v += jitter(rng);
    if (round == 4 || round == 8)
      for (auto& v : x) v *= 0.8;
    search.build(x.data(), 3, 4000, 4000, 0.08, list);
    NeighbourSearch fresh;
    NeighbourList ref;
    fresh.build(x.data(), 3, 4000, 4000, 0.08, ref);
    ASSERT_EQ(list.offset, ref.offset) << "round " << round;
    ASSERT_EQ(list.index, ref.index) << "round " << round;
    if (round == 5 || round == 10) {  // steady state from here: same cloud, same threads
      const std::uint32_t* p = list.index.data();
      const std::size_t bytes = search.bytes() + list.bytes();
      search.build(x.data(), 3, 4000, 4000, 0.08, list);
      EXPECT_EQ(list.index.data(), p) << "the list was reallocated in the steady state";
      EXPECT_EQ(search.bytes() + list.bytes(), bytes);
      EXPECT_EQ(list.index, ref.index);
    }
  }
  omp_set_num_threads(before);
}
