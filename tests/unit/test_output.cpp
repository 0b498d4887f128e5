// Output: .vtu snapshots read back with VTK's own reader, the .pvd collection and the CSV.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <vtkCellTypes.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "libcore/output.hpp"
#include "libcore/simulation.hpp"

using namespace poresph;
namespace fs = std::filesystem;

namespace {

std::string freshDir(const std::string& name) {
  const fs::path p = fs::path(PORESPH_BINARY_DIR) / "test-output" / name;
  fs::remove_all(p);
  return p.string();
}

std::string slurp(const std::string& path) {
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

/// A module that adds one diagnostic column (and optionally a second one later).
class ColumnsModule : public Module {
 public:
  std::string name() const override { return "columns"; }
  std::vector<std::string> materialModels() const override { return {}; }
  void configure(Simulation&, const std::vector<const Material*>&, const ParameterSet*) override {}
  void diagnostics(const Simulation& sim,
                   std::vector<std::pair<std::string, double>>& c) const override {
    c.emplace_back("answer", 42.0 + sim.time);
    if (extra) c.emplace_back("extra", 1.0);
  }
  bool extra = false;
};

/// A store of n particles in dimension d with a scalar, a vector, a tensor, an int field, a
/// 2-component "other" field and a field that is not for output, all with distinct values.
std::unique_ptr<Simulation> makeStore(int d, Index n) {
  auto sim = std::make_unique<Simulation>(d);
  ParticleStore& s = sim->store;
  s.addReal("pressure", 1, kFieldDefault, "test");
  s.addReal("stress", d * d, kFieldDefault, "test");
  s.addReal("pair", 2 + (d == 2 ? 1 : 0), kFieldDefault, "test");  // never a vector/tensor
  s.addInt("flags", 2, kFieldDefault, "test");
  s.addReal("hidden", 1, kFieldNone, "test");
  s.addParticles(n);
  for (const FieldSpec& spec : s.fields()) {
    const int id = static_cast<int>(&spec - s.fields().data());
    const Index c = spec.components;
    for (Index q = 0; q < n * c; ++q) {
      if (spec.type == FieldType::Real)
        s.data(RealField{id})[q] = 0.25 * id + 1e-3 * q - 0.1 * std::sin(q);
      else if (spec.name != "id")
        s.data(IntField{id})[q] = static_cast<std::int32_t>(7 * id + q);
    }
  }
  return sim;
}

void compareSnapshot(const Simulation& sim, const std::string& file) {
  const ParticleStore& s = sim.store;
  const int d = sim.dimension();
  const Index n = s.realCount();
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  vtkUnstructuredGrid* g = reader->GetOutput();
  ASSERT_EQ(g->GetNumberOfPoints(), n);
  ASSERT_EQ(g->GetNumberOfCells(), n);
  for (Index i = 0; i < n; ++i) EXPECT_EQ(g->GetCellType(i), VTK_VERTEX);
  for (Index i = 0; i < n; ++i) {
    double p[3];
    g->GetPoint(i, p);
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(p[a], a < d ? s.data(s.position())[i * d + a] : 0.0);
  }
  ASSERT_NE(g->GetFieldData()->GetArray("TimeValue"), nullptr);
  EXPECT_EQ(g->GetFieldData()->GetArray("TimeValue")->GetTuple1(0), sim.time);
  int expectedArrays = 0;
  for (size_t k = 0; k < s.fields().size(); ++k) {
    const FieldSpec& spec = s.fields()[k];
    const int id = static_cast<int>(k);
    vtkDataArray* arr = g->GetPointData()->GetArray(spec.name.c_str());
    if (!(spec.flags & kFieldOutput) || spec.name == "position") {
      EXPECT_EQ(arr, nullptr) << spec.name;
      continue;
    }
    ++expectedArrays;
    ASSERT_NE(arr, nullptr) << spec.name;
    SCOPED_TRACE(spec.name);
    const int c = spec.components;
    if (spec.type == FieldType::Int) {
      EXPECT_NE(vtkIntArray::SafeDownCast(arr), nullptr);
      ASSERT_EQ(arr->GetNumberOfComponents(), c);
      for (Index q = 0; q < n * c; ++q)
        EXPECT_EQ(arr->GetComponent(q / c, static_cast<int>(q % c)), s.data(IntField{id})[q]);
      continue;
    }
    const double* src = s.data(RealField{id});
    const bool vector = (d > 1 && c == d) || (d == 1 && (spec.name == "velocity" ||
                                                        spec.name == "acceleration"));
    const bool tensor = d > 1 && c == d * d;
    if (vector) {
      ASSERT_EQ(arr->GetNumberOfComponents(), 3);
      for (Index i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
          EXPECT_EQ(arr->GetComponent(i, a), a < d ? src[i * d + a] : 0.0);
    } else if (tensor) {
      ASSERT_EQ(arr->GetNumberOfComponents(), 9);
      for (Index i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b)  // VTK row-major, store column-major
            EXPECT_EQ(arr->GetComponent(i, 3 * a + b),
                      (a < d && b < d) ? src[i * d * d + a + d * b] : 0.0);
    } else {
      ASSERT_EQ(arr->GetNumberOfComponents(), c);
      for (Index q = 0; q < n * c; ++q)
        EXPECT_EQ(arr->GetComponent(q / c, static_cast<int>(q % c)), src[q]);
    }
  }
  // principal_stress: the descending principal values of the symmetric part of "stress" (2D:
  // the in-plane pair, then 0): they sum to the trace and each is a root of det(S - l 1).
  if (s.has("stress") && d > 1 && s.components(s.real("stress").id) == d * d) {
    ++expectedArrays;
    vtkDataArray* pr = g->GetPointData()->GetArray("principal_stress");
    ASSERT_NE(pr, nullptr);
    ASSERT_EQ(pr->GetNumberOfComponents(), 3);
    const double* S = s.data(s.real("stress"));
    for (Index i = 0; i < n; ++i) {
      Eigen::MatrixXd M(d, d);
      for (int a = 0; a < d; ++a)
        for (int b = 0; b < d; ++b)
          M(a, b) = 0.5 * (S[i * d * d + a + d * b] + S[i * d * d + b + d * a]);
      const double scale = std::max(1.0, M.norm());
      double sum = 0.0;
      for (int k = 0; k < d; ++k) {
        const double l = pr->GetComponent(i, k);
        sum += l;
        EXPECT_NEAR((M - l * Eigen::MatrixXd::Identity(d, d)).determinant(), 0.0,
                    1e-9 * std::pow(scale, d));
        if (k > 0) EXPECT_GE(pr->GetComponent(i, k - 1), l);
      }
      EXPECT_NEAR(sum, M.trace(), 1e-12 * scale);
      if (d == 2) EXPECT_EQ(pr->GetComponent(i, 2), 0.0);
    }
  }
  EXPECT_EQ(g->GetPointData()->GetNumberOfArrays(), expectedArrays);
}

class OutputDim : public ::testing::TestWithParam<int> {};

TEST_P(OutputDim, SnapshotRoundTripThroughVtkReader) {
  const int d = GetParam();
  auto sim = makeStore(d, 37);
  sim->time = 1.25e-3;
  sim->step = 12;
  OutputWriter out(freshDir("roundtrip" + std::to_string(d)));
  const std::string file = out.writeSnapshot(*sim);
  EXPECT_TRUE(fs::exists(file));
  EXPECT_NE(file.find("snapshots/step_00000012.vtu"), std::string::npos);
  // binary appended data, zlib-compressed
  const std::string text = slurp(file);
  EXPECT_NE(text.find("vtkZLibDataCompressor"), std::string::npos);
  EXPECT_NE(text.find("<AppendedData encoding=\"raw\">"), std::string::npos);
  compareSnapshot(*sim, file);
}

INSTANTIATE_TEST_SUITE_P(Dimensions, OutputDim, ::testing::Values(1, 2, 3));

TEST(Output, EmptyStoreGivesAValidEmptySnapshot) {
  auto sim = makeStore(3, 0);
  OutputWriter out(freshDir("empty"));
  const std::string file = out.writeSnapshot(*sim);
  compareSnapshot(*sim, file);
}

TEST(Output, GhostsAreNotWritten) {
  auto sim = makeStore(2, 10);
  sim->store.addGhosts({0, 1}, {1.0, 0.0, 1.0, 0.0});
  OutputWriter out(freshDir("ghosts"));
  const std::string file = out.writeSnapshot(*sim);
  vtkNew<vtkXMLUnstructuredGridReader> reader;
  reader->SetFileName(file.c_str());
  reader->Update();
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 10);
}

TEST(Output, PvdListsEverySnapshotWithItsTime) {
  auto sim = makeStore(2, 5);
  const std::string dir = freshDir("pvd");
  OutputWriter out(dir);
  const double times[3] = {0.0, 0.1, 0.30000000000000004};
  for (int k = 0; k < 3; ++k) {
    sim->time = times[k];
    sim->step = 100 * k;
    out.writeSnapshot(*sim);
    // valid after every snapshot: the collection lists exactly the files so far
    const std::string pvd = slurp(dir + "/results.pvd");
    EXPECT_NE(pvd.find("type=\"Collection\""), std::string::npos);
    EXPECT_NE(pvd.find("</VTKFile>"), std::string::npos);
    size_t count = 0;
    for (size_t p = pvd.find("<DataSet"); p != std::string::npos; p = pvd.find("<DataSet", p + 1))
      ++count;
    EXPECT_EQ(count, static_cast<size_t>(k + 1));
  }
  const std::string pvd = slurp(dir + "/results.pvd");
  EXPECT_NE(pvd.find("timestep=\"0\" group=\"\" part=\"0\" file=\"snapshots/step_00000000.vtu\""),
            std::string::npos);
  EXPECT_NE(pvd.find("timestep=\"0.10000000000000001\" group=\"\" part=\"0\" "
                     "file=\"snapshots/step_00000100.vtu\""),
            std::string::npos);
  EXPECT_NE(pvd.find("timestep=\"0.30000000000000004\" group=\"\" part=\"0\" "
                     "file=\"snapshots/step_00000200.vtu\""),
            std::string::npos);
  for (const auto& [t, f] : out.snapshots()) EXPECT_TRUE(fs::exists(fs::path(dir) / f));
  EXPECT_FALSE(fs::exists(fs::path(dir) / "results.pvd.tmp"));
  // rewriting the same step replaces its entry
  out.writeSnapshot(*sim);
  EXPECT_EQ(out.snapshots().size(), 3u);
}

TEST(Output, TimeseriesHeaderOnceThenRows) {
  auto sim = makeStore(2, 4);
  auto mod = std::make_unique<ColumnsModule>();
  ColumnsModule* cols = mod.get();
  sim->addModule(std::move(mod));
  const std::string dir = freshDir("csv");
  OutputWriter out(dir);
  for (int k = 0; k < 3; ++k) {
    sim->time = 0.5 * k;
    sim->step = k;
    sim->dt = 0.5;
    out.appendTimeseries(*sim);
  }
  std::ifstream f(dir + "/timeseries.csv");
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(f, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "time,step,dt,kinetic_energy,answer");
  EXPECT_EQ(lines[1].substr(0, 8), "0,0,0.5,");
  EXPECT_EQ(lines[3].substr(0, 8), "1,2,0.5,");
  EXPECT_NE(lines[3].find(",43"), std::string::npos);
  // kinetic energy column equals Simulation::kineticEnergy()
  std::stringstream ss(lines[3]);
  std::string cell;
  for (int k = 0; k < 4; ++k) std::getline(ss, cell, ',');
  EXPECT_DOUBLE_EQ(std::stod(cell), sim->kineticEnergy());
  // a changed column set is an error
  cols->extra = true;
  EXPECT_THROW(out.appendTimeseries(*sim), std::runtime_error);
}

TEST(Output, RestartContinuesPvdAndCsvFreshRunReplacesThem) {
  auto sim = makeStore(2, 3);
  const std::string dir = freshDir("restart");
  {
    OutputWriter out(dir);
    for (int k = 0; k <= 4; ++k) {  // t = 0, 0.1, ..., 0.4
      sim->time = 0.1 * k;
      sim->step = 10 * k;
      out.writeSnapshot(*sim);
      out.appendTimeseries(*sim);
    }
  }
  auto countLines = [](const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
    return n;
  };
  {  // restart from the checkpoint at t = 0.2 (step 20): entries at t >= 0.2 are replaced
    OutputWriter out(dir);
    sim->time = 0.2;
    sim->step = 20;
    out.writeSnapshot(*sim);
    out.appendTimeseries(*sim);
    sim->time = 0.25;
    sim->step = 25;
    out.writeSnapshot(*sim);
    out.appendTimeseries(*sim);
    const std::string pvd = slurp(dir + "/results.pvd");
    EXPECT_EQ(countLines(pvd, "<DataSet"), 4u);  // 0, 0.1, 0.2, 0.25
    EXPECT_NE(pvd.find("step_00000010.vtu"), std::string::npos);
    EXPECT_NE(pvd.find("step_00000025.vtu"), std::string::npos);
    EXPECT_EQ(pvd.find("step_00000030.vtu"), std::string::npos);
    const std::string csv = slurp(dir + "/timeseries.csv");
    EXPECT_EQ(countLines(csv, "\n"), 5u);  // header + t = 0, 0.1, 0.2, 0.25
    EXPECT_EQ(countLines(csv, "time,"), 1u);
  }
  {  // a fresh run in the same directory starts both anew
    OutputWriter out(dir);
    sim->time = 0.0;
    sim->step = 0;
    out.writeSnapshot(*sim);
    out.appendTimeseries(*sim);
    EXPECT_EQ(countLines(slurp(dir + "/results.pvd"), "<DataSet"), 1u);
    EXPECT_EQ(countLines(slurp(dir + "/timeseries.csv"), "\n"), 2u);
  }
}

TEST(Output, UnwritableDirectoryIsAnInputError) {
  const std::string file = freshDir("blocker");
  fs::create_directories(fs::path(file).parent_path());
  std::ofstream(file) << "x";  // a file where the directory should be
  EXPECT_THROW(OutputWriter{file + "/sub"}, InputError);
}

}  // namespace
