// Validation: rising bubble, Hysing et al. (2009) test case 1, at R/dx = 10 (dx = 1/40).
// Scene, protocol and reference values: fluid_rising_bubble_case.hpp; R/dx = 15 in the `long`
// test test_fluid_rising_bubble_long.cpp.
#include <gtest/gtest.h>

#include "tests/validation/fluid_rising_bubble_case.hpp"

TEST(FluidRisingBubble, Hysing2009Case1) { poresph::test::checkHysing1(10); }
