#pragma once
// Typed, range-checked access to one YAML mapping of a scene file (a material, a section).
//
// Every read names the key; every error names the file, line, key and value. finish() reports
// keys that nobody read (unknown keys are errors, not silently ignored). The owner of a parameter
// (a module) reads and checks it; the scene parser only dispatches mappings.
#include <yaml-cpp/yaml.h>

#include <limits>
#include <set>
#include <string>
#include <vector>

#include "libcore/types.hpp"

namespace poresph {

/// Allowed range of a real parameter; bounds are inclusive unless marked open.
struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool loOpen = false;
  bool hiOpen = false;
  static Range positive() { return Range{0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range nonNegative() { return Range{0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range closed(double a, double b) { return Range{a, b, false, false}; }
  static Range any() { return Range{}; }
  bool contains(double v) const;
  std::string describe() const;
};

/// Edit distance between two words (insertions, deletions, substitutions and transpositions of
/// adjacent characters each cost 1; letter case is ignored).
std::size_t editDistance(const std::string& a, const std::string& b);
/// The candidate closest to `word` by editDistance when it is close enough to be a likely
/// misspelling (at most 1 edit for words of up to 4 letters, 2 up to 8, else 3); "" if none.
std::string closestMatch(const std::string& word, const std::vector<std::string>& candidates);

/// Throws InputError when a mapping anywhere under `node` holds the same key twice (yaml-cpp
/// keeps both entries and a lookup returns the first, so the second value would be silently
/// ignored): "file:LINE: key 'path.key' appears twice (lines A and B)".
void checkDuplicateKeys(const YAML::Node& node, const std::string& file,
                        const std::string& path = "");

class ParameterSet {
 public:
  ParameterSet() = default;
  /// `node` must be a mapping; `path` is the key path used in messages ("materials[1]").
  ParameterSet(const YAML::Node& node, std::string file, std::string path);

  bool has(const std::string& key) const;
  double real(const std::string& key, Range range = Range::any()) const;
  double real(const std::string& key, double fallback, Range range) const;
  long integer(const std::string& key, long lo, long hi) const;
  long integer(const std::string& key, long fallback, long lo, long hi) const;
  bool boolean(const std::string& key) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  /// A string that must be one of `choices`.
  std::string choice(const std::string& key, const std::vector<std::string>& choices) const;
  std::string choice(const std::string& key, const std::string& fallback,
                     const std::vector<std::string>& choices) const;
  /// A list of `n` reals (n = 0: any length).
  std::vector<double> reals(const std::string& key, size_t n = 0, Range range = Range::any()) const;
  /// A nested mapping.
  ParameterSet section(const std::string& key) const;
  std::vector<ParameterSet> sectionList(const std::string& key) const;
  /// The raw node (for readers that need more than the typed accessors); marks the key used.
  YAML::Node raw(const std::string& key) const;

  /// Throws InputError naming the first key of the mapping that was never read, with the
  /// closest key that was read ("did you mean ...?") or the list of the keys read.
  void finish() const;

  const std::string& file() const { return file_; }
  const std::string& path() const { return path_; }
  /// "file:line: key 'path.key'" prefix for messages about `key`.
  std::string where(const std::string& key) const;
  /// Throws an InputError about `key` with the given reason, naming file, line, key and value.
  [[noreturn]] void fail(const std::string& key, const std::string& reason) const;

 private:
  YAML::Node get(const std::string& key) const;  // required; marks used
  YAML::Node node_;
  std::string file_;
  std::string path_;
  mutable std::set<std::string> used_;
};

}  // namespace poresph
