// fluid.wall_push_only (docs/fluid.md "The fix: wall_push_only") needs the full neighbour list:
// a scene with `neighbour_list: half` is refused when it is loaded (the fluid module then does not
// support the half list), naming the file, the key and the way out; with the full list the same
// scene runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;

namespace {

std::string boxScene(const std::string& list) {
  return R"(dimension: 2
domain: {lo: [-0.003, -0.003], hi: [0.013, 0.013]}
spacing: 0.001
kernel: wendland_c2
end_time: 1.0
max_steps: 3
time_step: {adaptive: true}
output: {every_steps: 100}
neighbour_list: )" + list + R"(
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 1.0e-3, background_pressure: 100}
  - {name: wall, model: wall, density: 1000}
geometry:
  - {shape: box, lo: [-0.003, -0.003], hi: [0.013, 0.013], material: wall}
  - {shape: box, lo: [0, 0], hi: [0.01, 0.01], material: water}
fluid: {pressure_reference: background, wall_push_only: true}
)";
}

RunResult run(const std::string& list, std::string* error) {
  const std::string dir =
      (std::filesystem::path(PORESPH_BINARY_DIR) / ("test-wall-push-only-" + list)).string();
  std::filesystem::remove_all(dir);
  RunOptions o;
  o.outDir = dir;
  o.handleSignals = false;
  try {
    Scene s = loadSceneText(boxScene(list), "wall_push_only.yaml");
    return runScene(s, o);
  } catch (const InputError& e) {
    *error = e.what();
  }
  return {};
}

}  // namespace

TEST(FluidWallPushOnly, HalfNeighbourListRefusedWhenTheSceneLoads) {
  std::string error;
  run("half", &error);
  EXPECT_NE(error.find("wall_push_only.yaml"), std::string::npos) << error;
  EXPECT_NE(error.find("key 'neighbour_list'"), std::string::npos) << error;
  EXPECT_NE(error.find("module 'fluid'"), std::string::npos) << error;
  EXPECT_NE(error.find("neighbour_list: full or auto"), std::string::npos) << error;
  // Without the key the fluid of this scene takes the half list.
  {
    std::string text = boxScene("half");
    text.replace(text.find(", wall_push_only: true"), 22, "");
    RunOptions o;
    o.outDir = (std::filesystem::path(PORESPH_BINARY_DIR) / "test-wall-push-only-off").string();
    std::filesystem::remove_all(o.outDir);
    o.handleSignals = false;
    Scene s = loadSceneText(text, "no_key.yaml");
    EXPECT_EQ(runScene(s, o).steps, 3);
  }
  std::string none;
  const RunResult full = run("full", &none);
  EXPECT_EQ(none, "");
  EXPECT_EQ(full.status, RunStatus::Finished);
  EXPECT_EQ(full.steps, 3);
}
