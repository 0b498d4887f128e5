#pragma once
// Run output (docs/output.md):
//   <dir>/snapshots/step_XXXXXXXX.vtu  VTK XML unstructured grid, one VTK_VERTEX cell per real
//                                      particle, binary appended data, zlib-compressed; every
//                                      field flagged kFieldOutput (vectors padded to 3
//                                      components, D x D tensors padded to 3 x 3 = 9 components,
//                                      int fields as vtkIntArray)
//   <dir>/results.pvd                  ParaView collection of the snapshots with their times,
//                                      rewritten after every snapshot (always valid)
//   <dir>/timeseries.csv               one row per call with the columns of sim.diagnostics()
#include <string>
#include <utility>
#include <vector>

namespace poresph {

class Simulation;

class OutputWriter {
 public:
  /// Creates <dir> and <dir>/snapshots if needed (InputError if that fails). Existing
  /// results.pvd / timeseries.csv in <dir> are rewritten by the first write, keeping only their
  /// entries/rows with a time earlier than the simulation's at that write: a fresh run (t = 0)
  /// starts them anew, a run restarted from a checkpoint continues them.
  explicit OutputWriter(std::string dir);

  /// Writes <dir>/snapshots/step_XXXXXXXX.vtu (XXXXXXXX = sim.step) and rewrites results.pvd.
  /// Returns the path of the .vtu written.
  std::string writeSnapshot(const Simulation& sim);
  /// Appends one row of sim.diagnostics() to <dir>/timeseries.csv (header written by the first
  /// call). A column set different from the header's throws std::runtime_error.
  void appendTimeseries(const Simulation& sim);

  const std::string& directory() const { return dir_; }
  /// (time, relative .vtu path) of every snapshot written so far.
  const std::vector<std::pair<double, std::string>>& snapshots() const { return snapshots_; }

 private:
  void writePvd() const;

  std::string dir_;
  std::vector<std::pair<double, std::string>> snapshots_;
  std::vector<std::string> columns_;
  bool pvdStarted_ = false;
};

}  // namespace poresph
