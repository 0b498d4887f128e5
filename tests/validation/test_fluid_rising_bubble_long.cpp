// Validation (label `long`): rising bubble, Hysing et al. (2009) test case 1, at R/dx = 15
// (dx = 1/60, 7200 particles, ~22,000 steps, ~4 min on one thread). Scene and protocol:
// fluid_rising_bubble_case.hpp.
#include <gtest/gtest.h>

#include "tests/validation/fluid_rising_bubble_case.hpp"

TEST(FluidRisingBubble, Hysing2009Case1R15) { poresph::test::checkHysing1(15); }
