// Validation records and the table made from them (issue 11): a row whose reference is 0 must not
// print the measured value as a "relative error". The record then carries relative_error = null
// and absolute_error = |measured - reference|; scripts/make_validation_table.py prints "abs. X"
// for it, "rel. X" only for a non-zero reference, and "n/a" where there is no reference.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/validation_record.hpp"

using namespace poresph::test;
namespace fs = std::filesystem;

namespace {

std::string readText(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream o;
  o << in.rdbuf();
  return o.str();
}

// The table line of `quantity` in the Markdown table `md` (empty when absent).
std::string rowOf(const std::string& md, const std::string& quantity) {
  std::istringstream in(md);
  for (std::string line; std::getline(in, line);)
    if (line.find("| " + quantity + " |") != std::string::npos) return line;
  return "";
}

fs::path freshDir(const std::string& name) {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "test-tmp" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

}  // namespace

TEST(ValidationRecord, ZeroReferenceHasNoRelativeErrorButAnAbsoluteOne) {
  const fs::path dir = freshDir("validation_record_json");
  // As the tests used to write it: relativeError = measured for a zero reference.
  const std::string file = recordValidation(
      {"case_a", "drift / E0", 0.0375, 0.0, 0.0375, "n = 1", 1.0, "< 0.1", "conservation"},
      dir.string());
  const std::string json = readText(file);
  EXPECT_NE(json.find("\"relative_error\": null"), std::string::npos) << json;
  EXPECT_NE(json.find("\"absolute_error\": 0.0375"), std::string::npos) << json;
  const std::string file2 = recordValidation(
      {"case_a", "period (s)", 1.1, 1.0, 0.1, "n = 1", 1.0, "< 20 %", "closed form"},
      dir.string());
  const std::string json2 = readText(file2);
  EXPECT_NE(json2.find("\"relative_error\": 0.1"), std::string::npos) << json2;
}

TEST(ValidationRecord, TableShowsAbsoluteErrorForAZeroReference) {
  if (std::system("python3 -c 'import json' > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3 not available";
  const fs::path build = freshDir("validation_table");
  const fs::path records = build / "validation-records";
  recordValidation({"case_a", "drift / E0", 0.0375, 0.0, 0.0375, "n = 1", 1.0, "< 0.1",
                    "conservation"},
                   records.string());
  recordValidation({"case_a", "period (s)", 1.1, 1.0, 0.1, "n = 1", 1.0, "< 20 %", "closed form"},
                   records.string());
  recordValidation({"case_a", "observed order", 1.33, 0.0, 0.0, "n = 1", 1.0, "reported only",
                    "none (need not converge)"},
                   records.string());
  // A previous table in the old format with a row that has no record (a long study): kept, and
  // its "rel. error" of a zero reference rewritten as an absolute error.
  const fs::path table = build / "validation.md";
  {
    std::ofstream t(table);
    t << "# Validation\n\n| case | quantity | measured | reference | rel. error | tolerance | "
         "resolution | wall [s] | reference source |\n| --- | --- | --- | --- | --- | --- | --- | "
         "--- | --- |\n| case_long | spurious Ca | 0.02 | 0 | 0.02 | < 0.1 | R 30 | 100 | 0 (rest) "
         "|\n| case_long | jump (Pa) | 33 | 33.33 | 0.0099 | < 5 % | R 30 | 100 | Laplace |\n"
         "| case_gone | old row | 1 | 0 | 1 | - | - | 1 | - |\n";
  }
  const std::string cmd = std::string("python3 ") + PORESPH_SOURCE_DIR +
                          "/scripts/make_validation_table.py " + build.string() + " " +
                          table.string() + " --drop '^case_gone' > " +
                          (build / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(cmd.c_str()), 0) << readText(build / "log.txt");
  const std::string md = readText(table);
  EXPECT_NE(md.find("| error |"), std::string::npos) << md;
  EXPECT_EQ(md.find("rel. error"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "drift / E0").find("| 0 | abs. 0.0375 |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "period (s)").find("| 1 | rel. 0.1 |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "observed order").find("| none | n/a |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "spurious Ca").find("| 0 | abs. 0.02 |"), std::string::npos) << md;
  EXPECT_NE(rowOf(md, "jump (Pa)").find("| 33.33 | rel. 0.0099 |"), std::string::npos) << md;
  EXPECT_EQ(rowOf(md, "old row"), "") << md;
  // Nowhere a relative error against 0.
  std::istringstream in(md);
  for (std::string line; std::getline(in, line);)
    EXPECT_EQ(line.find("| 0 | rel."), std::string::npos) << line;
}
