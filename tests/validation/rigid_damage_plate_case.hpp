#pragma once
// Crack-pattern measures of the plate with a rigid inclusion (issue 15 validation 5), shared by
// tests/validation/test_rigid_damage_plate.cpp (60 x 60) and test_rigid_damage_plate_long.cpp
// (150 x 150): they read PlateResult::gridCross (D on the reference lattice when the crack first
// reached both sides, damage_plate_case.hpp).
#include <algorithm>
#include <cmath>

#include "tests/validation/damage_plate_case.hpp"

namespace poresph::solid::plate {

/// The crack beside the inclusion at crossing: the damaged particles (D >= 0.5) with |X| > from
/// (the ligaments between the inclusion and the sides): their mean height Y [m] and the fraction
/// of them within `band` of the height yBand or -yBand (the inclusion's top or bottom).
struct Crack {
  double height = 1e300, inBand = 0.0;
  long count = 0;
};
inline Crack crackBeside(const PlateResult& r, double dx, double from, double yBand, double band) {
  const int n = r.gridN;
  Crack c;
  double sum = 0.0;
  long inside = 0;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const double X = (ix + 0.5) * dx - 0.15, Y = (iy + 0.5) * dx - 0.15;
      if (std::abs(X) <= from || r.gridCross[static_cast<size_t>(iy) * n + ix] < 0.5) continue;
      sum += Y;
      ++c.count;
      inside += std::min(std::abs(Y - yBand), std::abs(Y + yBand)) < band;
    }
  if (c.count > 0) {
    c.height = sum / static_cast<double>(c.count);
    c.inBand = static_cast<double>(inside) / static_cast<double>(c.count);
  }
  return c;
}

/// Overlap of two crack patterns at crossing: |A and B| / |A or B| over the lattice sites at
/// D >= 0.5 (Jaccard index; 1 = the same sites), B mirrored about y = 0 when `mirrorB` (a crack
/// below the inclusion compared with one above it).
inline double crackOverlap(const PlateResult& a, const PlateResult& b, bool mirrorB) {
  const int n = a.gridN;
  if (n == 0 || b.gridN != n) return 0.0;
  long both = 0, either = 0;
  for (int iy = 0; iy < n; ++iy)
    for (int ix = 0; ix < n; ++ix) {
      const bool A = a.gridCross[static_cast<size_t>(iy) * n + ix] >= 0.5;
      const int jy = mirrorB ? n - 1 - iy : iy;
      const bool B = b.gridCross[static_cast<size_t>(jy) * n + ix] >= 0.5;
      both += A && B;
      either += A || B;
    }
  return either > 0 ? static_cast<double>(both) / static_cast<double>(either) : 0.0;
}

}  // namespace poresph::solid::plate
