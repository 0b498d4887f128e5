// A restart keeps the fluid pressure gradient its checkpoint ran with (issue 11 audit,
// docs/output.md "Restart and changed defaults"). The fluid's default `pressure_gradient`
// changed from symmetric (Eq. 5.2b) to volume (Eq. 5.2a) on 2026-11-27 (b84d7bb). Module
// sections enter the scene signature as written, defaults not filled in, so a checkpoint of a
// scene without the key restarted silently under the new default. The fluid now records its
// resolved form in the checkpoint (module state `setting_pressure_gradient`): a restart whose
// scene leaves the key to the default keeps the checkpoint's form, an explicit other key is
// refused, and a checkpoint written before the record warns and accepts the explicit key.
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

// Rewrites a checkpoint as the binaries before the record wrote it: no /modules/fluid group,
// and the scene signature of `legacyScene` (the scene as it was then written, without the key).
void makeLegacy(const std::string& path, const std::string& legacySignature) {
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(file, 0);
  if (H5Lexists(file, "modules/fluid", H5P_DEFAULT) > 0) H5Ldelete(file, "modules/fluid", H5P_DEFAULT);
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

}  // namespace

// A checkpoint that ran with Eq. 5.2b restarted by the same scene without the key (as a
// scene written before the switch, restarted after it): the restart keeps 5.2b, the
// accelerations are those of 5.2b, not of the new default 5.2a; an explicit other key is refused.
TEST(FluidRestart, KeepsTheCheckpointsPressureGradientWhenTheSceneUsesTheDefault) {
  const std::string ckpt = runToCheckpoint("symmetric_run", "  pressure_gradient: symmetric\n");
  ASSERT_FALSE(ckpt.empty());
  Scene same = load("same.yaml", "  pressure_gradient: symmetric\n");
  const std::vector<double> a52b = accelerationsAfterRestore(same, ckpt);
  ASSERT_GT(maxAbs(a52b), 1.0);

  // Eq. 5.2a on the same state (a copy without the record, read by a scene that sets volume):
  // the two forms differ here, so the comparison below can tell them apart.
  const std::string copy = (tmpDir() / "no_record.h5").string();
  fs::copy_file(ckpt, copy, fs::copy_options::overwrite_existing);
  Scene vol = load("vol.yaml", "  pressure_gradient: volume\n");
  makeLegacy(copy, sceneSignature(vol));
  const std::vector<double> a52a = accelerationsAfterRestore(vol, copy);
  EXPECT_GT(maxDifference(a52a, a52b), 1e-6 * maxAbs(a52b));

  // The scene without the key: its signature differs from the checkpoint's by the key only, so
  // read without the signature (as a library caller); the fluid keeps 5.2b and says so.
  Scene plain = load("plain.yaml", "");
  testing::internal::CaptureStderr();
  readCheckpoint(*plain.sim, ckpt);
  const std::string note = testing::internal::GetCapturedStderr();
  plain.sim->evaluateRates();
  const double* ap = plain.sim->store.data(plain.sim->acceleration);
  const std::vector<double> aPlain(ap, ap + plain.sim->store.realCount() * 2);
  EXPECT_LE(maxDifference(aPlain, a52b), 1e-12 * maxAbs(a52b));
  EXPECT_NE(note.find("keeps symmetric (Eq. 5.2b)"), std::string::npos) << note;

  // An explicit other key against the recorded form is refused, naming both forms.
  Scene other = load("other.yaml", "  pressure_gradient: volume\n");
  try {
    readCheckpoint(*other.sim, ckpt);
    FAIL() << "an explicit pressure_gradient: volume against a 5.2b checkpoint was accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("symmetric (Eq. 5.2b)"), std::string::npos) << msg;
    EXPECT_NE(msg.find("volume (Eq. 5.2a)"), std::string::npos) << msg;
  }
}

// A checkpoint written before the record (no /modules/fluid, the signature of the scene without
// the key, as a run started before 2026-11-27 under the then default 5.2b left it): restarted by
// that scene it warns that the form is not recorded and names the key; with the key
// `pressure_gradient: symmetric` added the restart is accepted (the key alone does not make it
// another scene) and runs 5.2b; another explicit key is still another scene.
TEST(FluidRestart, ACheckpointWithoutTheRecordWarnsAndAcceptsTheOldDefaultAsAKey) {
  const std::string ckpt = runToCheckpoint("legacy_run", "  pressure_gradient: symmetric\n");
  ASSERT_FALSE(ckpt.empty());
  Scene same = load("legacy_same.yaml", "  pressure_gradient: symmetric\n");
  const std::vector<double> a52b = accelerationsAfterRestore(same, ckpt);

  const std::string legacy = (tmpDir() / "legacy.h5").string();
  fs::copy_file(ckpt, legacy, fs::copy_options::overwrite_existing);
  Scene plain = load("legacy_plain.yaml", "");
  makeLegacy(legacy, sceneSignature(plain));

  testing::internal::CaptureStderr();
  restoreCheckpoint(plain, legacy, nullptr);
  const std::string warning = testing::internal::GetCapturedStderr();
  EXPECT_NE(warning.find("does not record the fluid's pressure_gradient"), std::string::npos) << warning;
  EXPECT_NE(warning.find("'pressure_gradient: symmetric'"), std::string::npos) << warning;

  Scene withKey = load("legacy_key.yaml", "  pressure_gradient: symmetric\n");
  testing::internal::CaptureStderr();
  const std::vector<double> aKey = accelerationsAfterRestore(withKey, legacy);
  EXPECT_EQ(testing::internal::GetCapturedStderr().find("warning"), std::string::npos);
  EXPECT_LE(maxDifference(aKey, a52b), 1e-12 * maxAbs(a52b));

  Scene hu = load("legacy_hu.yaml", "  pressure_gradient: hu_adams\n");
  EXPECT_THROW(restoreCheckpoint(hu, legacy, nullptr), InputError);
}
