#pragma once
// The simulation box: bounds and periodicity per axis.
#include <array>

#include "libcore/types.hpp"

namespace poresph {

struct Domain {
  int dimension = 3;
  std::array<double, 3> lo{0.0, 0.0, 0.0};
  std::array<double, 3> hi{1.0, 1.0, 1.0};
  std::array<bool, 3> periodic{false, false, false};

  double length(int axis) const { return hi[static_cast<size_t>(axis)] - lo[static_cast<size_t>(axis)]; }
  bool anyPeriodic() const {
    for (int a = 0; a < dimension; ++a)
      if (periodic[static_cast<size_t>(a)]) return true;
    return false;
  }
};

}  // namespace poresph
