// A restart keeps the settings its checkpoint ran with (issue 11, docs/output.md "Restart and
// changed defaults"). Every module lists its resolved settings (Module::settings: the values
// after the defaults were applied); the runner records them in the checkpoint (/settings) and
// compares them on restart key by key, naming each difference with both values. The fluid's
// default `pressure_gradient` changed from symmetric (Eq. 5.2b) to volume (Eq. 5.2a) on
// 2026-11-27 (b84d7bb): such a change of a default is found by the recorded value, not by the
// scene text. A checkpoint written before the record warns and accepts the old default as a key.
#include <gtest/gtest.h>

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "libcore/checkpoint.hpp"
#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "libcore/simulation.hpp"

namespace fs = std::filesystem;
using namespace poresph;

namespace {

fs::path tmpDir() {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_fluid_restart_settings";
  fs::create_directories(d);
  return d;
}

// A 2D water column (10 x 20 particles) collapsing in a 20 x 20 walled box: after 4 ms its
// density varies enough for Eqs. 5.2a and 5.2b to give different accelerations. `fluidKey` is
// an extra line of the fluid section ("" : the default).
Scene load(const std::string& name, const std::string& fluidKey, double endTime = 0.01) {
  std::ostringstream s;
  s << R"(dimension: 2
domain: {lo: [-0.003, -0.003], hi: [0.023, 0.023]}
spacing: 0.001
kernel: wendland_c2
end_time: )" << endTime << R"(
time_step: {adaptive: true}
output: {every_time: 1.0}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 5, viscosity: 1.0e-3}
  - {name: steel, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.003, -0.003], hi: [0.023, 0.023], material: steel}
  - {shape: box, lo: [0.0, 0.0], hi: [0.02, 0.02], material: none}
  - {shape: box, lo: [0.0, 0.0], hi: [0.01, 0.02], material: water}
fluid:
  gravity: [0, -9.81]
)" << fluidKey;
  const fs::path p = tmpDir() / name;
  std::ofstream(p) << s.str();
  return loadScene(p.string());
}

// The checkpoint of the column run to 4 ms with the fluid line `fluidKey`.
std::string runToCheckpoint(const std::string& name, const std::string& fluidKey) {
  Scene s = load(name + ".yaml", fluidKey, 0.004);
  RunOptions o;
  o.outDir = (tmpDir() / name).string();
  fs::remove_all(o.outDir);
  o.handleSignals = false;
  const RunResult r = runScene(s, o);
  EXPECT_EQ(r.status, RunStatus::Finished);
  EXPECT_GT(r.steps, 20);
  return r.checkpoint;
}

// The accelerations after restoring `checkpoint` into `scene` (signature checked) and
// evaluating the rates.
std::vector<double> accelerationsAfterRestore(Scene& scene, const std::string& checkpoint) {
  restoreCheckpoint(scene, checkpoint, nullptr);
  Simulation& sim = *scene.sim;
  sim.evaluateRates();
  const double* a = sim.store.data(sim.acceleration);
  return std::vector<double>(a, a + sim.store.realCount() * sim.dimension());
}

double maxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  EXPECT_EQ(a.size(), b.size());
  double d = 0.0;
  for (size_t k = 0; k < std::min(a.size(), b.size()); ++k) d = std::max(d, std::abs(a[k] - b[k]));
  return d;
}

double maxAbs(const std::vector<double>& a) {
  double m = 0.0;
  for (double v : a) m = std::max(m, std::abs(v));
  return m;
}

// Rewrites a checkpoint as the binaries before the record wrote it: no /settings group (nor the
// interim /modules/fluid), and the signature of the whole scene text (legacySceneSignature).
void makeLegacy(const std::string& path, const std::string& legacySignature) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  if (H5Lexists(file, "modules", H5P_DEFAULT) > 0 &&
      H5Lexists(file, "modules/fluid", H5P_DEFAULT) > 0)
    H5Ldelete(file, "modules/fluid", H5P_DEFAULT);
  if (H5Lexists(file, "settings", H5P_DEFAULT) > 0) H5Ldelete(file, "settings", H5P_DEFAULT);
  H5Adelete(file, "scene_signature");
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, legacySignature.size());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(file, "scene_signature", type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, legacySignature.data());
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  H5Fclose(file);
}

// Overwrites the recorded setting `key` of a checkpoint with `value`: the record a binary with
// another default would have written for the same scene.
void editRecordedSetting(const std::string& path, const std::string& key, const std::string& value) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  const hid_t group = H5Gopen2(file, "settings", H5P_DEFAULT);
  ASSERT_GE(group, 0);
  ASSERT_GT(H5Aexists(group, key.c_str()), 0) << key;
  H5Adelete(group, key.c_str());
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = H5Acreate2(group, key.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(attr, type, value.c_str());
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
  H5Gclose(group);
  H5Fclose(file);
}

std::string recorded(const CheckpointRecord& r, const std::string& key) {
  for (const auto& [k, v] : r.settings)
    if (k == key) return v;
  return "(absent)";
}

// The message of the InputError restoreCheckpoint throws ("" if it accepts the checkpoint).
std::string refusal(Scene& scene, const std::string& checkpoint) {
  try {
    restoreCheckpoint(scene, checkpoint, nullptr);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The checkpoint records the run's resolved settings: the scene-wide kernel choices and the
// fluid's, those the scene leaves out with their defaults.
TEST(FluidRestart, TheCheckpointRecordsTheResolvedSettings) {
  const std::string ckpt = runToCheckpoint("record_run", "");
  ASSERT_FALSE(ckpt.empty());
  const CheckpointRecord r = readCheckpointRecord(ckpt);
  ASSERT_TRUE(r.hasSettings);
  EXPECT_EQ(recorded(r, "fluid.pressure_gradient"), "volume");  // the default since 2026-11-27
  EXPECT_EQ(recorded(r, "fluid.wall_pressure"), "extrapolated");
  EXPECT_EQ(recorded(r, "fluid.density"), "continuity");
  EXPECT_EQ(recorded(r, "kernel"), "wendland_c2");
  Scene same = load("record_same.yaml", "");
  const std::string integrator = same.resolved["integrator"].Scalar();
  EXPECT_EQ(recorded(r, "integrator"), integrator);
  EXPECT_EQ(r.signature, sceneSignature(same));
}

// A restart whose scene sets another value is refused, naming the setting and both values; the
// scene that leaves the key to a default other than the recorded value likewise, with the key to
// add; the key added at the recorded value is the same run (the signature leaves the recorded
// keys out), and continues with the recorded form (Eq. 5.2b's accelerations, not 5.2a's).
TEST(FluidRestart, AChangedSettingIsRefusedNamingTheSettingAndBothValues) {
  const std::string ckpt = runToCheckpoint("symmetric_run", "  pressure_gradient: symmetric\n");
  ASSERT_FALSE(ckpt.empty());
  Scene same = load("same.yaml", "  pressure_gradient: symmetric\n");
  const std::vector<double> a52b = accelerationsAfterRestore(same, ckpt);
  ASSERT_GT(maxAbs(a52b), 1.0);

  Scene other = load("other.yaml", "  pressure_gradient: volume\n");
  const std::string msg = refusal(other, ckpt);
  EXPECT_NE(msg.find("fluid.pressure_gradient: checkpoint symmetric, scene volume"),
            std::string::npos) << msg;
  EXPECT_EQ(msg.find("scene signature"), std::string::npos) << msg;

  Scene plain = load("plain.yaml", "");
  const std::string msgDefault = refusal(plain, ckpt);
  EXPECT_NE(msgDefault.find("fluid.pressure_gradient: checkpoint symmetric, scene volume (the default"),
            std::string::npos) << msgDefault;
  EXPECT_NE(msgDefault.find("add 'pressure_gradient: symmetric' to its fluid section"),
            std::string::npos) << msgDefault;

  // Two settings changed: both named.
  Scene two = load("two.yaml", "  pressure_gradient: hu_adams\n  wall_pressure: light_mirror\n");
  const std::string msgTwo = refusal(two, ckpt);
  EXPECT_NE(msgTwo.find("2 settings differ"), std::string::npos) << msgTwo;
  EXPECT_NE(msgTwo.find("fluid.pressure_gradient: checkpoint symmetric, scene hu_adams"),
            std::string::npos) << msgTwo;
  EXPECT_NE(msgTwo.find("fluid.wall_pressure: checkpoint extrapolated, scene light_mirror"),
            std::string::npos) << msgTwo;

  // Eq. 5.2a on the same state (the legacy copy, read by a scene that sets volume): the two
  // forms differ here, so the comparison above can tell them apart.
  const std::string copy = (tmpDir() / "no_record.h5").string();
  fs::copy_file(ckpt, copy, fs::copy_options::overwrite_existing);
  Scene vol = load("vol.yaml", "  pressure_gradient: volume\n");
  makeLegacy(copy, legacySceneSignature(vol));
  const std::vector<double> a52a = accelerationsAfterRestore(vol, copy);
  EXPECT_GT(maxDifference(a52a, a52b), 1e-6 * maxAbs(a52b));
}

// Only a default changed between the binary that wrote the checkpoint and this one (simulated by
// editing the recorded value of a checkpoint of the unchanged scene): the restart is refused by
// the setting, although the scene text and its signature are the same; the key added at the
// recorded value restarts it.
TEST(FluidRestart, AChangedDefaultIsDetectedByTheRecordedSetting) {
  const std::string ckpt = runToCheckpoint("default_run", "");
  ASSERT_FALSE(ckpt.empty());
  {
    Scene plain = load("default_plain.yaml", "");
    EXPECT_EQ(refusal(plain, ckpt), "");  // unchanged: accepted
  }
  const std::string old = (tmpDir() / "old_default.h5").string();
  fs::copy_file(ckpt, old, fs::copy_options::overwrite_existing);
  editRecordedSetting(old, "fluid.pressure_gradient", "symmetric");
  Scene plain = load("default_plain2.yaml", "");
  ASSERT_EQ(readCheckpointRecord(old).signature, sceneSignature(plain));
  const std::string msg = refusal(plain, old);
  EXPECT_NE(msg.find("1 setting differs"), std::string::npos) << msg;
  EXPECT_NE(msg.find("fluid.pressure_gradient: checkpoint symmetric, scene volume (the default"),
            std::string::npos) << msg;

  Scene pinned = load("default_pinned.yaml", "  pressure_gradient: symmetric\n");
  EXPECT_EQ(refusal(pinned, old), "");

  // A scene-wide choice the same way (the kernel's name is resolved by the scene).
  const std::string otherKernel = (tmpDir() / "old_kernel.h5").string();
  fs::copy_file(ckpt, otherKernel, fs::copy_options::overwrite_existing);
  editRecordedSetting(otherKernel, "kernel", "cubic_spline");
  Scene again = load("default_again.yaml", "");
  const std::string msgKernel = refusal(again, otherKernel);
  EXPECT_NE(msgKernel.find("kernel: checkpoint cubic_spline, scene wendland_c2"), std::string::npos)
      << msgKernel;
}

// A checkpoint written before the record (no /settings, the signature of the whole scene text,
// as a run started before 2026-11-27 under the then default 5.2b left it): restarted by that
// scene it warns that the form is not recorded and names the key; with the key
// `pressure_gradient: symmetric` added the restart is accepted (the key at its former default
// does not make it another scene) and runs 5.2b; another explicit key is still another scene.
TEST(FluidRestart, ACheckpointWithoutTheRecordWarnsAndAcceptsTheOldDefaultAsAKey) {
  const std::string ckpt = runToCheckpoint("legacy_run", "  pressure_gradient: symmetric\n");
  ASSERT_FALSE(ckpt.empty());
  Scene same = load("legacy_same.yaml", "  pressure_gradient: symmetric\n");
  const std::vector<double> a52b = accelerationsAfterRestore(same, ckpt);

  const std::string legacy = (tmpDir() / "legacy.h5").string();
  fs::copy_file(ckpt, legacy, fs::copy_options::overwrite_existing);
  Scene plain = load("legacy_plain.yaml", "");
  makeLegacy(legacy, legacySceneSignature(plain));
  EXPECT_FALSE(readCheckpointRecord(legacy).hasSettings);

  testing::internal::CaptureStderr();
  restoreCheckpoint(plain, legacy, nullptr);
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("does not record the fluid's pressure_gradient"), std::string::npos) << warning;
  EXPECT_NE(warning.find("'pressure_gradient: symmetric'"), std::string::npos) << warning;
  // `poresph run --restart` restores twice (the early check before --out is touched, then the
  // run's own restore): the early one is silent, so each warning is printed once.
  Scene plainEarly = load("legacy_plain_early.yaml", "");
  testing::internal::CaptureStderr();
  restoreCheckpoint(plainEarly, legacy, nullptr, /*printWarnings=*/false);
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");

  Scene withKey = load("legacy_key.yaml", "  pressure_gradient: symmetric\n");
  testing::internal::CaptureStderr();
  const std::vector<double> aKey = accelerationsAfterRestore(withKey, legacy);
  // (other settings whose default changed since may still warn; this one is pinned)
  const std::string pinnedNote = testing::internal::GetCapturedStderr();
  EXPECT_EQ(pinnedNote.find("pressure_gradient"), std::string::npos) << pinnedNote;
  EXPECT_LE(maxDifference(aKey, a52b), 1e-12 * maxAbs(a52b));

  Scene hu = load("legacy_hu.yaml", "  pressure_gradient: hu_adams\n");
  EXPECT_THROW(restoreCheckpoint(hu, legacy, nullptr), InputError);
  // A key at the current default is not the former one: another scene for this checkpoint.
  Scene vol = load("legacy_vol.yaml", "  pressure_gradient: volume\n");
  EXPECT_NE(refusal(vol, legacy).find("scene signature"), std::string::npos);
}

// The solid lists its materials' formulation, plane and damage choices by material name.
TEST(FluidRestart, TheSolidListsItsMaterialsSettings) {
  const fs::path p = tmpDir() / "solid.yaml";
  std::ofstream(p) << R"(dimension: 2
domain: {lo: [-0.002, -0.002], hi: [0.010, 0.010]}
spacing: 1.0e-3
end_time: 1.0e-3
time_step: {adaptive: true}
output: {every_time: 1.0}
materials:
  - name: clay
    model: elastic
    density: 2000
    young_modulus: 1.2e5
    poisson_ratio: 0.1
    damage: {law: rankine_mohr_coulomb, tensile_strain_onset: 0.002, tensile_strain_ultimate: 0.004, compressive_strain_onset: 0.015, friction_angle: 25, tensile_measure: stress}
geometry:
  - {shape: box, lo: [0.0, 0.0], hi: [0.008, 0.008], material: clay}
)";
  Scene scene = loadScene(p.string());
  const ModuleSettings st = sceneSettings(scene);
  auto value = [&](const std::string& key) {
    for (const ModuleSetting& s : st)
      if (s.key == key) return s.value;
    return std::string("(absent)");
  };
  EXPECT_EQ(value("materials.clay.formulation"), "total_lagrangian");
  EXPECT_EQ(value("materials.clay.plane"), "strain");
  EXPECT_EQ(value("materials.clay.damage.law"), "rankine_mohr_coulomb");
  EXPECT_EQ(value("materials.clay.damage.split"), "volumetric");
  EXPECT_EQ(value("materials.clay.damage.tensile_measure"), "stress");
  EXPECT_EQ(value("solid.damage_commit"), "step_end");
  // The signature leaves the recorded keys out: the damage section written without its default
  // split and with it (the same resolved value) is the same scene.
  std::ifstream in(p);
  std::stringstream text;
  text << in.rdbuf();
  std::string withSplit = text.str();
  const std::string at = "tensile_measure: stress}";
  withSplit.replace(withSplit.find(at), at.size(), "tensile_measure: stress, split: volumetric}");
  const fs::path q = tmpDir() / "solid_split.yaml";
  std::ofstream(q) << withSplit;
  Scene split = loadScene(q.string());
  EXPECT_EQ(sceneSignature(split), sceneSignature(scene));
  EXPECT_NE(legacySceneSignature(split), legacySceneSignature(scene));
}
