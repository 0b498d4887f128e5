// HDF5 checkpoints: bit-exact round trip and errors naming the file and the field.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "libcore/checkpoint.hpp"
#include "libcore/simulation.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {

std::string path(const std::string& name) {
  const fs::path dir = fs::path(PORESPH_BINARY_DIR) / "test-checkpoint";
  fs::create_directories(dir);
  return (dir / name).string();
}

/// dimension d, n particles; extra fields as a module would register them.
std::unique_ptr<Simulation> makeSim(int d, bool withDamage = true, int stressComponents = -1) {
  auto sim = std::make_unique<Simulation>(d);
  ParticleStore& s = sim->store;
  s.addReal("stress", stressComponents > 0 ? stressComponents : d * d, kFieldDefault, "solid");
  if (withDamage) s.addReal("damage", 1, kFieldDefault, "damage");
  s.addInt("broken", 1, kFieldCheckpoint, "damage");
  s.addReal("scratch", 1, kFieldNone, "solid");  // not restart state
  return sim;
}

void fill(Simulation& sim, Index n, unsigned seed) {
  ParticleStore& s = sim.store;
  s.addParticles(n);
  for (const FieldSpec& spec : s.fields()) {
    const int id = static_cast<int>(&spec - s.fields().data());
    const Index c = spec.components;
    for (Index q = 0; q < n * c; ++q) {
      if (spec.type == FieldType::Real) {
        // values that are not exact in decimal, plus extremes
        double v = std::sin(1.0 + seed + 0.37 * q + id) / 3.0;
        if (q == 0) v = std::numeric_limits<double>::denorm_min();
        if (q == 1) v = -std::numeric_limits<double>::max();
        s.data(RealField{id})[q] = v;
      } else {
        s.data(IntField{id})[q] = static_cast<std::int32_t>(seed * 1000 + 3 * q - id);
      }
    }
  }
  sim.time = 0.1 + 1.0 / 3.0;
  sim.dt = 1.0 / 7.0 * 1e-6;
  sim.step = 123456789012LL;
  sim.domain.lo = {-1.0 / 3.0, 0.0, 2.0};
  sim.domain.hi = {1.0 / 3.0, 5.5, 3.0};
  sim.domain.periodic = {true, false, true};
}

TEST(Checkpoint, RoundTripIsBitExact) {
  for (int d = 1; d <= 3; ++d) {
    SCOPED_TRACE(d);
    auto a = makeSim(d);
    fill(*a, 53, 1);
    const std::string file = path("roundtrip" + std::to_string(d) + ".h5");
    writeCheckpoint(*a, file);
    // the target has a different particle count and different values
    auto b = makeSim(d);
    fill(*b, 20, 2);
    b->store.addGhosts({0, 1, 2}, std::vector<double>(static_cast<size_t>(3 * d), 1.0));
    readCheckpoint(*b, file);
    const ParticleStore& sa = a->store;
    const ParticleStore& sb = b->store;
    ASSERT_EQ(sb.realCount(), sa.realCount());
    EXPECT_EQ(sb.ghostCount(), 0);
    for (const FieldSpec& spec : sa.fields()) {
      if (!(spec.flags & kFieldCheckpoint)) continue;
      const int id = static_cast<int>(&spec - sa.fields().data());
      const size_t bytes = static_cast<size_t>(sa.realCount() * spec.components) *
                           (spec.type == FieldType::Real ? sizeof(double) : sizeof(std::int32_t));
      const void* pa = spec.type == FieldType::Real ? static_cast<const void*>(sa.data(RealField{id}))
                                                    : static_cast<const void*>(sa.data(IntField{id}));
      const void* pb = spec.type == FieldType::Real ? static_cast<const void*>(sb.data(RealField{id}))
                                                    : static_cast<const void*>(sb.data(IntField{id}));
      EXPECT_EQ(std::memcmp(pa, pb, bytes), 0) << "field " << spec.name;
    }
    EXPECT_EQ(std::memcmp(&a->time, &b->time, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&a->dt, &b->dt, sizeof(double)), 0);
    EXPECT_EQ(b->step, a->step);
    EXPECT_EQ(b->domain.lo, a->domain.lo);
    EXPECT_EQ(b->domain.hi, a->domain.hi);
    EXPECT_EQ(b->domain.periodic, a->domain.periodic);
    // a larger target shrinks
    auto c = makeSim(d);
    fill(*c, 80, 3);
    readCheckpoint(*c, file);
    EXPECT_EQ(c->store.realCount(), 53);
  }
}

TEST(Checkpoint, EmptyStoreRoundTrip) {
  auto a = makeSim(2);
  fill(*a, 0, 1);
  const std::string file = path("empty.h5");
  writeCheckpoint(*a, file);
  auto b = makeSim(2);
  fill(*b, 7, 2);
  readCheckpoint(*b, file);
  EXPECT_EQ(b->store.realCount(), 0);
  EXPECT_EQ(b->step, a->step);
}

TEST(Checkpoint, NonCheckpointFieldsAreNotWritten) {
  auto a = makeSim(2);
  fill(*a, 5, 1);
  const std::string file = path("contents.h5");
  writeCheckpoint(*a, file);
  hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  EXPECT_GT(H5Lexists(f, "fields/stress", H5P_DEFAULT), 0);
  EXPECT_GT(H5Lexists(f, "fields/broken", H5P_DEFAULT), 0);
  EXPECT_EQ(H5Lexists(f, "fields/scratch", H5P_DEFAULT), 0);
  EXPECT_EQ(H5Lexists(f, "fields/acceleration", H5P_DEFAULT), 0);  // kFieldOutput only
  H5Fclose(f);
}

void expectInputError(Simulation& sim, const std::string& file, const std::string& needle) {
  try {
    readCheckpoint(sim, file);
    FAIL() << "expected InputError mentioning " << needle;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(file), std::string::npos) << m;
    EXPECT_NE(m.find(needle), std::string::npos) << m;
  }
}

TEST(Checkpoint, MismatchesNameTheFileAndTheField) {
  auto a = makeSim(2);
  fill(*a, 5, 1);
  const std::string file = path("mismatch.h5");
  writeCheckpoint(*a, file);
  {  // a field registered here but absent from the file
    auto b = makeSim(2);
    b->store.addReal("porosity", 1, kFieldCheckpoint, "fluid");
    expectInputError(*b, file, "'porosity'");
    EXPECT_EQ(b->store.realCount(), 0);  // untouched on error
  }
  {  // a field in the file that this simulation does not have
    auto b = makeSim(2, /*withDamage=*/false);
    expectInputError(*b, file, "'damage'");
  }
  {  // a different shape
    auto b = makeSim(2, true, 3);
    expectInputError(*b, file, "'stress'");
  }
  {  // a different type
    auto b = std::make_unique<Simulation>(2);
    b->store.addReal("stress", 4, kFieldDefault, "solid");
    b->store.addReal("damage", 1, kFieldDefault, "damage");
    b->store.addReal("broken", 1, kFieldCheckpoint, "damage");
    expectInputError(*b, file, "'broken'");
  }
  {  // a different dimension
    auto b = makeSim(3);
    expectInputError(*b, file, "dimension");
  }
  {  // not a checkpoint at all
    const std::string bogus = path("bogus.h5");
    std::ofstream(bogus) << "not hdf5";
    auto b = makeSim(2);
    expectInputError(*b, bogus, "HDF5");
    expectInputError(*b, path("does_not_exist.h5"), "HDF5");
  }
}

TEST(Checkpoint, UnwritablePathIsAnInputError) {
  auto a = makeSim(1);
  fill(*a, 2, 1);
  EXPECT_THROW(writeCheckpoint(*a, path("no_such_dir") + "/x.h5"), InputError);
}

}  // namespace

namespace {
/// A module with state outside the particle arrays (as rigid bodies and plates have).
class StatefulModule final : public Module {
 public:
  std::string name() const override { return "stateful"; }
  std::vector<std::string> materialModels() const override { return {}; }
  void configure(Simulation&, const std::vector<const Material*>&, const ParameterSet*) override {}
  ModuleState saveState() const override { return {{"orientation", q}, {"first_time", {t}}}; }
  void restoreState(const ModuleState& s) override {
    for (const auto& [name, v] : s) {
      if (name == "orientation") q = v;
      if (name == "first_time") t = v.at(0);
    }
  }
  std::vector<double> q{1.0 / 3.0, -0.25, 1e-300, 7.0};
  double t = -1.0;
};
}  // namespace

TEST(Checkpoint, ModuleStateRoundTripIsBitExact) {
  auto a = makeSim(3);
  fill(*a, 5, 1);
  auto* m = new StatefulModule();
  m->q = {0.1, std::sqrt(2.0), -1.0 / 7.0, 5e-17};
  m->t = 2.0 / 3.0;
  a->addModule(std::unique_ptr<Module>(m));
  const std::string f = path("module_state.h5");
  writeCheckpoint(*a, f);

  auto b = makeSim(3);
  fill(*b, 5, 2);
  auto* r = new StatefulModule();
  b->addModule(std::unique_ptr<Module>(r));
  ASSERT_NE(r->q, m->q);
  readCheckpoint(*b, f);
  EXPECT_EQ(r->q, m->q);
  EXPECT_EQ(r->t, m->t);
}

TEST(Checkpoint, MissingModuleStateNamesTheModule) {
  auto a = makeSim(2);
  fill(*a, 4, 1);
  const std::string f = path("no_module_state.h5");
  writeCheckpoint(*a, f);  // written without the module
  auto b = makeSim(2);
  fill(*b, 4, 2);
  b->addModule(std::make_unique<StatefulModule>());
  try {
    readCheckpoint(*b, f);
    FAIL() << "a checkpoint without the module's state was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("no_module_state.h5"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'stateful'"), std::string::npos) << msg;
  }
}
