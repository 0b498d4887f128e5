#pragma once
// Basic types shared by every part of PoreSPH. SI units everywhere.
#include <Eigen/Core>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>

namespace poresph {

using Index = std::int64_t;

template <int D>
using Vec = Eigen::Matrix<double, D, 1>;
template <int D>
using Mat = Eigen::Matrix<double, D, D>;

/// Error raised for bad user input (scene, image, parameter). The message names the file, key and
/// value; the command line prints it and exits non-zero.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Error raised when a run becomes non-physical (NaN, Inf, blow-up).
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Calls f(std::integral_constant<int, D>) for the run-time dimension, so that hot code is
/// compiled once per dimension with no 3D cost in 1D and 2D.
template <class F>
decltype(auto) dispatchDimension(int dim, F&& f) {
  switch (dim) {
    case 1: return f(std::integral_constant<int, 1>{});
    case 2: return f(std::integral_constant<int, 2>{});
    case 3: return f(std::integral_constant<int, 3>{});
    default: throw InputError("dimension must be 1, 2 or 3, got " + std::to_string(dim));
  }
}

}  // namespace poresph
