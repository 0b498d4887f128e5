// VTK XML snapshots, the ParaView collection and timeseries.csv (see libcore/output.hpp and
// docs/output.md).
#include "libcore/output.hpp"

#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "libcore/simulation.hpp"

namespace poresph {

namespace fs = std::filesystem;

namespace {

std::string formatDouble(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// How a real field of `c` components is laid out in VTK for dimension d.
enum class Shape { Scalar, Vector, Tensor, Other };

Shape shapeOf(const FieldSpec& s, int d) {
  const int c = s.components;
  if (d == 1) {
    // In 1D a vector and a scalar both have one component: the core vectors are padded.
    if (s.name == "velocity" || s.name == "acceleration" || s.name == "position")
      return Shape::Vector;
    return c == 1 ? Shape::Scalar : Shape::Other;
  }
  if (c == 1) return Shape::Scalar;
  if (c == d) return Shape::Vector;
  if (c == d * d) return Shape::Tensor;
  return Shape::Other;
}

}  // namespace

OutputWriter::OutputWriter(std::string dir) : dir_(std::move(dir)) {
  std::error_code ec;
  fs::create_directories(fs::path(dir_) / "snapshots", ec);
  if (ec)
    throw InputError("output directory '" + dir_ + "': cannot create it (" + ec.message() + ")");
}

std::string OutputWriter::writeSnapshot(const Simulation& sim) {
  const ParticleStore& s = sim.store;
  const int d = sim.dimension();
  const Index n = s.realCount();

  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkDoubleArray> coords;
  coords->SetNumberOfComponents(3);
  coords->SetNumberOfTuples(n);
  {
    const double* r = s.data(s.position());
    double* p = coords->GetPointer(0);
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i)
      for (int a = 0; a < 3; ++a) p[3 * i + a] = a < d ? r[i * d + a] : 0.0;
  }
  vtkNew<vtkPoints> points;
  points->SetData(coords);
  grid->SetPoints(points);

  // one VTK_VERTEX cell per particle
  vtkNew<vtkIdTypeArray> offsets;
  vtkNew<vtkIdTypeArray> connectivity;
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  for (Index i = 0; i < n; ++i) {
    offsets->SetValue(i, i);
    connectivity->SetValue(i, i);
  }
  offsets->SetValue(n, n);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  grid->SetCells(VTK_VERTEX, cells);

  for (size_t k = 0; k < s.fields().size(); ++k) {
    const FieldSpec& spec = s.fields()[k];
    if (!(spec.flags & kFieldOutput) || spec.name == "position") continue;
    const int id = static_cast<int>(k);
    const int c = spec.components;
    if (spec.type == FieldType::Int) {
      vtkNew<vtkIntArray> arr;
      arr->SetName(spec.name.c_str());
      arr->SetNumberOfComponents(c);
      arr->SetNumberOfTuples(n);
      const std::int32_t* src = s.data(IntField{id});
      int* dst = arr->GetPointer(0);
      for (Index q = 0; q < n * c; ++q) dst[q] = src[q];
      grid->GetPointData()->AddArray(arr);
      continue;
    }
    const Shape shape = shapeOf(spec, d);
    const int out = shape == Shape::Vector ? 3 : shape == Shape::Tensor ? 9 : c;
    vtkNew<vtkDoubleArray> arr;
    arr->SetName(spec.name.c_str());
    arr->SetNumberOfComponents(out);
    arr->SetNumberOfTuples(n);
    const double* src = s.data(RealField{id});
    double* dst = arr->GetPointer(0);
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      double* o = dst + out * i;
      const double* in = src + static_cast<Index>(c) * i;
      switch (shape) {
        case Shape::Vector:
          for (int a = 0; a < 3; ++a) o[a] = a < c ? in[a] : 0.0;
          break;
        case Shape::Tensor:  // store: column-major D x D; VTK: row-major 3 x 3
          for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b) o[3 * a + b] = (a < d && b < d) ? in[a + d * b] : 0.0;
          break;
        default:
          for (int q = 0; q < c; ++q) o[q] = in[q];
      }
    }
    grid->GetPointData()->AddArray(arr);
    // Principal values of a stress tensor (descending, of its symmetric part; 0 for particles
    // without stress, e.g. fluids): what damage criteria and crack pictures read (Table 5.1's
    // Rankine on the largest), so ParaView needs no calculator. Written for every D x D field
    // named "stress" (the solid's Cauchy stress).
    if (shape == Shape::Tensor && spec.name == "stress") {
      vtkNew<vtkDoubleArray> principal;
      principal->SetName("principal_stress");
      principal->SetNumberOfComponents(3);
      principal->SetNumberOfTuples(n);
      double* pr = principal->GetPointer(0);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        const double* in = src + static_cast<Index>(c) * i;
        Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
        for (int a = 0; a < d; ++a)
          for (int b = 0; b < d; ++b) M(a, b) = 0.5 * (in[a + d * b] + in[b + d * a]);
        Eigen::Vector3d ev = Eigen::Vector3d::Zero();  // 1D: sigma_xx; 2D: the in-plane pair
        if (d == 1) {
          ev[0] = M(0, 0);
        } else if (d == 2) {
          const double mid = 0.5 * (M(0, 0) + M(1, 1));
          const double rad = std::hypot(0.5 * (M(0, 0) - M(1, 1)), M(0, 1));
          ev = Eigen::Vector3d(mid + rad, mid - rad, 0.0);
        } else {
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
          es.computeDirect(M, Eigen::EigenvaluesOnly);
          ev = es.eigenvalues().reverse();  // descending
        }
        for (int a = 0; a < 3; ++a) pr[3 * i + a] = ev[a];
      }
      grid->GetPointData()->AddArray(principal);
    }
  }

  // TimeValue: ParaView shows it as the time of a single file
  vtkNew<vtkDoubleArray> timeValue;
  timeValue->SetName("TimeValue");
  timeValue->InsertNextValue(sim.time);
  grid->GetFieldData()->AddArray(timeValue);

  char name[64];
  std::snprintf(name, sizeof name, "step_%08lld.vtu", static_cast<long long>(sim.step));
  const std::string rel = std::string("snapshots/") + name;
  const std::string path = (fs::path(dir_) / rel).string();
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->SetFileName(path.c_str());
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->EncodeAppendedDataOff();  // raw binary
  writer->SetCompressorTypeToZLib();
  writer->SetHeaderTypeToUInt64();
  if (writer->Write() != 1) throw std::runtime_error("cannot write snapshot '" + path + "'");

  if (!pvdStarted_) {
    // A restarted run continues the collection: keep the earlier entries (time < now) whose
    // files still exist; a fresh run (time 0) drops them all.
    pvdStarted_ = true;
    std::ifstream old(fs::path(dir_) / "results.pvd");
    std::string line;
    while (std::getline(old, line)) {
      const size_t ts = line.find("timestep=\""), fi = line.find("file=\"");
      if (line.find("<DataSet") == std::string::npos || ts == std::string::npos ||
          fi == std::string::npos)
        continue;
      const size_t tsEnd = line.find('"', ts + 10), fiEnd = line.find('"', fi + 6);
      if (tsEnd == std::string::npos || fiEnd == std::string::npos) continue;
      try {
        const double t = std::stod(line.substr(ts + 10, tsEnd - ts - 10));
        const std::string f = line.substr(fi + 6, fiEnd - fi - 6);
        if (t < sim.time && f != rel && fs::exists(fs::path(dir_) / f))
          snapshots_.emplace_back(t, f);
      } catch (const std::exception&) {
      }
    }
  }
  // a rewrite of the same step (e.g. final snapshot) replaces the entry
  if (!snapshots_.empty() && snapshots_.back().second == rel) snapshots_.pop_back();
  snapshots_.emplace_back(sim.time, rel);
  writePvd();
  return path;
}

void OutputWriter::writePvd() const {
  const fs::path final = fs::path(dir_) / "results.pvd";
  const fs::path tmp = fs::path(dir_) / "results.pvd.tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write '" + tmp.string() + "'");
    f << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <Collection>\n";
    for (const auto& [t, file] : snapshots_)
      f << "    <DataSet timestep=\"" << formatDouble(t) << "\" group=\"\" part=\"0\" file=\""
        << file << "\"/>\n";
    f << "  </Collection>\n</VTKFile>\n";
    if (!f) throw std::runtime_error("cannot write '" + tmp.string() + "'");
  }
  std::error_code ec;
  fs::rename(tmp, final, ec);  // atomic: a run that dies still leaves a valid .pvd
  if (ec) throw std::runtime_error("cannot write '" + final.string() + "': " + ec.message());
}

void OutputWriter::appendTimeseries(const Simulation& sim) {
  const auto cols = sim.diagnostics();
  const fs::path path = fs::path(dir_) / "timeseries.csv";
  std::ofstream f;
  if (columns_.empty()) {
    for (const auto& c : cols) columns_.push_back(c.first);
    std::string header;
    for (size_t k = 0; k < columns_.size(); ++k) header += (k ? "," : "") + columns_[k];
    // A restarted run continues an existing file with the same header: rows with an earlier
    // time are kept, later ones (written after the checkpoint) dropped.
    std::vector<std::string> keep;
    {
      std::ifstream old(path);
      std::string line;
      if (std::getline(old, line) && line == header)
        while (std::getline(old, line)) {
          try {
            if (!line.empty() && std::stod(line.substr(0, line.find(','))) < sim.time)
              keep.push_back(line);
          } catch (const std::exception&) {
          }
        }
    }
    f.open(path, std::ios::trunc);
    if (!f) throw std::runtime_error("cannot write '" + path.string() + "'");
    f << header << "\n";
    for (const auto& row : keep) f << row << "\n";
  } else {
    bool same = cols.size() == columns_.size();
    for (size_t k = 0; same && k < cols.size(); ++k) same = cols[k].first == columns_[k];
    if (!same) {
      std::string got;
      for (const auto& c : cols) got += (got.empty() ? "" : ",") + c.first;
      throw std::runtime_error("timeseries '" + path.string() +
                               "': the diagnostic columns changed during the run (now: " + got +
                               ")");
    }
    f.open(path, std::ios::app);
    if (!f) throw std::runtime_error("cannot append to '" + path.string() + "'");
  }
  for (size_t k = 0; k < cols.size(); ++k) f << (k ? "," : "") << formatDouble(cols[k].second);
  f << "\n";
}

}  // namespace poresph
