// Validation: spurious currents of the CSF surface tension (Eqs. 5.6-5.8, 1.9) in the 2D static
// droplet at R/dx = 10, 15, 20: the capillary number Ca = mu u_max / gamma and the Laplace-jump
// error at each resolution and the observed order of Ca are printed and recorded. Asserted only
// what holds robustly: jump within 5 %, drop intact, Ca < 2e-2 at every resolution. R/dx = 30 is
// the `long` test test_fluid_spurious_currents_long.cpp. Scene and protocol:
// fluid_spurious_case.hpp.
#include <gtest/gtest.h>

#include "tests/validation/fluid_spurious_case.hpp"

TEST(FluidSpuriousCurrents, Droplet2DResolutions10To20) {
  std::vector<poresph::test::SpuriousRow> rows;
  for (int rdx : {10, 15, 20}) rows.push_back(poresph::test::runSpurious2D(rdx));
  poresph::test::checkSpuriousRows(rows, "fluid_spurious_currents_2d_order_R10_20");
}
