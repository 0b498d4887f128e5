// Scene files: every error names the file, the key and the value; masses, counts, motions and
// velocities of the built particles; the time-step check against the modules' limit.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "libcore/scene.hpp"

namespace fs = std::filesystem;
using namespace poresph;

namespace {

// A probe module owning the model "probe_body": density, sound_speed; stable limit
// 0.25 h / c (the acoustic CFL of Eq. 2.49 with c for |v|). Its section accepts `tag`.
class ProbeModule : public Module {
 public:
  std::string name() const override { return "probe"; }
  std::vector<std::string> materialModels() const override { return {"probe_body"}; }
  std::vector<PairClass> ownedPairs() const override { return {PairClass(kPhaseRigid, kPhaseRigid)}; }
  void configure(Simulation& sim, const std::vector<const Material*>& materials,
                 const ParameterSet* section) override {
    for (const Material* m : materials) {
      sim.materials[static_cast<size_t>(m->id)].phase = kPhaseRigid;  // pairs: its own class
      m->parameters.real("density", Range::positive());
      c_ = std::max(c_, m->parameters.real("sound_speed", Range::positive()));
      m->parameters.finish();
      ++materialCount;
    }
    if (section) {
      lastTag = section->string("tag", "");
      section->finish();
    }
    sim.store.addReal("probe_scalar", 1, kFieldDefault, "probe");
  }
  double timeStepLimit(const Simulation& sim) const override {
    return 0.25 * sim.kernel.h() / c_;
  }
  double c_ = 0.0;
  int materialCount = 0;
  static std::string lastTag;
};
std::string ProbeModule::lastTag;
PORESPH_REGISTER_MODULE(ProbeModule, "probe")

std::string tmpDir() {
  const fs::path d = fs::path(PORESPH_BINARY_DIR) / "tmp_test_scene";
  fs::create_directories(d);
  return d.string();
}

std::string writeScene(const std::string& name, const std::string& text) {
  const std::string path = tmpDir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A valid 2D scene: a 1.0 x 0.5 box of "water" (dx = 0.05: 20 x 10 = 200 particles) minus
// nothing, with a fixed dt below the probe's limit 0.25 * 1.3 * 0.05 / 10 = 1.625e-3 s.
const char* kBase = R"(dimension: 2
domain:
  lo: [0, 0]
  hi: [1.0, 0.5]
spacing: 0.05
end_time: 0.01
time_step:
  dt: 1.0e-3
output:
  every_steps: 5
materials:
  - name: water
    model: probe_body
    density: 1000
    sound_speed: 10
geometry:
  - shape: box
    lo: [0, 0]
    hi: [1.0, 0.5]
    material: water
)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) s.replace(pos, from.size(), to);
  return s;
}

// Loads `text` from file `name` and returns the InputError's message ("" if none).
std::string errorOf(const std::string& name, const std::string& text) {
  const std::string path = writeScene(name, text);
  try {
    loadScene(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_NAMES(msg, s) EXPECT_NE((msg).find(s), std::string::npos) << "message: " << (msg)

}  // namespace

TEST(Scene, ValidSceneBuildsParticlesWithMassRho0DxD) {
  Scene s = loadScene(writeScene("valid.yaml", kBase));
  const Simulation& sim = *s.sim;
  ASSERT_EQ(sim.store.realCount(), 200);
  EXPECT_EQ(s.particlesPerMaterial.at(0), 200);
  const double* m = sim.store.data(sim.store.mass());
  const double* rho = sim.store.data(sim.store.density());
  for (Index i = 0; i < sim.store.realCount(); ++i) {
    EXPECT_DOUBLE_EQ(m[i], 1000.0 * 0.05 * 0.05);
    EXPECT_DOUBLE_EQ(rho[i], 1000.0);
  }
  // Total mass = rho0 * area exactly when the box is a whole number of spacings.
  double total = 0.0;
  for (Index i = 0; i < sim.store.realCount(); ++i) total += m[i];
  EXPECT_NEAR(total, 1000.0 * 0.5, 1e-9);
  EXPECT_DOUBLE_EQ(sim.kernel.h(), 1.3 * 0.05);  // default h_over_dx
  EXPECT_EQ(s.integrator, "leapfrog");
  ASSERT_EQ(sim.modules.size(), 1u);
  EXPECT_EQ(sim.modules[0]->name(), "probe");
  EXPECT_TRUE(sim.store.has("probe_scalar"));
  EXPECT_NEAR(s.initialStableTimeStep, 0.25 * 1.3 * 0.05 / 10.0, 1e-15);
  // Fixed dt: 1e-3 each step, the last one clipped to land on end_time.
  EXPECT_DOUBLE_EQ(s.nextTimeStep(), 1e-3);
  s.sim->time = 0.0095;
  EXPECT_NEAR(s.nextTimeStep(), 0.0005, 1e-15);
  // No sliver: a remainder up to 1 % beyond dt is one step (1.005e-3 would leave 5e-6 s).
  s.sim->time = 0.01 - 1.005e-3;
  EXPECT_NEAR(s.nextTimeStep(), 1.005e-3, 1e-15);
  s.sim->time = 0.01 - 1.02e-3;
  EXPECT_DOUBLE_EQ(s.nextTimeStep(), 1e-3);
  s.sim->time = 0.0;
  // The echo holds the defaults that were used.
  const std::string echo = resolvedSceneYaml(s);
  EXPECT_NAMES(echo, "h_over_dx: 1.3");
  EXPECT_NAMES(echo, "kernel: cubic_spline");
  EXPECT_NAMES(echo, "sound_speed: 10");
  // No scene-wide correction exists, so the echo does not claim one (issue 11).
  EXPECT_EQ(echo.find("correction"), std::string::npos) << echo;
}

TEST(Scene, MissingFileNamesTheFile) {
  const std::string path = tmpDir() + "/no_such_scene.yaml";
  try {
    loadScene(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NAMES(std::string(e.what()), path);
  }
}

TEST(Scene, MalformedYamlNamesFileAndLine) {
  const std::string msg = errorOf("malformed.yaml", "dimension: 2\ndomain: [0, 1\nspacing: 1\n");
  EXPECT_NAMES(msg, "malformed.yaml:");
  EXPECT_NAMES(msg, "malformed YAML");
}

TEST(Scene, UnknownKeyNamesFileLineKeyAndValue) {
  const std::string msg =
      errorOf("unknown.yaml", replaced(kBase, "spacing: 0.05", "spacing: 0.05\nspacng: 0.07"));
  EXPECT_NAMES(msg, "unknown.yaml:6:");
  EXPECT_NAMES(msg, "spacng");
  EXPECT_NAMES(msg, "0.07");
}

TEST(Scene, UnknownMaterialParameterIsAnError) {
  const std::string msg = errorOf(
      "unknown_param.yaml", replaced(kBase, "sound_speed: 10", "sound_speed: 10\n    viscosty: 1e-3"));
  EXPECT_NAMES(msg, "unknown_param.yaml:");
  EXPECT_NAMES(msg, "materials[0].viscosty");
  EXPECT_NAMES(msg, "1e-3");
}

TEST(Scene, WrongTypeNamesKeyAndValue) {
  const std::string msg =
      errorOf("wrong_type.yaml", replaced(kBase, "spacing: 0.05", "spacing: fine"));
  EXPECT_NAMES(msg, "wrong_type.yaml:5:");
  EXPECT_NAMES(msg, "'spacing'");
  EXPECT_NAMES(msg, "'fine'");
  EXPECT_NAMES(msg, "expected a number");
}

TEST(Scene, MissingRequiredKeyNamesFileAndKey) {
  const std::string msg =
      errorOf("missing_key.yaml", replaced(kBase, "spacing: 0.05\n", ""));
  EXPECT_NAMES(msg, "missing_key.yaml:");
  EXPECT_NAMES(msg, "required key 'spacing' is missing");
}

TEST(Scene, NegativeSpacingNamesKeyValueAndRange) {
  const std::string msg =
      errorOf("negative.yaml", replaced(kBase, "spacing: 0.05", "spacing: -0.05"));
  EXPECT_NAMES(msg, "negative.yaml:5:");
  EXPECT_NAMES(msg, "'spacing'");
  EXPECT_NAMES(msg, "'-0.05'");
  EXPECT_NAMES(msg, "(0, inf)");
}

TEST(Scene, FixedDtAboveStableLimitIsRefusedWithBothValues) {
  // limit 0.25 * h / c = 0.25 * 0.065 / 10 = 1.625e-3 s
  const std::string msg =
      errorOf("dt_above_cfl.yaml", replaced(kBase, "dt: 1.0e-3", "dt: 2.0e-3"));
  EXPECT_NAMES(msg, "dt_above_cfl.yaml:8:");
  EXPECT_NAMES(msg, "time_step.dt");
  EXPECT_NAMES(msg, "0.002");
  EXPECT_NAMES(msg, "0.001625");
  EXPECT_NAMES(msg, "module 'probe'");
  EXPECT_NAMES(msg, "adaptive: true");
}

TEST(Scene, AdaptiveStepIsCflTimesLimitCappedByDt) {
  Scene s = loadScene(writeScene(
      "adaptive.yaml",
      replaced(kBase, "  dt: 1.0e-3\n", "  dt: 2.0e-3\n  adaptive: true\n  cfl: 0.5\n")));
  EXPECT_TRUE(s.timeStep.adaptive);
  EXPECT_NEAR(s.nextTimeStep(), 0.5 * 1.625e-3, 1e-15);
  Scene capped = loadScene(writeScene(
      "adaptive_cap.yaml",
      replaced(kBase, "  dt: 1.0e-3\n", "  dt: 1.0e-4\n  adaptive: true\n")));
  EXPECT_NEAR(capped.nextTimeStep(), 1e-4, 1e-18);
}

TEST(Scene, CflWithoutAdaptiveIsAnError) {
  const std::string msg =
      errorOf("cfl_fixed.yaml", replaced(kBase, "dt: 1.0e-3", "dt: 1.0e-3\n  cfl: 0.5"));
  EXPECT_NAMES(msg, "time_step.cfl");
  EXPECT_NAMES(msg, "0.5");
}

TEST(Scene, UnknownModelListsTheKnownOnes) {
  const std::string msg =
      errorOf("model.yaml", replaced(kBase, "model: probe_body", "model: probe_bdy"));
  EXPECT_NAMES(msg, "model.yaml:13:");
  EXPECT_NAMES(msg, "materials[0].model");
  EXPECT_NAMES(msg, "'probe_bdy'");
  EXPECT_NAMES(msg, "probe_body");
}

TEST(Scene, UnknownMaterialInGeometryIsAnError) {
  const std::string msg =
      errorOf("geo_mat.yaml", replaced(kBase, "material: water", "material: oil"));
  EXPECT_NAMES(msg, "geo_mat.yaml:20:");
  EXPECT_NAMES(msg, "geometry[0].material");
  EXPECT_NAMES(msg, "'oil'");
}

TEST(Scene, UnknownKernelAndIntegratorAreErrors) {
  std::string msg = errorOf("kernel.yaml", replaced(kBase, "spacing: 0.05", "spacing: 0.05\nkernel: spline"));
  EXPECT_NAMES(msg, "kernel.yaml:6:");
  EXPECT_NAMES(msg, "'spline'");
  EXPECT_NAMES(msg, "cubic_spline");
  msg = errorOf("integ.yaml", replaced(kBase, "spacing: 0.05", "spacing: 0.05\nintegrator: euler"));
  EXPECT_NAMES(msg, "integ.yaml:6:");
  EXPECT_NAMES(msg, "'euler'");
  EXPECT_NAMES(msg, "leapfrog");
}

// The top-level `correction:` key was parsed but read by no module (issue 11): it is gone, and a
// scene giving it, even with a formerly valid value, is refused as an unknown key with the reason.
TEST(Scene, CorrectionKeyIsAnUnknownKey) {
  for (const char* value : {"mixed_2.63b", "none", "mixd"}) {
    const std::string msg = errorOf(
        "corr.yaml", replaced(kBase, "spacing: 0.05", std::string("spacing: 0.05\ncorrection: ") + value));
    EXPECT_NAMES(msg, "corr.yaml:6:");
    EXPECT_NAMES(msg, "'correction'");
    EXPECT_NAMES(msg, value);
    EXPECT_NAMES(msg, "unknown key");
    EXPECT_NAMES(msg, "no module reads");
  }
}

TEST(Scene, OutputNeedsExactlyOneCadence) {
  std::string msg = errorOf("out_both.yaml",
                            replaced(kBase, "every_steps: 5", "every_steps: 5\n  every_time: 0.1"));
  EXPECT_NAMES(msg, "out_both.yaml:");
  EXPECT_NAMES(msg, "exactly one");
  msg = errorOf("out_zero.yaml", replaced(kBase, "every_steps: 5", "every_steps: 0"));
  EXPECT_NAMES(msg, "output.every_steps");
  EXPECT_NAMES(msg, "'0'");
}

TEST(Scene, DomainHiMustExceedLo) {
  const std::string msg =
      errorOf("domain.yaml", replaced(kBase, "hi: [1.0, 0.5]\nspacing", "hi: [1.0, -0.5]\nspacing"));
  EXPECT_NAMES(msg, "domain.yaml:4:");
  EXPECT_NAMES(msg, "domain.hi");
  EXPECT_NAMES(msg, "-0.5");
}

TEST(Scene, WrongLengthListNamesTheKey) {
  const std::string msg =
      errorOf("len.yaml", replaced(kBase, "lo: [0, 0]\n  hi", "lo: [0, 0, 0]\n  hi"));
  EXPECT_NAMES(msg, "len.yaml:3:");
  EXPECT_NAMES(msg, "domain.lo");
  EXPECT_NAMES(msg, "list of 2 numbers");
}

TEST(Scene, ModuleSectionIsPassedToItsModule) {
  ProbeModule::lastTag.clear();
  Scene s = loadScene(writeScene("section.yaml", std::string(kBase) + "probe:\n  tag: hello\n"));
  EXPECT_EQ(ProbeModule::lastTag, "hello");
  ASSERT_EQ(s.moduleSections.size(), 1u);
  const std::string msg =
      errorOf("section_bad.yaml", std::string(kBase) + "probe:\n  tga: hello\n");
  EXPECT_NAMES(msg, "section_bad.yaml:22:");
  EXPECT_NAMES(msg, "probe.tga");
  EXPECT_NAMES(msg, "'hello'");
}

TEST(Scene, RegionsSetMaterialMotionAndVelocity) {
  // Two materials: the right half of the box is overridden by "rock", fixed; the left half
  // moves at (1, -2) m/s. A disc of radius 0.1 at (0.25, 0.25) is subtracted.
  const std::string text = R"(dimension: 2
domain: {lo: [0, 0], hi: [1.0, 0.5], periodic: [true, false]}
spacing: 0.05
end_time: 0.01
time_step: {dt: 1.0e-4}
output: {every_time: 0.005}
materials:
  - {name: water, model: probe_body, density: 1000, sound_speed: 10}
  - {name: rock, model: probe_body, density: 2500, sound_speed: 20}
geometry:
  - {shape: box, lo: [0, 0], hi: [1.0, 0.5], material: water, velocity: [1, -2]}
  - {shape: box, lo: [0.5, 0], hi: [1.0, 0.5], material: rock, motion: fixed}
  - {shape: sphere, centre: [0.25, 0.25], radius: 0.1, material: none}
)";
  Scene s = loadScene(writeScene("regions.yaml", text));
  const Simulation& sim = *s.sim;
  // Disc sites: (2i+1)^2 + (2j+1)^2 <= (2 * 0.1 / 0.05)^2 = 16 -> i, j in {-2..1}, 12 sites.
  long disc = 0;
  for (int i = -3; i <= 2; ++i)
    for (int j = -3; j <= 2; ++j)
      if ((2 * i + 1) * (2 * i + 1) + (2 * j + 1) * (2 * j + 1) <= 16) ++disc;
  EXPECT_EQ(disc, 12);
  EXPECT_EQ(s.particlesPerMaterial.at(0), 100 - disc);
  EXPECT_EQ(s.particlesPerMaterial.at(1), 100);
  ASSERT_EQ(sim.store.realCount(), 200 - disc);
  const auto& st = sim.store;
  for (Index i = 0; i < st.realCount(); ++i) {
    const int mat = st.data(st.material())[i];
    const double x = st.data(st.position())[2 * i];
    EXPECT_EQ(mat, x > 0.5 ? 1 : 0);
    EXPECT_DOUBLE_EQ(st.data(st.mass())[i], (mat == 1 ? 2500.0 : 1000.0) * 0.05 * 0.05);
    EXPECT_EQ(st.data(sim.motion)[i], mat == 1 ? kMotionFixed : kMotionFree);
    EXPECT_DOUBLE_EQ(st.data(st.velocity())[2 * i], mat == 1 ? 0.0 : 1.0);
    EXPECT_DOUBLE_EQ(st.data(st.velocity())[2 * i + 1], mat == 1 ? 0.0 : -2.0);
  }
  EXPECT_TRUE(sim.domain.periodic[0]);
  EXPECT_FALSE(sim.domain.periodic[1]);
  EXPECT_DOUBLE_EQ(s.output.everyTime, 0.005);
  // Both materials go to the one module that owns their model.
  ASSERT_EQ(sim.modules.size(), 1u);
  EXPECT_EQ(static_cast<const ProbeModule*>(sim.modules[0].get())->materialCount, 2);
}

TEST(Scene, GeometryWithoutParticlesIsAnError) {
  const std::string msg = errorOf(
      "empty_geo.yaml",
      std::string(kBase) + "  - {shape: box, lo: [-1, -1], hi: [2, 2], material: none}\n");
  EXPECT_NAMES(msg, "empty_geo.yaml:");
  EXPECT_NAMES(msg, "no particle");
}

TEST(Scene, LatticeNeighbourEstimate) {
  // Cubic spline, h = 1.3 dx: support 2.6 dx. 1D: 2 * 2 = 4 sites (|i| <= 2 < 2.6).
  EXPECT_EQ(latticeNeighbourCount(1, 2.6), 4);
  // 2D: sites with i^2 + j^2 < 6.76: count by hand = 20 (|i|,|j| <= 2: 24 minus 4 corners
  // (8 > 6.76)), i.e. 5x5 - 1 self - 4 corners = 20.
  EXPECT_EQ(latticeNeighbourCount(2, 2.6), 20);
}

TEST(Scene, ResolvedSceneIsItselfAValidSceneThatBuildsTheSameParticles) {
  Scene s = loadScene(writeScene("echo_src.yaml", std::string(kBase) + "probe:\n  tag: x\n"));
  const std::string echo = resolvedSceneYaml(s);
  EXPECT_NAMES(echo, "modules in stage order: probe");
  EXPECT_NAMES(echo, "max_steps: 0");
  Scene again = loadSceneText(echo, "run.yaml");
  EXPECT_EQ(again.sim->store.realCount(), s.sim->store.realCount());
  EXPECT_DOUBLE_EQ(again.sim->kernel.h(), s.sim->kernel.h());
  const std::string twice = resolvedSceneYaml(again);
  EXPECT_EQ(twice.substr(twice.find("# smoothing")), echo.substr(echo.find("# smoothing")));
}

TEST(Scene, CylinderRegionIsReadNormalisedAndRefusesBadKeys) {
  // A 2D cylinder along (1, 1): a rectangle 2 x 0.1 by 0.4 tilted at 45 degrees, subtracted.
  const std::string cyl =
      "  - {shape: cylinder, centre: [0.5, 0.25], axis: [1, 1], radius: 0.1, length: 0.4, "
      "material: none}\n";
  Scene s = loadScene(writeScene("cylinder.yaml", std::string(kBase) + cyl));
  ASSERT_EQ(s.regions.size(), 2u);
  const Region& r = s.regions[1];
  EXPECT_EQ(r.shape, Region::Shape::Cylinder);
  EXPECT_NEAR(r.axis[0], std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(r.axis[1], std::sqrt(0.5), 1e-15);
  EXPECT_DOUBLE_EQ(r.length, 0.4);
  // The rectangle covers 0.08 m^2 = 32 sites of 0.05 x 0.05; the lattice count of a tilted
  // rectangle 4 x 8 spacings differs from it by boundary sites only.
  EXPECT_NEAR(200 - s.particlesPerMaterial.at(0), 32, 6);
  const std::string zero = errorOf(
      "cylinder_axis.yaml",
      std::string(kBase) + "  - {shape: cylinder, centre: [0.5, 0.25], axis: [0, 0], radius: 0.1, "
                           "length: 0.4, material: none}\n");
  EXPECT_NAMES(zero, "cylinder_axis.yaml");
  EXPECT_NAMES(zero, "geometry[1].axis");
  const std::string len = errorOf(
      "cylinder_length.yaml",
      std::string(kBase) + "  - {shape: cylinder, centre: [0.5, 0.25], axis: [1, 0], radius: 0.1, "
                           "length: -1, material: none}\n");
  EXPECT_NAMES(len, "geometry[1].length");
}
