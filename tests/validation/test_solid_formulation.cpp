// Issue 13, first part: the formulation that carries damage is the total-Lagrangian SVK form with
// corrected reference gradients (docs/solid.md, "Which formulation carries damage"). Its
// convergence on the two elastic stress problems the damage cases rest on, at the Poisson ratios
// of the thesis (nu = 0.1, COx, Table 5.1; nu = 0.25, Table 4.2), in 2D plane strain and in 3D
// (a slab periodic along z: plane strain computed with the 3D kernel, families and law):
//  - Lame (thick-walled cylinder a = 10 mm, b = 20 mm, internal pressure p): max error of the
//    radial and hoop stress over 8 radial bins (/ p) and the bore displacement u_r(a + dx/2),
//  - Kirsch (hole radius a in a plate W = 8 a pulled by sigma0): K_t from the first three rings
//    extrapolated to r = a.
// Body-fitted rings around the curved surfaces (solid_scenes.hpp appendRings, as in
// test_solid_lame / test_solid_kirsch); quarter models with symmetry mirrors; dynamic relaxation
// with damping. Each case at three resolutions: the error is asserted at the finest one AND the
// observed order between the coarsest and the finest must stay above a floor set from the
// measurement (it fails if convergence is lost). 3D and the 2D Kirsch at nu = 0.25 are in
// test_solid_formulation_long.cpp (label validation_long, about 10 min on a loaded core); this
// file runs the 2D Lame at both ratios and the 2D Kirsch at nu = 0.1 (about 15 s on one core).
#include "tests/validation/test_solid_formulation_cases.hpp"

using namespace poresph::solid::formulation_cases;

TEST(SolidFormulation, Lame2DConvergesAtNu010And025) {
  for (const double nu : {0.1, 0.25}) checkLame<2>(nu, {10, 14, 20});
}

TEST(SolidFormulation, Kirsch2DConvergesAtNu010) { checkKirsch<2>(0.1, {4, 6, 8}, 0.05); }
