// solid: {family_storage: fast | compact} (docs/solid.md): the TL reference family keeps both
// corrected gradients per member (fast, the default) or g_ab and the slot of b's own entry for a
// (compact: D x 8 - 4 bytes less per member, 2.1 kB per particle in 3D). The two read the same
// numbers, so a run must be bitwise the same; the compact one must register the smaller field;
// the key is refused where no family exists.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "libcore/parameters.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "physics/solid/elastic_solid.hpp"

using namespace poresph;

namespace {
std::string cantilever(const std::string& storage, const std::string& formulation) {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/solid_cantilever.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  const size_t f = text.find("formulation: total_lagrangian");
  EXPECT_NE(f, std::string::npos);
  text.replace(f, 29, "formulation: " + formulation);
  if (formulation != "total_lagrangian") {  // hourglass control is TL only
    const size_t h = text.find("    hourglass:");
    if (h != std::string::npos) text.erase(h, text.find('\n', h) - h + 1);
  }
  const size_t s = text.find("\nsolid:\n");
  EXPECT_NE(s, std::string::npos);
  if (!storage.empty()) text.insert(s + 8, "  family_storage: " + storage + "\n");
  const size_t e = text.find("end_time: 0.6");
  EXPECT_NE(e, std::string::npos);
  text.replace(e, 13, "end_time: 0.6\nmax_steps: 60");
  return text;
}
}  // namespace

TEST(SolidFamilyStorage, CompactRunsBitwiseAsFastWithLessMemory) {
  Scene fast = loadSceneText(cantilever("", "total_lagrangian"), "fast.yaml");
  Scene compact = loadSceneText(cantilever("compact", "total_lagrangian"), "compact.yaml");
  RunOptions o;
  o.handleSignals = false;
  o.outDir = std::string(PORESPH_BINARY_DIR) + "/test-family-storage/fast";
  ASSERT_EQ(runScene(fast, o).status, RunStatus::Finished);
  o.outDir = std::string(PORESPH_BINARY_DIR) + "/test-family-storage/compact";
  ASSERT_EQ(runScene(compact, o).status, RunStatus::Finished);
  const ParticleStore& a = fast.sim->store;
  const ParticleStore& b = compact.sim->store;
  ASSERT_EQ(a.realCount(), b.realCount());
  ASSERT_EQ(fast.sim->step, 60);
  const int d = fast.sim->dimension();
  double vmax = 0.0;
  for (Index q = 0; q < a.realCount() * d; ++q) {
    ASSERT_EQ(a.data(a.position())[q], b.data(b.position())[q]) << q;
    ASSERT_EQ(a.data(a.velocity())[q], b.data(b.velocity())[q]) << q;
    vmax = std::max(vmax, std::abs(a.data(a.velocity())[q]));
  }
  EXPECT_GT(vmax, 0.0);
  // The family rows are held by the module (compressed over the solid particles): compact keeps
  // a 4-byte slot instead of D doubles per member; the store holds the same fields in both.
  const auto* sa = dynamic_cast<const solid::ElasticSolidModule*>(fast.sim->modules.front().get());
  const auto* sb =
      dynamic_cast<const solid::ElasticSolidModule*>(compact.sim->modules.front().get());
  ASSERT_NE(sa, nullptr);
  ASSERT_NE(sb, nullptr);
  const std::int64_t members = sa->familyMembers();
  EXPECT_EQ(members, sb->familyMembers());
  EXPECT_GT(members, a.realCount());
  EXPECT_EQ(a.bytesPerParticle(), b.bytesPerParticle());
  EXPECT_EQ(sa->heldBytes() - sb->heldBytes(),
            static_cast<std::uint64_t>(members) * (d * sizeof(double) - sizeof(std::int32_t)));
}

// The family is held only for the solid's own particles, in rows of their own length (not padded
// to the largest family): the bytes held equal the members times their size plus one offset per
// solid particle. (Other particles hold the 4-byte row index only: OnlyWhatASceneNeeds tests.)
TEST(SolidFamilyStorage, HeldOnlyForSolidParticlesInRowsOfTheirOwnLength) {
  Scene fast = loadSceneText(cantilever("", "total_lagrangian"), "fast.yaml");
  const auto* m = dynamic_cast<const solid::ElasticSolidModule*>(fast.sim->modules.front().get());
  ASSERT_NE(m, nullptr);
  const ParticleStore& st = fast.sim->store;
  const std::int32_t* row = st.data(st.integer("solid_family_row"));
  Index solidParticles = 0;
  for (Index i = 0; i < st.realCount(); ++i) solidParticles += row[i] >= 0 ? 1 : 0;
  ASSERT_GT(solidParticles, 0);
  const int d = fast.sim->dimension();
  const std::int64_t members = m->familyMembers();
  EXPECT_LT(members, static_cast<std::int64_t>(m->familyCapacity()) * solidParticles)
      << "rows padded to the largest family";
  EXPECT_EQ(m->heldBytes(), static_cast<std::uint64_t>(solidParticles + 1) * 8 +
                                static_cast<std::uint64_t>(members) * (4 + 2 * d * 8));
}

TEST(SolidFamilyStorage, RefusedWithoutAFamilyOrWithAnUnknownValue) {
  try {
    loadSceneText(cantilever("compact", "small_strain_stress"), "ss.yaml");
    FAIL() << "accepted family_storage with a small-strain solid";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("family_storage"), std::string::npos) << e.what();
  }
  try {
    loadSceneText(cantilever("tiny", "total_lagrangian"), "tiny.yaml");
    FAIL() << "accepted family_storage: tiny";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tiny"), std::string::npos) << e.what();
  }
}
