// `poresph study` (libcore/study.hpp, libcore/reference.hpp): the grid, the --vary names and their
// scene keys, the refused names, the Pareto front, the error against the finest run, the
// `reference:` section (parsing, refusals, timeseries quantities) and, end to end on a tiny
// droplet (0.3 s a run), a failing and an unstable run that become rows while the others run.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "libcore/parameters.hpp"
#include "libcore/reference.hpp"
#include "libcore/scene.hpp"
#include "libcore/study.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

StudyRow row(const std::string& name, double wall, double error, bool healthy = true) {
  StudyRow r;
  r.name = name;
  r.wallSeconds = wall;
  r.error = error;
  r.hasError = true;
  r.healthy = healthy;
  return r;
}

const char* kTinyScene = R"(dimension: 1
domain: {lo: [0.0], hi: [1.0]}
spacing: 0.1
end_time: 1.0
time_step: {dt: 0.01}
output: {every_steps: 10}
materials:
  - {name: water, model: fluid, density: 1000, sound_speed: 10, viscosity: 0.001}
geometry:
  - {shape: box, lo: [0.0], hi: [1.0], material: water}
)";

Scene tinyScene(const std::string& reference) {
  SceneOptions so;
  so.buildParticles = false;
  so.initialise = false;
  so.checkMemory = false;
  return loadSceneText(std::string(kTinyScene) + reference, "tiny.yaml", so);
}

}  // namespace

TEST(Study, GridFirstAxisSlowest) {
  const auto g = expandGrid({{"spacing", {"1", "2"}}, {"kernel", {"a", "b", "c"}}});
  ASSERT_EQ(g.size(), 6u);
  EXPECT_EQ(g[0][0].second, "1");
  EXPECT_EQ(g[0][1].second, "a");
  EXPECT_EQ(g[1][1].second, "b");
  EXPECT_EQ(g[3][0].second, "2");
  EXPECT_EQ(g[3][1].second, "a");
  EXPECT_EQ(g[5][1].second, "c");
  EXPECT_NE(errorOf([] { expandGrid({{"a", std::vector<std::string>(40, "x")}, {"b", std::vector<std::string>(40, "y")}}, 1000); }).find("more than 1000"),
            std::string::npos);
  EXPECT_EQ(caseFolderName(2, {{"spacing", "1e-4"}, {"materials.gas.density", "10"}}),
            "case03_spacing=1e-4_density=10");
}

TEST(Study, VaryNamesMapToSceneKeys) {
  const VaryAxis k = parseVary("kernel=cubic,wendland,quintic,gaussian");
  EXPECT_EQ(k.values, (std::vector<std::string>{"cubic_spline", "wendland_c2", "quintic_spline", "gaussian"}));
  auto e = studyEdits("kernel", "wendland");
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].path, "kernel");
  EXPECT_EQ(e[0].value, "wendland_c2");
  e = studyEdits("cfl", "0.7");
  ASSERT_EQ(e.size(), 3u);
  EXPECT_EQ(e[0].path, "time_step.adaptive");
  EXPECT_EQ(e[0].value, "true");
  EXPECT_EQ(e[1].path, "time_step.cfl");
  EXPECT_EQ(e[1].value, "0.7");
  EXPECT_TRUE(e[2].remove);
  EXPECT_EQ(e[2].path, "time_step.dt");
  e = studyEdits("spacing", "1e-4");
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].path, "spacing");
  e = studyEdits("h_over_dx", "1.5");
  EXPECT_EQ(e[0].path, "h_over_dx");
  // precision is the fluid module's pair precision (single is float's alias).
  const VaryAxis pr = parseVary("precision=double,single");
  ASSERT_EQ(pr.values.size(), 2u);
  EXPECT_EQ(pr.values[1], "float");
  e = studyEdits("precision", "float");
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(e[0].path, "fluid.pair_precision");
  EXPECT_EQ(e[0].value, "float");
  // A dotted path is a scene key.
  const VaryAxis p = parseVary("materials.gas.density=1000,10");
  EXPECT_EQ(p.values.size(), 2u);
  EXPECT_EQ(studyEdits(p.name, "10")[0].path, "materials.gas.density");
}

TEST(Study, RefusedNamesSayWhy) {
  EXPECT_NE(errorOf([] { parseVary("precision=half,double"); }).find("unknown precision 'half'"),
            std::string::npos);
  EXPECT_NE(errorOf([] { parseVary("correction=none,mixed"); }).find("no scene key selects a kernel or gradient correction"),
            std::string::npos);
  const std::string unknown = errorOf([] { parseVary("spacng=1,2"); });
  EXPECT_NE(unknown.find("--vary spacng: unknown name"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("did you mean 'spacing'"), std::string::npos) << unknown;
  EXPECT_NE(errorOf([] { parseVary("kernel=cubic,bogus"); }).find("unknown kernel 'bogus'"), std::string::npos);
  EXPECT_NE(errorOf([] { parseVary("spacing=1,,2"); }).find("an empty value"), std::string::npos);
  EXPECT_NE(errorOf([] { parseVary("spacing"); }).find("expected NAME=v1,v2"), std::string::npos);
}

TEST(Study, ParetoFront) {
  std::vector<StudyRow> rows = {row("slow_exact", 10, 0.001), row("fast_rough", 1, 0.1),
                                row("dominated", 5, 0.2), row("middle", 3, 0.01),
                                row("unstable_fast", 0.5, 1e-6, false), row("tie", 3, 0.01)};
  const auto front = markParetoFront(rows);
  EXPECT_TRUE(rows[0].pareto);
  EXPECT_TRUE(rows[1].pareto);
  EXPECT_FALSE(rows[2].pareto);  // slower and less accurate than "middle"
  EXPECT_TRUE(rows[3].pareto);
  EXPECT_FALSE(rows[4].pareto);  // unstable runs are never on the front
  EXPECT_TRUE(rows[5].pareto);   // equal to "middle" in both: neither dominates
  ASSERT_EQ(front.size(), 4u);
  EXPECT_EQ(front.front(), 1u);  // by wall time
  EXPECT_EQ(front.back(), 0u);
}

TEST(Study, ErrorAgainstFinestRunOrClosedForm) {
  std::vector<StudyRow> rows(4);
  const double values[] = {1.10, 1.02, 1.00, 5.0};
  const long long particles[] = {100, 400, 1600, 6400};
  for (int k = 0; k < 4; ++k) {
    rows[k].name = "r" + std::to_string(k);
    rows[k].measured = true;
    rows[k].value = values[k];
    rows[k].particles = particles[k];
    rows[k].healthy = k < 3;  // the most particles, but unstable: not the reference
  }
  assignStudyErrors(rows, false, 0.0);
  EXPECT_NEAR(rows[0].error, 0.10, 1e-12);
  EXPECT_NEAR(rows[1].error, 0.02, 1e-12);
  EXPECT_FALSE(rows[2].hasError);  // the reference itself
  EXPECT_NEAR(rows[3].error, 4.0, 1e-12);
  EXPECT_NE(rows[0].errorAgainst.find("finest run r2"), std::string::npos);
  assignStudyErrors(rows, true, 1.05);
  EXPECT_NEAR(rows[2].error, 0.05 / 1.05, 1e-12);
  assignStudyErrors(rows, true, 0.0);  // a zero reference: absolute
  EXPECT_NEAR(rows[1].error, 1.02, 1e-12);
}

TEST(Reference, SectionParsedAndRefused) {
  const Scene s = tinyScene("reference: {quantity: kinetic_energy, at: max, value: 2.5}\n");
  EXPECT_TRUE(s.reference.declared);
  EXPECT_EQ(s.reference.quantity, "kinetic_energy");
  EXPECT_EQ(s.reference.at, "max");
  EXPECT_DOUBLE_EQ(s.reference.value, 2.5);
  EXPECT_FALSE(tinyScene("").reference.declared);
  const std::string unknown = errorOf([] { tinyScene("reference: {quantity: laplace_jump, centre: [0.5], radius: 0.2, valu: 3}\n"); });
  EXPECT_NE(unknown.find("tiny.yaml"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("reference.valu"), std::string::npos) << unknown;
  const std::string atMax = errorOf([] { tinyScene("reference: {quantity: laplace_jump, centre: [0.5], radius: 0.2, at: max}\n"); });
  EXPECT_NE(atMax.find("only at: end"), std::string::npos) << atMax;
  const std::string badAt = errorOf([] { tinyScene("reference: {quantity: kinetic_energy, at: later}\n"); });
  EXPECT_NE(badAt.find("expected end, max, min, first COLUMN or a time"), std::string::npos) << badAt;
  const std::string badFirst = errorOf([] { tinyScene("reference: {quantity: kinetic_energy, at: first a b}\n"); });
  EXPECT_NE(badFirst.find("'first' takes one timeseries column"), std::string::npos) << badFirst;
  for (const char* bad : {"first a > 1", "first a >= x", "first a >= 1 2", "first a >="})
    EXPECT_NE(errorOf([&] { tinyScene(std::string("reference: {quantity: kinetic_energy, at: '") + bad + "'}\n"); })
                  .find("'first' takes one timeseries column"),
              std::string::npos)
        << bad;
  EXPECT_NO_THROW(tinyScene("reference: {quantity: kinetic_energy, at: 'first solid_damage_max >= 0.1'}\n"));
  const std::string firstOfState = errorOf([] { tinyScene("reference: {quantity: laplace_jump, centre: [0.5], radius: 0.2, at: first x}\n"); });
  EXPECT_NE(firstOfState.find("only at: end"), std::string::npos) << firstOfState;
  const std::string missing = errorOf([] { tinyScene("reference: {quantity: hoop_stress, centre: [0.0]}\n"); });
  EXPECT_NE(missing.find("needs a 2D or 3D scene"), std::string::npos) << missing;
}

TEST(Reference, StateQuantitiesOnAKnownState) {
  // A 2D elastic plate 1 x 1 m of 10 x 10 particles; the stress set by hand to diag(1, 2) Pa:
  // about the centre (0, 0) at the point (0.5, 0) the radial stress is sigma_xx = 1 and the hoop
  // stress sigma_yy = 2; on the diagonal both are 1.5. material_volume of the box [0, 0.5]^2 is
  // 25 particles x 0.01 m^2.
  const std::string base = R"(dimension: 2
domain: {lo: [0, 0], hi: [1, 1]}
spacing: 0.1
end_time: 1.0
time_step: {dt: 1e-6}
output: {every_steps: 10}
materials:
  - {name: rock, model: elastic, density: 2000, young_modulus: 1e9, poisson_ratio: 0.25}
geometry:
  - {shape: box, lo: [0, 0], hi: [1, 1], material: rock}
)";
  auto eval = [&](const std::string& ref) {
    SceneOptions so;
    so.initialise = false;
    so.checkMemory = false;
    Scene s = loadSceneText(base + ref, "plate.yaml", so);
    ParticleStore& st = s.sim->store;
    double* sig = st.data(st.real("stress"));
    for (Index i = 0; i < st.realCount(); ++i) {
      sig[4 * i + 0] = 1.0;  // (x, x)
      sig[4 * i + 1] = 0.0;
      sig[4 * i + 2] = 0.0;
      sig[4 * i + 3] = 2.0;  // (y, y)
    }
    return evaluateReference(s, "");
  };
  ReferenceResult r = eval("reference: {quantity: hoop_stress, centre: [0, 0], point: [0.5, 0.02], value: 2}\n");
  ASSERT_TRUE(r.ok) << r.note;
  EXPECT_NEAR(r.measured, 2.0, 2e-3);  // e_r is not exactly x at (0.5, 0.02): 2 - sin^2(2.3 deg)
  r = eval("reference: {quantity: radial_stress, centre: [0, 0], point: [0.5, 0.02]}\n");
  EXPECT_NEAR(r.measured, 1.0, 2e-3);
  r = eval("reference: {quantity: hoop_stress, centre: [0, 0], point: [0.5, 0.5]}\n");
  EXPECT_NEAR(r.measured, 1.5, 1e-12);
  r = eval("reference: {quantity: material_volume, material: rock, box: {min: [0, 0], max: [0.5, 0.5]}, scale: 2}\n");
  EXPECT_NEAR(r.measured, 2 * 25 * 0.01, 1e-12);
  r = eval("reference: {quantity: material_volume, material: water, box: {min: [0, 0], max: [1, 1]}}\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.note.find("no material 'water'"), std::string::npos) << r.note;
  r = eval("reference: {quantity: laplace_jump, centre: [0.5, 0.5], radius: 0.2}\n");
  EXPECT_FALSE(r.ok);  // no fluid
}

TEST(Reference, TimeseriesQuantities) {
  const fs::path csv = fs::temp_directory_path() / ("test_study_ts_" + std::to_string(getpid()) + ".csv");
  {
    std::ofstream f(csv);
    // ev: an event column (0 before t = 0.0925 s, a quarter period, then 1, as drainage_percolated
    // switches); never: one that stays 0.
    f << "time,step,foo,ev,never\n";
    const double T = 0.37;
    for (int k = 0; k <= 400; ++k) {
      const double t = 0.005 * k;
      f << t << "," << k << "," << 3.0 + std::sin(2 * M_PI * t / T) << "," << (k >= 19 ? 1 : 0)
        << ",0\n";
    }
  }
  auto eval = [&](const std::string& ref) {
    const Scene s = tinyScene(ref);
    return evaluateReference(s, csv.string());
  };
  ReferenceResult r = eval("reference: {quantity: period, column: foo, value: 0.37}\n");
  ASSERT_TRUE(r.ok) << r.note;
  EXPECT_LT(r.error, 2e-3);
  r = eval("reference: {quantity: period, column: foo, factor: 2}\n");
  EXPECT_NEAR(r.measured, 0.74, 2e-3);
  r = eval("reference: {quantity: foo, at: max}\n");
  EXPECT_NEAR(r.measured, 4.0, 1e-3);
  r = eval("reference: {quantity: foo, at: min}\n");
  EXPECT_NEAR(r.measured, 2.0, 1e-3);
  r = eval("reference: {quantity: foo, at: 0.0925, value: 4.0}\n");  // a quarter period
  EXPECT_NEAR(r.measured, 4.0, 1e-3);
  EXPECT_LT(r.error, 1e-3);
  r = eval("reference: {quantity: foo, at: first ev}\n");  // the row of t = 0.095 s
  ASSERT_TRUE(r.ok) << r.note;
  EXPECT_NEAR(r.measured, 3.0 + std::sin(2 * M_PI * 0.095 / 0.37), 1e-5);  // as written (6 digits)
  // `first COLUMN >= VALUE`: the time COLUMN first reaches VALUE, interpolated between the rows
  // (foo rises through 3.5 between the rows of t = 0.015 and 0.02 s: 3 + sin(2 pi t / T) = 3.5 at
  // t = T / 12 = 0.030833 s; linear between the rows 0.030 and 0.035 s); the quantity is read there.
  r = eval("reference: {quantity: time, at: first foo >= 3.5}\n");
  ASSERT_TRUE(r.ok) << r.note;
  {
    const double t0 = 0.03, t1 = 0.035, y0 = 3.0 + std::sin(2 * M_PI * t0 / 0.37),
                 y1 = 3.0 + std::sin(2 * M_PI * t1 / 0.37);
    EXPECT_NEAR(r.measured, t0 + (3.5 - y0) / (y1 - y0) * (t1 - t0), 1e-6);
    EXPECT_NEAR(r.measured, 0.37 / 12, 2e-4);  // the crossing itself, within the row's chord
  }
  r = eval("reference: {quantity: time, at: first foo <= 2.5}\n");  // falling through 2.5 at 7 T / 12
  ASSERT_TRUE(r.ok) << r.note;
  EXPECT_NEAR(r.measured, 7 * 0.37 / 12, 2e-4);
  r = eval("reference: {quantity: foo, at: first ev >= 1}\n");  // a 0 -> 1 switch: the switch row
  ASSERT_TRUE(r.ok) << r.note;
  EXPECT_NEAR(r.measured, 3.0 + std::sin(2 * M_PI * 0.095 / 0.37), 1e-5);
  r = eval("reference: {quantity: foo, at: first foo >= 4.5}\n");  // never
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.note.find("did not happen"), std::string::npos) << r.note;
  r = eval("reference: {quantity: foo, at: first never}\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.note.find("did not happen"), std::string::npos) << r.note;
  r = eval("reference: {quantity: foo, at: first nope}\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.note.find("no column 'nope'"), std::string::npos) << r.note;
  r = eval("reference: {quantity: foo, at: 50}\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.note.find("outside the timeseries"), std::string::npos) << r.note;
  r = eval("reference: {quantity: bar}\n");
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.note.find("no column 'bar'"), std::string::npos) << r.note;
  fs::remove(csv);
}

TEST(Study, FailedAndUnstableRunsAreRows) {
  // A droplet of 225 particles (0.3 s a run): spacing 2e-4 does not divide the periodic box (the
  // scene parser refuses it: a bad-scene row), a density-variation bound of 1e-9 stops the run
  // at its first step (an unstable row); the others run and are measured.
  const fs::path out = fs::path(PORESPH_BINARY_DIR) / ("tmp_test_study_" + std::to_string(getpid()));
  fs::remove_all(out);
  StudyOptions o;
  o.scene = std::string(PORESPH_SOURCE_DIR) + "/studies/static_droplet.yaml";
  o.out = out.string();
  o.vary = {"spacing=3e-4,2e-4", "health.density_variation=0.1,1e-9"};
  o.sets = {"end_time=0.004"};
  o.threads = "1";
  o.noPlot = true;
  o.executable = std::string(PORESPH_BINARY_DIR) + "/poresph";
  const auto rows = runStudy(o);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_TRUE(rows[0].healthy) << rows[0].status;
  EXPECT_TRUE(rows[0].measured);
  EXPECT_TRUE(rows[0].hasError);  // against the closed form gamma / R
  EXPECT_GT(rows[0].particles, 0);
  EXPECT_GT(rows[0].steps, 0);
  EXPECT_GT(rows[0].cpuSeconds, 0.0);
  EXPECT_GT(rows[0].maxRssKiB, 0);
  EXPECT_FALSE(rows[1].healthy);
  EXPECT_EQ(rows[1].code, 3);
  EXPECT_NE(rows[1].status.find("unstable: density_variation"), std::string::npos) << rows[1].status;
  EXPECT_FALSE(rows[1].pareto);
  for (int k : {2, 3}) {
    EXPECT_FALSE(rows[k].healthy);
    EXPECT_NE(rows[k].status.find("bad scene"), std::string::npos) << rows[k].status;
    EXPECT_NE(rows[k].status.find("not a whole number of spacings"), std::string::npos) << rows[k].status;
  }
  EXPECT_TRUE(rows[0].pareto);
  std::ostringstream md;
  md << std::ifstream(out / "study.md").rdbuf();
  EXPECT_NE(md.str().find("unstable: density_variation"), std::string::npos);
  std::ostringstream csvText;
  csvText << std::ifstream(out / "study.csv").rdbuf();
  EXPECT_NE(csvText.str().find("case,spacing,health.density_variation,status,healthy"), std::string::npos) << csvText.str();
  // An existing study folder is refused, before anything runs.
  EXPECT_NE(errorOf([&] { runStudy(o); }).find("the folder exists and is not empty"), std::string::npos);
  // A scene without `reference:` is refused, naming the fix.
  o.scene = std::string(PORESPH_SOURCE_DIR) + "/samples/fluid_static_droplet.yaml";
  o.out = (out / "none").string();
  EXPECT_NE(errorOf([&] { runStudy(o); }).find("declares no `reference:`"), std::string::npos);
  // The precision is the fluid module's: a scene without one is refused (no fluid module added).
  o.scene = std::string(PORESPH_SOURCE_DIR) + "/samples/solid_lame.yaml";
  o.vary = {"precision=double,float"};
  EXPECT_NE(errorOf([&] { runStudy(o); }).find("has no `fluid:` section"), std::string::npos);
  fs::remove_all(out);
}
