// Validation (label `long`): the spurious-current study of test_fluid_spurious_currents.cpp
// extended to R/dx = 30 (8100 particles, ~11 500 steps), with R/dx = 20 rerun for the order.
// Scene and protocol: fluid_spurious_case.hpp.
#include <gtest/gtest.h>

#include "tests/validation/fluid_spurious_case.hpp"

TEST(FluidSpuriousCurrents, Droplet2DResolutions20And30) {
  std::vector<poresph::test::SpuriousRow> rows;
  for (int rdx : {20, 30}) rows.push_back(poresph::test::runSpurious2D(rdx));
  poresph::test::checkSpuriousRows(rows, "fluid_spurious_currents_2d_order_R20_30");
}
