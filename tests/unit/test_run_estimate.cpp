// `poresph info`'s run-time estimate (libcore/runner.hpp estimateRun / describeEstimate): each
// module's stable step, the step taken now, and the projection of a few timed steps to end_time.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"

using namespace poresph;

namespace {
std::string sample(const std::string& name) {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/" + name);
  std::stringstream buf;
  buf << in.rdbuf();
  return buf.str();
}
}  // namespace

TEST(RunEstimate, ProjectsTheTimedStepsToTheEnd) {
  // Fixed step: the projection is exact in steps (end_time / dt), whatever the machine's speed.
  std::string text = sample("fluid_oscillating_droplet.yaml");
  const size_t t = text.find("time_step: {adaptive: true, cfl: 1.0}");
  ASSERT_NE(t, std::string::npos);
  text.replace(t, 37, "time_step: {adaptive: false, dt: 1.0e-5}");
  Scene scene = loadSceneText(text, "estimate.yaml");
  const RunEstimate e = estimateRun(scene, 4, 60.0);
  EXPECT_TRUE(e.failure.empty()) << e.failure;
  EXPECT_EQ(e.stepsTimed, 4);
  EXPECT_EQ(scene.sim->step, 5);  // one untimed priming step, then the timed ones
  EXPECT_DOUBLE_EQ(e.dt, 1e-5);
  EXPECT_NEAR(e.stepsToEnd, scene.endTime / 1e-5, 1e-6 * scene.endTime / 1e-5);
  EXPECT_GT(e.secondsPerStep, 0.0);
  EXPECT_NEAR(e.secondsToEnd, e.stepsToEnd * e.secondsPerStep, 1e-9 * e.secondsToEnd);
  ASSERT_FALSE(e.moduleLimits.empty());
  EXPECT_EQ(e.moduleLimits[0].first, "fluid");
  EXPECT_GT(e.moduleLimits[0].second, 0.0);
  const std::string text2 = describeEstimate(scene, e);
  EXPECT_NE(text2.find("stable steps: fluid"), std::string::npos) << text2;
  EXPECT_NE(text2.find("run time:"), std::string::npos) << text2;
}

TEST(RunEstimate, AdaptiveStepUsesTheSmallestModuleLimit) {
  Scene scene = loadSceneText(sample("drainage_two_pores_2d.yaml"), "two.yaml");
  const RunEstimate e = estimateRun(scene, 2, 60.0);
  EXPECT_TRUE(e.failure.empty()) << e.failure;
  double smallest = e.cflLimit;
  for (const auto& [name, limit] : e.moduleLimits) smallest = std::min(smallest, limit);
  EXPECT_NEAR(e.dt, scene.timeStep.cfl * smallest, 1e-12 * smallest);
  bool solid = false;
  for (const auto& [name, limit] : e.moduleLimits) solid = solid || name == "solid";
  EXPECT_TRUE(solid);
}

TEST(RunEstimate, NoStepsTimedWhenAskedForNone) {
  Scene scene = loadSceneText(sample("fluid_oscillating_droplet.yaml"), "none.yaml");
  const RunEstimate e = estimateRun(scene, 0, 60.0);
  EXPECT_EQ(e.stepsTimed, 0);
  EXPECT_EQ(scene.sim->step, 0);
  EXPECT_EQ(describeEstimate(scene, e).find("run time:"), std::string::npos);
}
