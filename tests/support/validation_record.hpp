#pragma once
// Validation records: every `validation` test writes what it measured to
// <build>/validation-records/<case>__<quantity>.json; scripts/make_validation_table.py turns
// them into docs/validation.md (the one table of accuracy and cost per capability).
#include <chrono>
#include <string>

namespace poresph::test {

struct ValidationRecord {
  std::string caseName;    ///< e.g. "poiseuille_2d"
  std::string quantity;    ///< e.g. "L2 error of u(y) at steady state"
  double measured = 0.0;
  double reference = 0.0;
  /// |measured - reference| / |reference| unless stated otherwise. Ignored (written as null) when
  /// the reference is 0 or not finite: an error relative to 0 is meaningless, and the record then
  /// carries only absolute_error = |measured - reference|, in the units of the quantity (state its
  /// scale in `quantity`, e.g. "... / p"). A reference of NaN means "no reference" (reported value).
  double relativeError = 0.0;
  std::string resolution;  ///< e.g. "40 x 20 particles, h/dx = 1.3"
  double wallSeconds = 0.0;
  std::string tolerance;   ///< what the test asserts, e.g. "< 2 %"
  std::string reference_source;  ///< e.g. "closed form (Eq. 2.94)" or "thesis Table 2.1"
};

/// Writes the record (overwrites the same case and quantity) to
/// <dir>/<case>__<quantity>.json, dir = <build>/validation-records unless given. Returns the path.
std::string recordValidation(const ValidationRecord& r, const std::string& dir = "");

/// Wall-clock stopwatch for the records.
class Stopwatch {
 public:
  Stopwatch() : t0_(std::chrono::steady_clock::now()) {}
  double seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  }
 private:
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace poresph::test
