// Validation (issue 16, thesis Sec. 5.4): the confining stress controls the damage of drainage
// on the main job's crop. samples/drainage_ketton_3d_sweep.yaml (the main job: 16^3 Ketton crop,
// spectral split and stress measure, dP = 300 Pa, gamma 0.002, wall_push_only, y plates sealed 1 dx
// short of the sample's ends; wall_overlap_pressure; every load ramp over 8 ms) run at 160 / 120 / 80 Pa (sigma / dP =
// 0.53 / 0.40 / 0.27: the thesis' 8 and 6 MPa at its dP = 15 MPa, and a 4 MPa analogue; sigma / f_t
// = 1.03 / 0.77 / 0.51 with f_t = E eps_t0 = 156 Pa) to 1.5 ms after breakthrough. The thesis
// (Sec. 5.4, Figs. 5.9 and 5.12): lower confinement gives an earlier percolation, a larger
// porosity increase and more damage. Measured (docs/drainage.md, "The sweep with slow load ramps
// and wall_push_only", 2026-11-28): damaged 0.31 / 0.62 / 0.91 % at breakthrough at 160 / 120 /
// 80 Pa, no damage before 6.5 ms (the damage comes
// with the gas in the inlet-side pore, not with the load ramp), 87-100 % of it within 1.5 dx of a
// pore; the plates hold (< 2 um) and the crop compacts (porosity 0.1360-0.1362 at 10.5 ms from
// 0.1396). Breakthrough 10.499 / 10.566 / 10.511 ms (10.620 / 10.566 / 10.511 without
// wall_overlap_pressure: ordered there, not here; differences under 0.6 %, set by the fluids):
// breakthrough and porosity recorded, not ordered. Asserted: every case breaks through with both
// plates within 0.1 dx of their start (below ~80 Pa the front plate lifts off, 1.2 dx at 40 Pa),
// the damaged fraction at 9 ms and at breakthrough is larger as the stress falls, and the damaged
// fraction at 6 ms is under a tenth of that at breakthrough.
// Long test (three runs of ~2,520 steps, ~4 min CPU each): tests/long-tests.txt.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "libcore/runner.hpp"
#include "libcore/scene.hpp"
#include "tests/support/timeseries_table.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
namespace fsys = std::filesystem;

namespace {

struct Case {
  double stress = 0.0, percolation = -1.0, porosityChange = NAN, damaged = NAN, damaged6 = NAN, damaged9 = NAN;
  double gasSaturation = NAN, front = NAN, back = NAN, wall = 0.0;
};

Case run(double stress) {
  std::ifstream in(std::string(PORESPH_SOURCE_DIR) + "/samples/drainage_ketton_3d_sweep.yaml");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  int replaced = 0;
  for (size_t p = text.find("stress: 80,"); p != std::string::npos; p = text.find("stress: 80,", p + 1), ++replaced)
    text.replace(p, 11, "stress: " + std::to_string(stress) + ",");
  EXPECT_EQ(replaced, 2) << "both plates of the sweep sample";
  // The image path is relative to the sample: resolve it from the source tree.
  const std::string image = "file: ../data/";
  const size_t ip = text.find(image);
  EXPECT_NE(ip, std::string::npos);
  if (ip != std::string::npos) text.replace(ip, image.size(), "file: " + std::string(PORESPH_SOURCE_DIR) + "/data/");
  const fsys::path dir = fsys::path(PORESPH_BINARY_DIR) / "test-drainage-confinement-3d";
  fsys::create_directories(dir);
  const std::string name = "stress_" + std::to_string(static_cast<int>(stress));
  Scene scene = loadSceneText(text, (dir / (name + ".yaml")).string());
  RunOptions options;
  options.outDir = (dir / name).string();
  fsys::remove_all(options.outDir);
  options.handleSignals = false;
  test::Stopwatch clock;
  const RunResult r = runScene(scene, options);
  EXPECT_EQ(r.status, RunStatus::Finished) << stress << ": " << r.message;
  const test::TimeseriesTable s = test::readTimeseries(options.outDir + "/timeseries.csv");
  Case c;
  c.stress = stress;
  c.wall = clock.seconds();
  c.percolation = s.rows.back().at("drainage_percolation_time");
  c.damaged6 = s.interpolated("drainage_damaged_fraction", 0.006);
  c.damaged9 = s.interpolated("drainage_damaged_fraction", 0.009);
  if (c.percolation > 0.0) {
    c.porosityChange = s.interpolated("drainage_porosity", c.percolation) - s.rows.front().at("drainage_porosity");
    c.damaged = s.interpolated("drainage_damaged_fraction", c.percolation);
    c.gasSaturation = s.interpolated("drainage_gas_saturation", c.percolation);
    c.front = s.interpolated("plate0_displacement", c.percolation);
    c.back = s.interpolated("plate1_displacement", c.percolation);
  }
  return c;
}

}  // namespace

TEST(DrainageConfinement3D, CropLowerStressDamagesMoreAfterTheGasArrivesWhilePlatesHold) {
  std::vector<Case> cases;
  for (double s : {160.0, 120.0, 80.0}) cases.push_back(run(s));
  for (const Case& c : cases) {
    test::ValidationRecord rec;
    rec.caseName = "drainage_confinement_3d_crop_" + std::to_string(static_cast<int>(c.stress)) + "Pa";
    rec.resolution = "16^3 Ketton crop, dx = 0.1 mm, quintic h = dx, 13,552 particles";
    rec.wallSeconds = c.wall;
    rec.reference = NAN;
    rec.reference_source = "thesis Sec. 5.4 trends (Figs. 5.9, 5.12)";
    rec.tolerance = "recorded (within 0.6 %, not ordered: set by the fluids while the plates hold)";
    rec.quantity = "percolation time [s]";
    rec.measured = c.percolation;
    test::recordValidation(rec);
    rec.tolerance = "recorded (measured flat: the crop compacts while the plates hold)";
    rec.quantity = "porosity change at breakthrough";
    rec.measured = c.porosityChange;
    test::recordValidation(rec);
    rec.tolerance = "grows as the stress falls";
    rec.quantity = "damaged fraction (D > 0.5) at breakthrough";
    rec.measured = c.damaged;
    test::recordValidation(rec);
    rec.quantity = "damaged fraction (D > 0.5) at 9 ms";
    rec.measured = c.damaged9;
    test::recordValidation(rec);
    rec.tolerance = "under a tenth of the value at breakthrough (not a load-ramp transient)";
    rec.quantity = "damaged fraction (D > 0.5) at 6 ms";
    rec.measured = c.damaged6;
    test::recordValidation(rec);
    rec.tolerance = "recorded";
    rec.quantity = "gas saturation at breakthrough";
    rec.measured = c.gasSaturation;
    test::recordValidation(rec);
    rec.tolerance = "|u| < 1e-5 m (0.1 dx), both plates";
    rec.quantity = "front plate displacement at breakthrough [m]";
    rec.measured = c.front;
    test::recordValidation(rec);
  }
  for (const Case& c : cases) {
    ASSERT_GT(c.percolation, 0.0) << c.stress;
    EXPECT_LT(std::abs(c.front), 1e-5) << c.stress << " Pa: the front plate lifted off (m)";
    EXPECT_LT(std::abs(c.back), 1e-5) << c.stress << " Pa: the back plate lifted off (m)";
    EXPECT_LT(c.damaged6, 0.1 * c.damaged) << c.stress << " Pa: damage set before the gas arrives";
  }
  for (size_t k = 1; k < cases.size(); ++k) {
    EXPECT_GT(cases[k].damaged9, cases[k - 1].damaged9) << cases[k].stress;
    EXPECT_GT(cases[k].damaged, cases[k - 1].damaged) << cases[k].stress;
  }
}
