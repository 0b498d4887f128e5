#include "libcore/parameters.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
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
std::string keyText(const YAML::Node& k) {
  if (k.IsScalar()) return k.Scalar();
  std::ostringstream s;
  s << YAML::Dump(k);
  return s.str();
}

void checkDuplicates(const YAML::Node& node, const std::string& file, const std::string& path,
                     long& budget) {
  if (--budget < 0)
    throw InputError(file + ": the scene expands to more than a million YAML nodes (nested "
                            "aliases?); a scene is a small text file");
  if (node.IsMap()) {
    std::map<std::string, int> lineOf;
    for (const auto& kv : node) {
      const std::string key = keyText(kv.first);
      const int line = kv.first.Mark().line + 1;
      const std::string full = path.empty() ? key : path + "." + key;
      const auto seen = lineOf.find(key);
      if (seen != lineOf.end())
        throw InputError(file + ":" + std::to_string(line) + ": key '" + full +
                         "' appears twice (lines " + std::to_string(seen->second) + " and " +
                         std::to_string(line) + "); give each key once");
      lineOf.emplace(key, line);
      checkDuplicates(kv.second, file, full, budget);
    }
  } else if (node.IsSequence()) {
    for (std::size_t k = 0; k < node.size(); ++k)
      checkDuplicates(node[k], file, path + "[" + std::to_string(k) + "]", budget);
  }
}
}  // namespace

std::size_t editDistance(const std::string& a0, const std::string& b0) {
  std::string a = a0, b = b0;
  for (char& c : a) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (char& c : b) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const std::size_t n = a.size(), m = b.size();
  // Optimal string alignment distance (Damerau-Levenshtein without repeated edits of a substring).
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1, 0));
  for (std::size_t i = 0; i <= n; ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= n; ++i)
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[n][m];
}

std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t bestDistance = std::numeric_limits<std::size_t>::max();
  for (const auto& c : candidates) {
    if (c == word) continue;
    const std::size_t len = std::min(word.size(), c.size());
    const std::size_t allowed = len <= 4 ? 1 : len <= 8 ? 2 : 3;
    const std::size_t d = editDistance(word, c);
    if (d <= allowed && d < bestDistance) {
      best = c;
      bestDistance = d;
    }
  }
  return best;
}

void checkDuplicateKeys(const YAML::Node& node, const std::string& file, const std::string& path) {
  long budget = 1000000;
  checkDuplicates(node, file, path, budget);
}

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
    // A key present but not read (yet) that is close to the missing one is likely its misspelling.
    std::vector<std::string> unread;
    std::map<std::string, int> lineOf;
    if (node_.IsMap())
      for (const auto& kv : node_) {
        const std::string k = keyText(kv.first);
        if (used_.count(k) || k == key) continue;
        unread.push_back(k);
        lineOf.emplace(k, kv.first.Mark().line + 1);
      }
    const std::string guess = closestMatch(key, unread);
    std::string hint;
    if (!guess.empty())
      hint = " (did you mean '" + guess + "' on line " + std::to_string(lineOf[guess]) +
             "? it is not a known key here)";
    else if (node_.IsMap() && node_[key].IsDefined())
      hint = " (it is given, but empty)";
    throw InputError(file_ + ":" + std::to_string(node_.Mark().line + 1) + ": required key '" +
                     full + "' is missing" + hint);
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
  const std::string guess = closestMatch(v, choices);
  fail(key, "must be one of: " + list + (guess.empty() ? "" : " (did you mean '" + guess + "'?)"));
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
    const std::string key = keyText(kv.first);
    if (!used_.count(key)) {
      const std::vector<std::string> known(used_.begin(), used_.end());
      const std::string guess = closestMatch(key, known);
      std::string hint;
      if (!guess.empty())
        hint = "did you mean '" + guess + "'?";
      else if (!known.empty()) {
        hint = "misspelt, or not used by this model; known keys here: ";
        for (std::size_t k = 0; k < known.size(); ++k) hint += (k ? ", " : "") + known[k];
      } else {
        hint = "misspelt, or not used by this model";
      }
      throw InputError(file_ + ":" + std::to_string(kv.first.Mark().line + 1) + ": unknown key '" +
                       (path_.empty() ? key : path_ + "." + key) + "' = " + nodeText(kv.second) +
                       " (" + hint + ")");
    }
  }
}

}  // namespace poresph
