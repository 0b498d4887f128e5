// Unit tests of the particle store (libcore/particle_store.hpp): registration, allocation,
// bytesPerParticle, permute, ghosts, refreshGhosts, compact.
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <set>
#include <stdexcept>

#include "libcore/particle_store.hpp"

using namespace poresph;

namespace {

// Core fields in d dimensions: position, velocity (d doubles each), mass, density (one double
// each), phase, material, id (one int32 each).
std::size_t coreBytes(int d) { return (2 * d + 2) * sizeof(double) + 3 * sizeof(std::int32_t); }

// A distinct value for (particle, component, field) so that any mix-up is visible.
double tag(Index i, int q, int field) { return 1000.0 * static_cast<double>(i) + 10.0 * q + field; }

}  // namespace

TEST(ParticleStore, CoreFieldsAndDimension) {
  for (int d = 1; d <= 3; ++d) {
    ParticleStore s(d);
    EXPECT_EQ(s.dimension(), d);
    for (const char* name : {"position", "velocity", "mass", "density", "phase", "material", "id"})
      EXPECT_TRUE(s.has(name)) << name;
    EXPECT_EQ(s.components(s.position().id), d);
    EXPECT_EQ(s.components(s.velocity().id), d);
    EXPECT_EQ(s.components(s.mass().id), 1);
    EXPECT_EQ(s.fields().size(), 7u);
    EXPECT_EQ(s.bytesPerParticle(), coreBytes(d));
  }
  EXPECT_THROW(ParticleStore(0), InputError);
  EXPECT_THROW(ParticleStore(4), InputError);
}

TEST(ParticleStore, ProduceIsRegisterIfAbsent) {
  ParticleStore s(2);
  const RealField a = s.addReal("stress", 4, kFieldOutput, "solid");
  const RealField b = s.addReal("stress", 4, kFieldCheckpoint, "damage");
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(s.real("stress").id, a.id);
  // Flags are OR-ed, the first owner is kept.
  EXPECT_EQ(s.spec(a.id).flags, unsigned(kFieldOutput | kFieldCheckpoint));
  EXPECT_EQ(s.spec(a.id).owner, "solid");
  EXPECT_EQ(s.fields().size(), 8u);
  // Registering a core field again gives the core handle.
  EXPECT_EQ(s.addReal("position", 2).id, s.position().id);
  EXPECT_EQ(s.addInt("phase", 1).id, s.phase().id);

  const IntField f = s.addInt("family", 3, kFieldNone, "bonds");
  EXPECT_EQ(s.addInt("family", 3).id, f.id);
  EXPECT_EQ(s.integer("family").id, f.id);
}

TEST(ParticleStore, DifferentShapeOrTypeThrows) {
  ParticleStore s(3);
  s.addReal("stress", 9);
  EXPECT_THROW(s.addReal("stress", 3), std::logic_error);
  EXPECT_THROW(s.addInt("stress", 9), std::logic_error);
  EXPECT_THROW(s.addReal("position", 2), std::logic_error);
  EXPECT_THROW(s.addReal("bad", 0), std::logic_error);
  // Consume of an absent field or of the wrong type fails.
  EXPECT_THROW(s.real("absent"), std::logic_error);
  EXPECT_THROW(s.integer("stress"), std::logic_error);
  EXPECT_THROW(s.real("phase"), std::logic_error);
  EXPECT_FALSE(s.has("absent"));
}

TEST(ParticleStore, OnlyRegisteredFieldsAllocatedAndBytesPerParticle) {
  ParticleStore s(3);
  s.addParticles(100);
  EXPECT_EQ(s.realCount(), 100);
  EXPECT_EQ(s.size(), 100);
  EXPECT_FALSE(s.has("pressure"));
  EXPECT_EQ(s.bytesPerParticle(), coreBytes(3));  // 76 bytes in 3D
  EXPECT_EQ(coreBytes(3), 76u);
  // A field registered after particles exist has the right length, zero-filled.
  const RealField p = s.addReal("pressure", 1);
  const RealField sig = s.addReal("stress", 9);
  const IntField fam = s.addInt("family", 2);
  EXPECT_EQ(s.bytesPerParticle(), coreBytes(3) + 8 + 72 + 8);
  for (Index i = 0; i < 100; ++i) {
    EXPECT_EQ(s.data(p)[i], 0.0);
    EXPECT_EQ(s.mat<3>(sig, i).squaredNorm(), 0.0);
    EXPECT_EQ(s.data(fam)[2 * i + 1], 0);
  }
  // Registering the same field twice does not count it twice.
  s.addReal("pressure", 1);
  EXPECT_EQ(s.bytesPerParticle(), coreBytes(3) + 8 + 72 + 8);
}

TEST(ParticleStore, AddParticlesGivesFreshIdsAndZeroFields) {
  ParticleStore s(2);
  EXPECT_EQ(s.addParticles(5), 0);
  EXPECT_EQ(s.addParticles(3), 5);
  std::set<std::int32_t> ids;
  for (Index i = 0; i < s.size(); ++i) {
    ids.insert(s.data(s.id())[i]);
    EXPECT_EQ(s.vec<2>(s.position(), i).squaredNorm(), 0.0);
    EXPECT_EQ(s.data(s.mass())[i], 0.0);
  }
  EXPECT_EQ(ids.size(), 8u);
}

TEST(ParticleStore, VecAndMatViews) {
  ParticleStore s(3);
  s.addParticles(2);
  const RealField t = s.addReal("tensor", 9);
  Mat<3> m;
  m << 1, 2, 3, 4, 5, 6, 7, 8, 9;
  s.mat<3>(t, 1) = m;
  s.vec<3>(s.velocity(), 1) = Vec<3>(1.5, -2.5, 3.5);
  // Column-major storage, D*D doubles per particle.
  EXPECT_EQ(s.data(t)[9 + 0], 1.0);
  EXPECT_EQ(s.data(t)[9 + 1], 4.0);
  EXPECT_EQ(s.data(t)[9 + 3], 2.0);
  EXPECT_EQ(s.data(s.velocity())[3 + 2], 3.5);
  EXPECT_EQ(s.mat<3>(t, 0).squaredNorm(), 0.0);
  const ParticleStore& cs = s;
  EXPECT_EQ((cs.mat<3>(t, 1) - m).norm(), 0.0);
}

// Fills every field of the store with tag(original index, component, field id).
void fillTagged(ParticleStore& s) {
  for (const auto& spec : s.fields()) {
    const int f = static_cast<int>(&spec - &s.fields()[0]);
    if (spec.name == "id") continue;  // keep the store's own ids
    for (Index i = 0; i < s.size(); ++i)
      for (int q = 0; q < spec.components; ++q) {
        if (spec.type == FieldType::Real)
          s.data(RealField{f})[i * spec.components + q] = tag(i, q, f);
        else
          s.data(IntField{f})[i * spec.components + q] = static_cast<std::int32_t>(tag(i, q, f));
      }
  }
}

// Checks that particle k of the store carries the tags of original particle src[k].
void expectTagged(const ParticleStore& s, const std::vector<Index>& src, Index first = 0) {
  for (const auto& spec : s.fields()) {
    const int f = static_cast<int>(&spec - &s.fields()[0]);
    if (spec.name == "id") continue;
    for (size_t k = 0; k < src.size(); ++k) {
      const Index i = first + static_cast<Index>(k);
      for (int q = 0; q < spec.components; ++q) {
        const double expect = tag(src[k], q, f);
        if (spec.type == FieldType::Real)
          ASSERT_EQ(s.data(RealField{f})[i * spec.components + q], expect)
              << spec.name << " particle " << i << " component " << q;
        else
          ASSERT_EQ(s.data(IntField{f})[i * spec.components + q], static_cast<std::int32_t>(expect))
              << spec.name << " particle " << i << " component " << q;
      }
    }
  }
}

TEST(ParticleStore, PermuteKeepsEveryFieldConsistent) {
  for (int d = 1; d <= 3; ++d) {
    ParticleStore s(d);
    s.addReal("scalar", 1);
    s.addReal("vector", d);
    s.addReal("tensor", d * d);
    s.addInt("flag", 1);
    s.addInt("ivec", 3);
    const Index n = 1000;
    s.addParticles(n);
    fillTagged(s);
    std::vector<std::int32_t> ids(s.data(s.id()), s.data(s.id()) + n);
    std::vector<Index> order(static_cast<size_t>(n));
    std::iota(order.begin(), order.end(), 0);
    std::mt19937 rng(42 + d);
    std::shuffle(order.begin(), order.end(), rng);
    s.permute(order);
    EXPECT_EQ(s.realCount(), n);
    expectTagged(s, order);
    for (Index k = 0; k < n; ++k) ASSERT_EQ(s.data(s.id())[k], ids[static_cast<size_t>(order[k])]);
    // A second permutation composes with the first.
    std::vector<Index> order2(order.rbegin(), order.rend());
    std::vector<Index> composed(static_cast<size_t>(n));
    for (Index k = 0; k < n; ++k) composed[k] = order[static_cast<size_t>(order2[k])];
    s.permute(order2);
    expectTagged(s, composed);
  }
}

TEST(ParticleStore, PermuteAndAddParticlesRefusedWithGhosts) {
  ParticleStore s(2);
  s.addParticles(3);
  s.addGhosts({0}, {1.0, 0.0});
  EXPECT_THROW(s.permute({0, 1, 2}), std::logic_error);
  EXPECT_THROW(s.addParticles(1), std::logic_error);
  EXPECT_THROW(s.compact({1, 1, 1}), std::logic_error);
  s.clearGhosts();
  EXPECT_THROW(s.permute({0, 1}), std::logic_error);  // wrong size
  EXPECT_NO_THROW(s.permute({2, 0, 1}));
}

TEST(ParticleStore, GhostsCopyOnlyToGhostFieldsAndShiftPositions) {
  ParticleStore s(2);
  const RealField copied = s.addReal("copied", 3, kFieldToGhosts);
  const RealField local = s.addReal("local", 1, kFieldOutput | kFieldCheckpoint);
  const IntField icopied = s.addInt("icopied", 2, kFieldToGhosts);
  const IntField ilocal = s.addInt("ilocal", 1, kFieldOutput);
  const Index n = 10;
  s.addParticles(n);
  fillTagged(s);
  const std::vector<Index> sources{3, 7, 3, 0};
  const std::vector<double> shifts{1.0, 0.0, -1.0, 2.0, 0.0, -0.5, 0.25, 0.25};
  s.addGhosts(sources, shifts);
  EXPECT_EQ(s.realCount(), n);
  EXPECT_EQ(s.ghostCount(), 4);
  EXPECT_EQ(s.size(), n + 4);
  EXPECT_EQ(s.ghostSources(), sources);
  // Real particles untouched.
  std::vector<Index> identity(static_cast<size_t>(n));
  std::iota(identity.begin(), identity.end(), 0);
  expectTagged(s, identity);
  for (size_t k = 0; k < sources.size(); ++k) {
    const Index g = n + static_cast<Index>(k), src = sources[k];
    for (int q = 0; q < 3; ++q) EXPECT_EQ(s.data(copied)[3 * g + q], tag(src, q, copied.id));
    for (int q = 0; q < 2; ++q)
      EXPECT_EQ(s.data(icopied)[2 * g + q], static_cast<std::int32_t>(tag(src, q, icopied.id)));
    // Fields without kFieldToGhosts are not copied (new ghost slots are zero).
    EXPECT_EQ(s.data(local)[g], 0.0);
    EXPECT_EQ(s.data(ilocal)[g], 0);
    // Default-flagged core fields travel (mass, velocity, id, phase).
    EXPECT_EQ(s.data(s.mass())[g], tag(src, 0, s.mass().id));
    EXPECT_EQ(s.data(s.id())[g], s.data(s.id())[src]);
    EXPECT_EQ(s.vec<2>(s.velocity(), g), s.vec<2>(s.velocity(), src));
    // Positions shifted.
    for (int q = 0; q < 2; ++q)
      EXPECT_EQ(s.data(s.position())[2 * g + q], tag(src, q, s.position().id) + shifts[2 * k + q]);
  }
  // A position without kFieldToGhosts still travels: positions are always copied and shifted.
  ParticleStore t(1);
  t.addReal("position", 1, kFieldNone);  // flags OR-ed: still default
  t.addParticles(2);
  t.data(t.position())[1] = 0.5;
  t.addGhosts({1}, {-1.0});
  EXPECT_EQ(t.data(t.position())[2], -0.5);

  // clearGhosts removes them; a second set can be made.
  s.clearGhosts();
  EXPECT_EQ(s.size(), n);
  EXPECT_TRUE(s.ghostSources().empty());
  s.addGhosts({9}, {0.0, 0.0});
  EXPECT_EQ(s.size(), n + 1);
  EXPECT_EQ(s.data(copied)[3 * n + 2], tag(9, 2, copied.id));
  EXPECT_EQ(s.data(local)[n], 0.0);
  // Two calls of addGhosts append.
  s.addGhosts({1, 2}, {0.0, 0.0, 0.0, 0.0});
  EXPECT_EQ(s.ghostCount(), 3);
  EXPECT_EQ(s.ghostSources(), (std::vector<Index>{9, 1, 2}));
  EXPECT_EQ(s.data(copied)[3 * (n + 2)], tag(2, 0, copied.id));
}

TEST(ParticleStore, RefreshGhostsCopiesTheCurrentValues) {
  ParticleStore s(3);
  const RealField p = s.addReal("pressure", 1, kFieldOutput);  // not copied on creation
  const RealField v = s.addReal("vel2", 3, kFieldToGhosts);
  const IntField k = s.addInt("state", 1, kFieldOutput);
  s.addParticles(6);
  s.addGhosts({5, 1, 5}, std::vector<double>(9, 1.0));
  for (Index i = 0; i < 6; ++i) {
    s.data(p)[i] = 10.0 + i;
    s.vec<3>(v, i) = Vec<3>(i, 2 * i, 3 * i);
    s.data(k)[i] = static_cast<std::int32_t>(100 + i);
  }
  for (Index g = 6; g < 9; ++g) EXPECT_EQ(s.data(p)[g], 0.0);
  s.refreshGhosts(p);
  s.refreshGhosts(v);
  s.refreshGhosts(k);
  const Index src[3] = {5, 1, 5};
  for (Index g = 0; g < 3; ++g) {
    EXPECT_EQ(s.data(p)[6 + g], 10.0 + src[g]);
    EXPECT_EQ(s.vec<3>(v, 6 + g), s.vec<3>(v, src[g]));
    EXPECT_EQ(s.data(k)[6 + g], 100 + src[g]);
  }
  // Positions are not touched by refreshing another field.
  EXPECT_EQ(s.vec<3>(s.position(), 6), Vec<3>(1.0, 1.0, 1.0));
}

TEST(ParticleStore, CompactKeepsSelectedParticlesInOrder) {
  ParticleStore s(3);
  s.addReal("tensor", 9);
  s.addInt("flags", 2);
  const Index n = 50;
  s.addParticles(n);
  fillTagged(s);
  std::vector<char> keep(static_cast<size_t>(n));
  std::vector<Index> kept;
  std::vector<std::int32_t> keptIds;
  for (Index i = 0; i < n; ++i) {
    keep[static_cast<size_t>(i)] = (i % 3 != 1);
    if (keep[static_cast<size_t>(i)]) kept.push_back(i), keptIds.push_back(s.data(s.id())[i]);
  }
  s.compact(keep);
  EXPECT_EQ(s.realCount(), static_cast<Index>(kept.size()));
  EXPECT_EQ(s.size(), static_cast<Index>(kept.size()));
  expectTagged(s, kept);
  for (size_t k = 0; k < kept.size(); ++k) EXPECT_EQ(s.data(s.id())[k], keptIds[k]);
  // New particles after a compact get fresh ids (never reused).
  const Index first = s.addParticles(2);
  std::set<std::int32_t> ids(s.data(s.id()), s.data(s.id()) + s.size());
  EXPECT_EQ(ids.size(), static_cast<size_t>(s.size()));
  EXPECT_EQ(s.data(s.mass())[first], 0.0);
  // Keep nothing / everything.
  s.compact(std::vector<char>(static_cast<size_t>(s.realCount()), 1));
  EXPECT_EQ(s.realCount(), static_cast<Index>(kept.size()) + 2);
  s.compact(std::vector<char>(static_cast<size_t>(s.realCount()), 0));
  EXPECT_EQ(s.realCount(), 0);
}

TEST(ParticleStore, CompactRejectsAWrongMaskSize) {
  ParticleStore s(2);
  s.addParticles(4);
  EXPECT_THROW(s.compact({1, 0}), std::logic_error);
}

TEST(ParticleStore, ReserveAvoidsReallocationOfFields) {
  ParticleStore s(3);
  const RealField t = s.addReal("tensor", 9);
  s.reserve(1000);
  s.addParticles(10);
  const double* x0 = s.data(s.position());
  const double* t0 = s.data(t);
  s.addParticles(500);
  s.addGhosts(std::vector<Index>(400, 3), std::vector<double>(1200, 0.5));
  s.clearGhosts();
  // permute works in place: the reserved memory (and the pointers) survive a reorder.
  std::vector<Index> order(510);
  std::iota(order.rbegin(), order.rend(), 0);
  s.permute(order);
  s.addGhosts(std::vector<Index>(10, 3), std::vector<double>(30, 0.5));
  EXPECT_EQ(s.data(s.position()), x0);
  EXPECT_EQ(s.data(t), t0);
}
