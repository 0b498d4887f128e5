// `poresph study` as a validation tool: a three-point study of the clamped-clamped vibrating bar
// (studies/vibrating_bar.yaml; thesis Chapter 3, Table 1) in the spacing, run through the study
// driver exactly as `poresph study` runs it (each case a `poresph run` child, the period measured by
// the scene's `reference:` from the kinetic-energy column, libcore/reference.cpp). The error
// against the closed form T = 2 L / c must decrease with the spacing (L/50, L/100, L/200; cubic
// spline, h = 1.3 dx), and the finest must be within 0.06 % (measured 0.029 %).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "libcore/study.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
namespace fs = std::filesystem;

TEST(StudyValidation, VibratingBarPeriodConvergesWithSpacing) {
  test::Stopwatch clock;
  const fs::path out = fs::path(PORESPH_BINARY_DIR) / ("tmp_validation_study_" + std::to_string(getpid()));
  fs::remove_all(out);
  StudyOptions o;
  o.scene = std::string(PORESPH_SOURCE_DIR) + "/studies/vibrating_bar.yaml";
  o.out = out.string();
  o.vary = {"spacing=2.666e-3,1.333e-3,6.665e-4"};
  o.sets = {"kernel=cubic_spline", "h_over_dx=1.3", "output.every_time=1.0e-6"};
  o.threads = "1";
  o.noPlot = true;
  o.executable = std::string(PORESPH_BINARY_DIR) + "/poresph";
  const auto rows = runStudy(o);
  ASSERT_EQ(rows.size(), 3u);
  for (const auto& r : rows) {
    ASSERT_TRUE(r.healthy) << r.name << ": " << r.status;
    ASSERT_TRUE(r.hasError) << r.name;
    EXPECT_NE(r.errorAgainst.find("closed form"), std::string::npos);
    std::printf("%s: period %.6e s, error %.3e, CPU %.2f s, %lld particles\n", r.name.c_str(),
                r.value, r.error, r.cpuSeconds, r.particles);
  }
  EXPECT_LT(rows[1].error, rows[0].error);
  EXPECT_LT(rows[2].error, rows[1].error);
  EXPECT_LT(rows[2].error, 6e-4);
  const double T = 5.27605e-5;
  test::recordValidation({"study_bar_period", "period from the study's reference (dx = L/200)",
                          rows[2].value, T, rows[2].error,
                          "dx = L/50, L/100, L/200 (74 / 150 / 300 particles, clamped margins included), cubic "
                          "h = 1.3 dx, dt = 1e-8 s, 3 periods",
                          clock.seconds(), "error decreases with dx; < 0.06 % at L/200",
                          "closed form T = 2 L / c (thesis Ch. 3, Eq. 4)"});
  fs::remove_all(out);
}
