// Unit tests of the periodic halo (libcore/halo.hpp): wrapping, which particles get images
// (faces, edges, corners), image positions and fields, refusal of too short periodic lengths.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

#include "libcore/halo.hpp"

using namespace poresph;

namespace {

Domain box(int d, double L, std::array<bool, 3> periodic) {
  Domain dom;
  dom.dimension = d;
  dom.lo = {0.0, 0.0, 0.0};
  dom.hi = {L, L, L};
  dom.periodic = periodic;
  return dom;
}

}  // namespace

TEST(PeriodicHalo, WrapBringsParticlesBackIntoTheBox) {
  ParticleStore s(2);
  s.addParticles(5);
  const double in[10] = {-0.25, 0.5, 1.25, 0.5, 3.5, -2.75, 1.0, 1.0, 0.0, 0.999};
  std::copy(in, in + 10, s.data(s.position()));
  PeriodicHalo halo;
  halo.wrap(s, box(2, 1.0, {true, false, false}));  // x periodic only
  const double* x = s.data(s.position());
  EXPECT_DOUBLE_EQ(x[0], 0.75);
  EXPECT_DOUBLE_EQ(x[2], 0.25);
  EXPECT_DOUBLE_EQ(x[4], 0.5);
  EXPECT_DOUBLE_EQ(x[5], -2.75);  // y not periodic: untouched
  EXPECT_DOUBLE_EQ(x[6], 0.0);    // x = hi is wrapped to lo
  EXPECT_DOUBLE_EQ(x[8], 0.0);
  EXPECT_DOUBLE_EQ(x[9], 0.999);
  for (int i = 0; i < 5; ++i) {
    EXPECT_GE(x[2 * i], 0.0);
    EXPECT_LT(x[2 * i], 1.0);
  }
}

TEST(PeriodicHalo, ImagesOfALatticeHaveTheClosedFormCount) {
  // m^d lattice at (k + 1/2) dx, width w = 2 dx covers 2 layers at each face: along a periodic
  // axis a particle has 1 + (number of faces within w) copies; the images are the product minus
  // the particle itself: (m + 4)^p m^(d-p) - m^d for p periodic axes.
  const int m = 10;
  const double dx = 0.1, w = 2 * dx;
  for (int d = 1; d <= 3; ++d)
    for (int p = 0; p <= d; ++p) {
      ParticleStore s(d);
      const Index n = static_cast<Index>(std::pow(m, d));
      s.addParticles(n);
      double* x = s.data(s.position());
      for (Index i = 0; i < n; ++i) {
        Index r = i;
        for (int a = 0; a < d; ++a) x[i * d + a] = (r % m + 0.5) * dx, r /= m;
      }
      std::array<bool, 3> per{false, false, false};
      for (int a = 0; a < p; ++a) per[a] = true;
      PeriodicHalo halo;
      halo.build(s, box(d, m * dx, per), w);
      const double expect = std::pow(m + 4, p) * std::pow(m, d - p) - std::pow(m, d);
      EXPECT_EQ(static_cast<double>(s.ghostCount()), expect) << d << "D, " << p << " periodic";
      // Every image is within w of the box along periodic axes and inside it along the others,
      // and is its source shifted by a whole number of periods.
      const double* y = s.data(s.position());
      std::set<std::vector<long>> seen;
      for (Index g = 0; g < s.ghostCount(); ++g) {
        const Index k = n + g, src = s.ghostSources()[g];
        ASSERT_LT(src, n);
        std::vector<long> key{static_cast<long>(src)};
        bool shifted = false;
        for (int a = 0; a < d; ++a) {
          const double v = y[k * d + a], shift = v - y[src * d + a];
          const double periods = shift / (m * dx);
          EXPECT_NEAR(periods, std::round(periods), 1e-12);
          if (!per[a]) EXPECT_EQ(shift, 0.0);
          EXPECT_GT(v, -w);
          EXPECT_LT(v, m * dx + w);
          shifted |= std::round(periods) != 0.0;
          key.push_back(std::lround(periods));
        }
        EXPECT_TRUE(shifted);
        EXPECT_TRUE(seen.insert(key).second) << "the same image twice";
      }
    }
}

TEST(PeriodicHalo, ImagesCarryTheFieldsOfTheirSource) {
  ParticleStore s(3);
  const RealField sigma = s.addReal("stress", 9);
  s.addParticles(2);
  s.vec<3>(s.position(), 0) = Vec<3>(0.01, 0.01, 0.01);  // corner: 7 images
  s.vec<3>(s.position(), 1) = Vec<3>(0.5, 0.5, 0.5);     // centre: none
  s.data(s.mass())[0] = 2.5;
  s.mat<3>(sigma, 0) = Mat<3>::Identity() * 4.0;
  PeriodicHalo halo;
  halo.build(s, box(3, 1.0, {true, true, true}), 0.1);
  ASSERT_EQ(s.ghostCount(), 7);
  for (Index g = 2; g < 9; ++g) {
    EXPECT_EQ(s.data(s.mass())[g], 2.5);
    EXPECT_EQ(s.mat<3>(sigma, g), Mat<3>::Identity() * 4.0);
    EXPECT_EQ(s.data(s.id())[g], s.data(s.id())[0]);
  }
  // Rebuilding replaces the ghosts (no accumulation).
  halo.build(s, box(3, 1.0, {true, true, true}), 0.1);
  EXPECT_EQ(s.ghostCount(), 7);
  // Non-periodic: no ghosts at all.
  halo.build(s, box(3, 1.0, {false, false, false}), 0.1);
  EXPECT_EQ(s.ghostCount(), 0);
}

TEST(PeriodicHalo, ShortPeriodicLengthIsAnInputError) {
  ParticleStore s(2);
  s.addParticles(3);
  PeriodicHalo halo;
  Domain dom = box(2, 1.0, {false, true, false});
  dom.hi[1] = 0.05;  // periodic y shorter than the width
  try {
    halo.build(s, dom, 0.1);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("axis 1"), std::string::npos) << e.what();
  }
  // The same length along a non-periodic axis is fine.
  dom.periodic = {true, false, false};
  EXPECT_NO_THROW(halo.build(s, dom, 0.1));
  // Length equal to the width is accepted (each particle near both faces gets both images).
  dom = box(1, 0.1, {true, false, false});
  ParticleStore t(1);
  t.addParticles(1);
  t.data(t.position())[0] = 0.05;
  halo.build(t, dom, 0.1);
  EXPECT_EQ(t.ghostCount(), 2);
}
