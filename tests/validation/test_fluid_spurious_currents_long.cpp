// Validation (label `validation_long`): the spurious-current study of
// test_fluid_spurious_currents.cpp extended to R/dx = 30 (8100 particles, ~11 500 steps), with
// R/dx = 20 rerun for the order; and the same with h/dx growing as sqrt(R/dx / 10) (h/dx = 1,
// 1.414, 1.732 at R/dx = 10, 20, 30: h ~ dx^(1/2), the neighbour count grows), where the
// spurious currents do converge (measured Ca 1.16e-2, 5.5e-3, 3.0e-3). Asserted there: Ca at
// R/dx = 30 below half of that at 10 (measured 0.26). Scene and protocol:
// fluid_spurious_case.hpp.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/validation/fluid_spurious_case.hpp"

TEST(FluidSpuriousCurrents, Droplet2DResolutions20And30) {
  std::vector<poresph::test::SpuriousRow> rows;
  for (int rdx : {20, 30}) rows.push_back(poresph::test::runSpurious2D(rdx));
  poresph::test::checkSpuriousRows(rows, "fluid_spurious_currents_2d_order_R20_30");
}

TEST(FluidSpuriousCurrents, Droplet2DGrowingNeighbourCount) {
  std::vector<poresph::test::SpuriousRow> rows;
  rows.push_back(poresph::test::runSpurious2D(10, 1.0));
  rows.push_back(poresph::test::runSpurious2D(20, std::sqrt(2.0)));
  rows.push_back(poresph::test::runSpurious2D(30, std::sqrt(3.0)));
  poresph::test::checkSpuriousRows(rows, "fluid_spurious_currents_2d_order_h_sqrt_dx");
  EXPECT_LT(rows.back().caMean, 0.5 * rows.front().caMean);
}

// Convergence to R/dx = 40 at h = dx (issue 14): asserted, and FAILING on the present code
// (measured on a loaded machine, 321 s CPU for R/dx 40: Ca 4.38e-3 -> 4.21e-3 from R/dx 20 to
// 40, i.e. no convergence; the jump error grows from 1.03 % to 5.57 %). Kept as the statement of
// what has to hold: Ca must fall by 20 % per doubling of R/dx and the jump stay within 2 %.
TEST(FluidSpuriousCurrents, Droplet2DResolution40Converges) {
  std::vector<poresph::test::SpuriousRow> rows;
  for (int rdx : {20, 40}) rows.push_back(poresph::test::runSpurious2D(rdx));
  poresph::test::checkSpuriousRows(rows, "fluid_spurious_currents_2d_order_R20_40");
  EXPECT_LT(rows[1].caMean, 0.8 * rows[0].caMean);
  for (const auto& r : rows) EXPECT_LT(r.err, 0.02) << "R/dx = " << r.rdx;
}
