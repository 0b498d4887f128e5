#include <gtest/gtest.h>
#include "libcore/simulation.hpp"
TEST(Smoke, StoreHasCoreFields) {
  poresph::Simulation sim(2);
  EXPECT_TRUE(sim.store.has("position"));
}
