#include "tests/support/validation_record.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

namespace poresph::test {

namespace {
std::string jsonString(const std::string& s) {
  std::ostringstream o;
  o << '"';
  for (char c : s) {
    if (c == '"' || c == '\\') o << '\\' << c;
    else if (c == '\n') o << "\\n";
    else o << c;
  }
  o << '"';
  return o.str();
}
std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream o;
  o << std::setprecision(10) << v;
  return o.str();
}
std::string safeName(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return out;
}
}  // namespace

std::string recordValidation(const ValidationRecord& r, const std::string& where) {
  namespace fs = std::filesystem;
  const fs::path dir =
      where.empty() ? fs::path(PORESPH_BINARY_DIR) / "validation-records" : fs::path(where);
  fs::create_directories(dir);
  const fs::path file = dir / (safeName(r.caseName) + "__" + safeName(r.quantity) + ".json");
  // A zero (or missing) reference has no relative error: write null, keep the absolute error.
  const bool relativeMeaningful = std::isfinite(r.reference) && r.reference != 0.0;
  const double relative = relativeMeaningful ? r.relativeError : std::nan("");
  std::ofstream out(file);
  out << "{\"case\": " << jsonString(r.caseName) << ", \"quantity\": " << jsonString(r.quantity)
      << ", \"measured\": " << jsonNumber(r.measured) << ", \"reference\": " << jsonNumber(r.reference)
      << ", \"relative_error\": " << jsonNumber(relative)
      << ", \"absolute_error\": " << jsonNumber(std::abs(r.measured - r.reference))
      << ", \"resolution\": " << jsonString(r.resolution)
      << ", \"wall_seconds\": " << jsonNumber(r.wallSeconds)
      << ", \"tolerance\": " << jsonString(r.tolerance)
      << ", \"reference_source\": " << jsonString(r.reference_source) << "}\n";
  return file.string();
}

}  // namespace poresph::test
