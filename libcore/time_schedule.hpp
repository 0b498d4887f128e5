#pragma once
// Time factors of loads and body forces, written once for every module.
//
//   linearRamp(t, T) = min(1, max(0, t / T))   (1 when T <= 0)
// is the `ramp_time` of the solid's boundary loads (Eq. 4.31's u_d ramped), the rigid plates'
// load and the drainage reservoir's body force; linearRampRate is its derivative.
//
// TimeSchedule is a factor f(t) given by a table of points (t_k, f_k): linear between the points
// (or `exponential`: ln f linear, i.e. f_k (f_k+1 / f_k)^s with s = linearRamp(t - t_k, t_k+1 -
// t_k), the same relative rate d ln f / dt along a segment), f_0 before the first point and the
// last f after the last. The fluid's `gravity_schedule` (docs/fluid.md "Ramped gravity") reads
// one from a scene:
//   gravity_schedule: {times: [0, 0.03, 0.43], factors: [0.133, 0.133, 1], interpolation: exponential}
// The linear ramp of `ramp_time` T is the table {times: [0, T], factors: [0, 1]}.
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "libcore/parameters.hpp"

namespace poresph {

/// min(1, max(0, t / rampTime)); 1 when rampTime <= 0 (applied at once).
inline double linearRamp(double t, double rampTime) {
  if (!(rampTime > 0.0)) return 1.0;
  return std::min(1.0, std::max(0.0, t / rampTime));
}
/// d linearRamp / dt: 1 / rampTime during the ramp [0, rampTime), 0 otherwise.
inline double linearRampRate(double t, double rampTime) {
  if (!(rampTime > 0.0)) return 0.0;
  return (t >= 0.0 && t < rampTime) ? 1.0 / rampTime : 0.0;
}

class TimeSchedule {
 public:
  enum class Interpolation { Linear, Exponential };

  /// No table: the factor is 1 at all times.
  TimeSchedule() = default;
  /// Throws std::invalid_argument (the reason, naming the offending entry) unless the table is
  /// valid: one or more points, as many factors as times, finite values, times >= 0 and strictly
  /// increasing, and for `Exponential` factors > 0.
  TimeSchedule(std::vector<double> times, std::vector<double> factors,
               Interpolation interpolation = Interpolation::Linear)
      : times_(std::move(times)), factors_(std::move(factors)), interpolation_(interpolation) {
    const std::string why = check(times_, factors_, interpolation_);
    if (!why.empty()) throw std::invalid_argument(why);
  }

  /// Reads {times: [...], factors: [...], interpolation: linear | exponential} (interpolation
  /// optional, linear); refuses an invalid table with an InputError naming file, line, key and
  /// value (ParameterSet::fail) and unknown keys (finish()).
  static TimeSchedule read(const ParameterSet& s) {
    const std::vector<double> t = s.reals("times");
    const std::vector<double> f = s.reals("factors");
    const Interpolation interp =
        s.choice("interpolation", "linear", {"linear", "exponential"}) == "exponential"
            ? Interpolation::Exponential
            : Interpolation::Linear;
    s.finish();
    if (t.size() != f.size())
      s.fail("factors", "needs one factor per entry of 'times' (" + std::to_string(t.size()) +
                            " times, " + std::to_string(f.size()) + " factors)");
    const std::string why = check(t, f, interp);
    if (!why.empty()) s.fail(why.rfind("factor", 0) == 0 ? "factors" : "times", why);
    return TimeSchedule(t, f, interp);
  }

  /// True without a table (the factor is 1 at all times).
  bool constant() const { return times_.empty(); }
  /// The factor at time t.
  double factor(double t) const {
    if (times_.empty()) return 1.0;
    if (!(t > times_.front())) return factors_.front();
    if (t >= times_.back()) return factors_.back();
    const size_t k = static_cast<size_t>(
        std::upper_bound(times_.begin(), times_.end(), t) - times_.begin() - 1);
    const double s = linearRamp(t - times_[k], times_[k + 1] - times_[k]);
    const double f0 = factors_[k], f1 = factors_[k + 1];
    if (interpolation_ == Interpolation::Exponential) return f0 * std::pow(f1 / f0, s);
    return f0 + (f1 - f0) * s;
  }
  /// The largest |factor| the schedule reaches (1 without a table): the interpolation never
  /// leaves the range of its points.
  double largestFactor() const {
    double m = times_.empty() ? 1.0 : 0.0;
    for (double f : factors_) m = std::max(m, std::abs(f));
    return m;
  }
  const std::vector<double>& times() const { return times_; }
  const std::vector<double>& factors() const { return factors_; }
  Interpolation interpolation() const { return interpolation_; }
  /// One line for reports: "linear over (0 s, 0), (0.1 s, 1)".
  std::string describe() const {
    if (times_.empty()) return "constant";
    std::ostringstream o;
    o.precision(6);
    o << (interpolation_ == Interpolation::Exponential ? "exponential" : "linear") << " over";
    for (size_t k = 0; k < times_.size(); ++k)
      o << (k ? ", (" : " (") << times_[k] << " s, " << factors_[k] << ")";
    return o.str();
  }

 private:
  /// "" for a valid table, else the reason (starting with "factor" when about the factors).
  static std::string check(const std::vector<double>& t, const std::vector<double>& f,
                           Interpolation interp) {
    if (t.empty()) return "times: needs at least one point";
    if (t.size() != f.size())
      return "factors: one per time needed (" + std::to_string(t.size()) + " times, " +
             std::to_string(f.size()) + " factors)";
    for (size_t k = 0; k < t.size(); ++k) {
      std::ostringstream v;
      v.precision(10);
      if (!std::isfinite(t[k])) {
        v << "times[" << k << "] = " << t[k] << " is not a finite number";
        return v.str();
      }
      if (t[k] < 0.0) {
        v << "times[" << k << "] = " << t[k] << " s is negative (the run starts at t = 0)";
        return v.str();
      }
      if (k > 0 && !(t[k] > t[k - 1])) {
        v << "times must increase strictly: times[" << k << "] = " << t[k] << " s after times["
          << k - 1 << "] = " << t[k - 1] << " s";
        return v.str();
      }
      if (!std::isfinite(f[k])) {
        v << "factors[" << k << "] = " << f[k] << " is not a finite number";
        return v.str();
      }
      if (interp == Interpolation::Exponential && !(f[k] > 0.0)) {
        v << "factors[" << k << "] = " << f[k]
          << " must be > 0 with interpolation: exponential (ln f is interpolated)";
        return v.str();
      }
    }
    return "";
  }

  std::vector<double> times_, factors_;
  Interpolation interpolation_ = Interpolation::Linear;
};

}  // namespace poresph
