#pragma once
// A run's timeseries.csv read back as rows of named columns (tests that compare runs by their
// drainage_* or plate columns).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace poresph::test {

struct TimeseriesTable {
  std::vector<std::map<std::string, double>> rows;
  /// Value of the last row with time <= t (NaN before the first row).
  double atOrBefore(const std::string& col, double t) const {
    double v = NAN;
    for (const auto& r : rows)
      if (r.at("time") <= t + 1e-9) v = r.at(col);
    return v;
  }
  /// Linear interpolation of a column between the output rows (NaN past the last row).
  double interpolated(const std::string& col, double t) const {
    for (size_t k = 1; k < rows.size(); ++k) {
      const double t0 = rows[k - 1].at("time"), t1 = rows[k].at("time");
      if (t <= t1 + 1e-12) {
        const double w = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 1.0;
        return (1.0 - w) * rows[k - 1].at(col) + w * rows[k].at(col);
      }
    }
    return NAN;
  }
  double max(const std::string& col) const {
    double v = -INFINITY;
    for (const auto& r : rows) v = std::max(v, r.at(col));
    return v;
  }
};

inline TimeseriesTable readTimeseries(const std::string& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) names.push_back(c);
  TimeseriesTable s;
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::map<std::string, double> row;
    size_t k = 0;
    for (std::string c; std::getline(ls, c, ',') && k < names.size(); ++k) row[names[k]] = std::stod(c);
    s.rows.push_back(row);
  }
  return s;
}

}  // namespace poresph::test
