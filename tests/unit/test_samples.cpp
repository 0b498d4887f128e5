// Every sample scene shipped in samples/ loads: its keys are valid, its materials are owned by a
// module, its particles are built and its modules initialise (fixed time steps are checked
// against the stability limits). The quick samples' behaviour is checked by the module tests
// that run the same set-ups; this guards the files themselves against drifting from the format.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "libcore/scene.hpp"

using namespace poresph;
namespace fs = std::filesystem;

TEST(Samples, EverySampleSceneLoadsAndInitialises) {
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(fs::path(PORESPH_SOURCE_DIR) / "samples"))
    if (e.path().extension() == ".yaml") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  ASSERT_GE(scenes.size(), 2u) << "samples/ should hold the shipped scenes";
  for (const auto& path : scenes) {
    SCOPED_TRACE(path.string());
    try {
      Scene scene = loadScene(path.string());
      EXPECT_GT(scene.sim->store.realCount(), 0);
      EXPECT_FALSE(scene.sim->modules.empty());
    } catch (const std::exception& e) {
      ADD_FAILURE() << path << ": " << e.what();
    }
  }
}
