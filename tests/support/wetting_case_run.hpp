#pragma once
// Pieces the wetting cases share (tests/validation/fluid_wetting_case.hpp, _3d_case, _curved_case,
// _moving_case): the end-state dump, the statistics of a reading sampled over a time window, and
// the run's cost. Written once here so the four runners differ only in their scenes and readings.
#include <algorithm>
#include <cstdint>
#include <ctime>
#include <fstream>
#include <string>

#include "libcore/simulation.hpp"
#include "tests/support/validation_record.hpp"

namespace poresph::test {

/// Writes <build>/name, one line per real particle: its coordinates and code(material id),
/// separated by single spaces (read by scripts/plot_wetting_dumps.py and plot_sessile_3d_cut.py).
template <class Code>
void dumpParticles(const Simulation& sim, const std::string& name, Code code) {
  const auto& st = sim.store;
  std::ofstream f(std::string(PORESPH_BINARY_DIR) + "/" + name);
  const int D = sim.dimension();
  const double* x = st.data(st.position());
  const std::int32_t* mt = st.data(st.material());
  for (Index i = 0; i < st.realCount(); ++i) {
    for (int d = 0; d < D; ++d) f << x[D * i + d] << " ";
    f << code(mt[i]) << "\n";
  }
}

/// Mean and extremes of the samples of a reading.
struct WindowMean {
  double mean = 0, lo = 1e300, hi = -1e300;
  int samples = 0;
  void add(double a) {
    mean += a;
    lo = std::min(lo, a);
    hi = std::max(hi, a);
    ++samples;
  }
};

/// The window of the wetting tests: runTo(t) at t = t1, t1 + every, ... up to tEnd, read() after
/// each; returns the samples' mean (sum / count), smallest and largest.
template <class RunTo, class Read>
WindowMean sampleWindow(double t1, double tEnd, double every, RunTo runTo, Read read) {
  WindowMean w;
  for (double t = t1; t <= tEnd * (1 + 1e-9); t += every) {
    runTo(t);
    w.add(read(t));
  }
  w.mean /= w.samples;
  return w;
}

/// Wall and CPU time from construction; finish() fills a result's steps, particles, wall and cpu.
struct RunCost {
  Stopwatch clock;
  std::clock_t c0 = std::clock();
  template <class Result>
  void finish(const Simulation& sim, Result& r) const {
    r.steps = static_cast<long long>(sim.step);
    r.particles = static_cast<long long>(sim.store.realCount());
    r.wall = clock.seconds();
    r.cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  }
};

}  // namespace poresph::test
