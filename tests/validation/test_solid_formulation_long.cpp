// Long part of the formulation study of issue 13 (label validation_long, tests/long-tests.txt):
// Lame and Kirsch in 3D (slab periodic along z, 6 layers) at nu = 0.1 and 0.25, three
// resolutions each, and the 2D Kirsch at nu = 0.25. See test_solid_formulation.cpp.
#include "tests/validation/test_solid_formulation_cases.hpp"

using namespace poresph::solid::formulation_cases;

TEST(SolidFormulationLong, Lame3DConvergesAtNu010And025) {
  for (const double nu : {0.1, 0.25}) checkLame<3>(nu, {8, 11, 14});
}

TEST(SolidFormulationLong, Kirsch3DConvergesAtNu010And025) {
  for (const double nu : {0.1, 0.25}) checkKirsch<3>(nu, {3, 4, 6}, 0.08);
}

TEST(SolidFormulationLong, Kirsch2DNu025) { checkKirsch<2>(0.25, {4, 6, 8}, 0.06); }
