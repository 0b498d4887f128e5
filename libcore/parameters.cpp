#include "libcore/parameters.hpp"

#include <cmath>
#include <sstream>

namespace poresph {

namespace {
std::string formatReal(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}
std::string nodeText(const YAML::Node& n) {
  if (!n.IsDefined() || n.IsNull()) return "(empty)";
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  std::ostringstream s;
  s << YAML::Dump(n);
  std::string t = s.str();
  for (char& c : t)
    if (c == '\n') c = ' ';
  return "'" + t + "'";
}
}  // namespace

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  if (loOpen ? !(v > lo) : !(v >= lo)) return false;
  if (hiOpen ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  std::string s = loOpen ? "(" : "[";
  s += std::isinf(lo) ? "-inf" : formatReal(lo);
  s += ", ";
  s += std::isinf(hi) ? "inf" : formatReal(hi);
  s += hiOpen || std::isinf(hi) ? ")" : "]";
  return s;
}

ParameterSet::ParameterSet(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)) {
  if (!node_.IsMap()) {
    std::ostringstream m;
    m << file_ << ":" << node_.Mark().line + 1 << ": '" << path_
      << "' must be a mapping of key: value, got " << nodeText(node_);
    throw InputError(m.str());
  }
}

std::string ParameterSet::where(const std::string& key) const {
  int line = node_.Mark().line + 1;
  if (node_.IsMap() && node_[key].IsDefined()) line = node_[key].Mark().line + 1;
  const std::string full = path_.empty() ? key : path_ + "." + key;
  return file_ + ":" + std::to_string(line) + ": key '" + full + "'";
}

void ParameterSet::fail(const std::string& key, const std::string& reason) const {
  std::string value;
  if (node_.IsMap() && node_[key].IsDefined()) value = " = " + nodeText(node_[key]);
  throw InputError(where(key) + value + ": " + reason);
}

bool ParameterSet::has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined() && !node_[key].IsNull();
}

YAML::Node ParameterSet::get(const std::string& key) const {
  if (!has(key)) {
    const std::string full = path_.empty() ? key : path_ + "." + key;
    throw InputError(file_ + ":" + std::to_string(node_.Mark().line + 1) + ": required key '" +
                     full + "' is missing");
  }
  used_.insert(key);
  return node_[key];
}

YAML::Node ParameterSet::raw(const std::string& key) const { return get(key); }

double ParameterSet::real(const std::string& key, Range range) const {
  const YAML::Node n = get(key);
  double v = 0.0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) fail(key, "expected a number");
  if (!range.contains(v)) fail(key, "must lie in " + range.describe());
  return v;
}

double ParameterSet::real(const std::string& key, double fallback, Range range) const {
  if (!has(key)) {
    used_.insert(key);
    return fallback;
  }
  return real(key, range);
}

long ParameterSet::integer(const std::string& key, long lo, long hi) const {
  const YAML::Node n = get(key);
  long v = 0;
  if (!n.IsScalar() || !YAML::convert<long>::decode(n, v)) fail(key, "expected a whole number");
  if (v < lo || v > hi)
    fail(key, "must lie in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

long ParameterSet::integer(const std::string& key, long fallback, long lo, long hi) const {
  if (!has(key)) {
    used_.insert(key);
    return fallback;
  }
  return integer(key, lo, hi);
}

bool ParameterSet::boolean(const std::string& key) const {
  const YAML::Node n = get(key);
  bool v = false;
  if (!n.IsScalar() || !YAML::convert<bool>::decode(n, v)) fail(key, "expected true or false");
  return v;
}

bool ParameterSet::boolean(const std::string& key, bool fallback) const {
  if (!has(key)) {
    used_.insert(key);
    return fallback;
  }
  return boolean(key);
}

std::string ParameterSet::string(const std::string& key) const {
  const YAML::Node n = get(key);
  if (!n.IsScalar()) fail(key, "expected a text value");
  return n.Scalar();
}

std::string ParameterSet::string(const std::string& key, const std::string& fallback) const {
  if (!has(key)) {
    used_.insert(key);
    return fallback;
  }
  return string(key);
}

std::string ParameterSet::choice(const std::string& key, const std::vector<std::string>& choices) const {
  const std::string v = string(key);
  for (const auto& c : choices)
    if (c == v) return v;
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
  fail(key, "must be one of: " + list);
}

std::string ParameterSet::choice(const std::string& key, const std::string& fallback,
                                 const std::vector<std::string>& choices) const {
  if (!has(key)) {
    used_.insert(key);
    return fallback;
  }
  return choice(key, choices);
}

std::vector<double> ParameterSet::reals(const std::string& key, size_t n, Range range) const {
  const YAML::Node node = get(key);
  if (!node.IsSequence()) fail(key, "expected a list of numbers");
  if (n != 0 && node.size() != n) fail(key, "expected a list of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (const auto& e : node) {
    double v = 0.0;
    if (!e.IsScalar() || !YAML::convert<double>::decode(e, v)) fail(key, "expected a list of numbers");
    if (!range.contains(v)) fail(key, "every entry must lie in " + range.describe());
    out.push_back(v);
  }
  return out;
}

ParameterSet ParameterSet::section(const std::string& key) const {
  const YAML::Node n = get(key);
  return ParameterSet(n, file_, path_.empty() ? key : path_ + "." + key);
}

std::vector<ParameterSet> ParameterSet::sectionList(const std::string& key) const {
  const YAML::Node n = get(key);
  if (!n.IsSequence()) fail(key, "expected a list of mappings");
  std::vector<ParameterSet> out;
  const std::string base = path_.empty() ? key : path_ + "." + key;
  for (size_t k = 0; k < n.size(); ++k)
    out.emplace_back(n[k], file_, base + "[" + std::to_string(k) + "]");
  return out;
}

void ParameterSet::finish() const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (!used_.count(key)) {
      throw InputError(file_ + ":" + std::to_string(kv.first.Mark().line + 1) + ": unknown key '" +
                       (path_.empty() ? key : path_ + "." + key) + "' = " + nodeText(kv.second) +
                       " (misspelt, or not used by this model)");
    }
  }
}

}  // namespace poresph
