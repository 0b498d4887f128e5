// Validation: capillary entry into a slit between elastic walls (issue 11 item 5; label
// validation_long, ~40 s CPU per run on one core). samples/coupling_elastic_slit_entry.yaml, set-up and
// closed forms in coupling_slit_entry_case.hpp and docs/coupling.md "Gas entry between elastic
// walls". A body force f along the periodic loop drives the gas against the Young-Laplace
// threshold f* of the slit (Eq. 1.10 contact angle); the blocks forming the slit are clay on
// rollers, so the water's pressure opens the slit by delta and lowers the threshold to
// f*_el = f* (1/(w + delta) - 1/H) / (1/w - 1/H). Criteria of the fixed-wall test
// (test_fluid_capillary_entry.cpp): gas front past the entrance < 0.5 w and advancing < 0.1 w
// over the second half below the threshold, > 0.6 w and advancing > 0.15 w above it. The opening
// (time mean over the last third, wet rows) against the estimate at the face and end pressures
// the fluids put on the blocks, y (1 + nu)((1 - nu) p_face - nu p_ends) / E per block
// (coupling_slit_entry_case.hpp: exact by Betti's theorem for the mean of the wet face).
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <vector>

#include "tests/support/validation_record.hpp"
#include "tests/validation/coupling_slit_entry_case.hpp"

using namespace poresph;
namespace se = poresph::slitentry;

namespace {

struct EntryRun {
  double frontHalf = 0, frontEnd = 0;  ///< gas front past the entrance / w at T/2 and T
  double opening = 0, estimate = 0;     ///< time means over the last third
  double pFace = 0, pEnds = 0;          ///< mean face / weighted end pressures, last third
  double pLeft = 0, pRight = 0;         ///< the ends' mean pressures, last third
  double modeAmplitude = 0;  ///< rows 1-8 of the lower block: largest deviation from their line
  double wetRowLag = 0;      ///< wet row / the rows' line carried on to it - 1
  double cpu = 0;
  long long steps = 0;
};

EntryRun runEntry(double ratio, bool fixedWalls, const std::string& model = "extrapolated") {
  test::Stopwatch clock;
  Scene s = loadSceneText(se::entryScene(ratio, fixedWalls, model), "coupling_elastic_slit_entry.yaml");
  Simulation& sim = *s.sim;
  auto integrator = makeIntegrator("leapfrog");
  const int gas = se::materialId(sim, "gas");
  const double T = s.endTime;
  EntryRun r;
  long n = 0;
  int k = 1;
  double nextSample = 0.0;
  // The lower block's rows (reference Y, 10 rows of dx) in the slit's x range: time means of u_y
  // and of -sigma_yy, -sigma_xx per row over the last third. Study hook SLIT_ENTRY_ROWS=1 prints
  // them, with the fluid's force on the block and the gap to the first fluid row.
  const bool rows = std::getenv("SLIT_ENTRY_ROWS") != nullptr;
  std::vector<double> rowU(10, 0.0), rowSyy(10, 0.0), rowSxx(10, 0.0);
  std::vector<long> rowN(10, 0);
  std::vector<double> rowF(10, 0.0);  // the pairs' y force on each row (face middle), per length
  double forceMid = 0.0, forceAll = 0.0, gapSum = 0.0;
  long gapN = 0;
  while (!s.finished()) {
    integrator->step(sim, s.nextTimeStep());
    if (sim.time >= 2.0 / 3.0 * T && sim.time >= nextSample) {  // every 0.2 ms
      ParticleStore& ps = sim.store;
      const Index nn = ps.realCount();
      const std::int32_t* ph = ps.data(ps.phase());
      const double* xc = ps.data(ps.position());
      const double* X = ps.has("reference_position") ? ps.data(ps.real("reference_position")) : nullptr;
      if (X) {
        const double* sg = ps.data(ps.real("stress"));
        for (Index i = 0; i < nn; ++i) {
          if (ph[i] != kPhaseSolid || X[2 * i] < se::kXs || X[2 * i] > se::kXs + se::kLs) continue;
          const int row = static_cast<int>(std::floor(X[2 * i + 1] / sim.spacing));
          if (row < 0 || row >= 10) continue;
          rowU[static_cast<size_t>(row)] += xc[2 * i + 1] - X[2 * i + 1];
          rowSxx[static_cast<size_t>(row)] -= sg[4 * i];
          rowSyy[static_cast<size_t>(row)] -= sg[4 * i + 3];
          ++rowN[static_cast<size_t>(row)];
        }
      }
      Module* coupling = sim.module("coupling");
      if (rows && X && coupling) {
        // The fluid's force on the lower block (the coupling's stage re-run on this state, the
        // store's rates put back): y over the face's middle (0.3 mm from the ends) per unit
        // length, and over the whole block (ends and corners included) per unit length.
        double* acc = ps.data(sim.acceleration);
        std::vector<double> accSaved(acc, acc + 2 * nn);
        std::vector<std::vector<double>> saved;
        for (const IntegratedField& f : sim.integrated) {
          const double* rr = ps.data(f.rate);
          saved.emplace_back(rr, rr + nn * ps.components(f.rate.id));
        }
        std::fill(acc, acc + 2 * nn, 0.0);
        coupling->interfaces(sim);
        const double* m = ps.data(ps.mass());
        double mid = 0.0, all = 0.0;
        for (Index i = 0; i < nn; ++i) {
          if (ph[i] != kPhaseSolid || X[2 * i + 1] > 0.5 * (se::kH - se::kW)) continue;
          if (X[2 * i] < se::kXs || X[2 * i] > se::kXs + se::kLs) continue;
          const double fy = m[i] * acc[2 * i + 1];
          all += fy;
          if (X[2 * i] > se::kXs + 3e-4 && X[2 * i] < se::kXs + se::kLs - 3e-4) {
            mid += fy;
            const int row = static_cast<int>(std::floor(X[2 * i + 1] / sim.spacing));
            if (row >= 0 && row < 10) rowF[static_cast<size_t>(row)] -= fy / (se::kLs - 6e-4);
          }
        }
        // The gap between the lower block's wet row and the first fluid row above it (face
        // middle): dx on a lattice continued across the face.
        double yS = 0.0, yF = 0.0;
        long nS = 0, nF = 0;
        const double face = 0.5 * (se::kH - se::kW), dxs = sim.spacing;
        for (Index i = 0; i < nn; ++i) {
          if (xc[2 * i] < se::kXs + 3e-4 || xc[2 * i] > se::kXs + se::kLs - 3e-4) continue;
          if (ph[i] == kPhaseSolid && X[2 * i + 1] < face && X[2 * i + 1] > face - dxs)
            yS += xc[2 * i + 1], ++nS;
          if (ph[i] == kPhaseFluid && xc[2 * i + 1] > face && xc[2 * i + 1] < face + dxs)
            yF += xc[2 * i + 1], ++nF;
        }
        if (nS > 0 && nF > 0) gapSum += (yF / nF - yS / nS) / dxs, ++gapN;
        forceMid += -mid / (se::kLs - 6e-4);
        forceAll += -all / se::kLs;
        std::copy(accSaved.begin(), accSaved.end(), acc);
        for (size_t q = 0; q < sim.integrated.size(); ++q)
          std::copy(saved[q].begin(), saved[q].end(), ps.data(sim.integrated[q].rate));
      }
      const se::SlitState st = se::readSlit(sim);
      r.opening += st.opening(), r.estimate += st.estimate();
      r.pFace += 0.5 * (st.pFaceLow + st.pFaceHigh), r.pEnds += 0.5 * (st.pEndsLow + st.pEndsHigh);
      r.pLeft += st.pLeft, r.pRight += st.pRight;
      ++n;
      nextSample = sim.time + 2e-4;
    }
    if (sim.time >= T * k / 8 - 1e-12) {
      const se::SlitState st = se::readSlit(sim);
      const double f = se::gasFront(sim, gas) / se::kW;
      if (k == 4) r.frontHalf = f;
      std::printf("  %s %.2f f*: t = %.3f s, front %.3f w, opening %.3e m (estimate %.3e), p face %.1f / "
                  "%.1f, ends %.1f / %.1f Pa\n",
                  fixedWalls ? "fixed" : model.c_str(), ratio, sim.time, f, st.opening(), st.estimate(),
                  st.pFaceLow, st.pFaceHigh, st.pEndsLow, st.pEndsHigh);
      ++k;
    }
  }
  r.frontEnd = se::gasFront(sim, gas) / se::kW;
  if (rows && n > 0)
    std::printf("  lower block: fluid's y-force per unit length, face middle %.2f Pa, whole block %.2f Pa "
                "(face pressure %.2f Pa); first fluid row above the wet row by %.4f dx\n", forceMid / n,
                forceAll / n, r.pFace / n, gapN > 0 ? gapSum / gapN : 0.0);
  for (int row = 0; rows && row < 10; ++row)
    std::printf("  row Y = %.2f mm: u_y %+.3f um, -sigma_yy %.2f Pa, -sigma_xx %.2f Pa, pairs' y force "
                "(face middle) %.4f of the total\n",
                (row + 0.5) * sim.spacing * 1e3, 1e6 * rowU[row] / rowN[row], rowSyy[row] / rowN[row],
                rowSxx[row] / rowN[row], forceMid != 0.0 ? rowF[row] / forceMid : 0.0);
  // The odd-even mode: the largest deviation of the rows 1-8 (reference Y = 0.05 ... 0.75 mm) from
  // their least-squares line, and the wet row (Y = 0.95 mm) against that line carried on to it,
  // both relative to the line's value at the wet row.
  if (!fixedWalls) {
    double sy = 0, su = 0, syy = 0, syu = 0;
    const size_t m = 8;
    std::vector<double> u(10), y(10);
    for (int row = 0; row < 10; ++row) {
      u[static_cast<size_t>(row)] = rowN[static_cast<size_t>(row)] > 0 ? rowU[static_cast<size_t>(row)] / rowN[static_cast<size_t>(row)] : 0.0;
      y[static_cast<size_t>(row)] = (row + 0.5) * sim.spacing;
    }
    for (size_t q = 0; q < m; ++q) sy += y[q], su += u[q], syy += y[q] * y[q], syu += y[q] * u[q];
    const double slope = (m * syu - sy * su) / (m * syy - sy * sy), icpt = (su - slope * sy) / m;
    const double atWet = slope * y[9] + icpt;
    for (size_t q = 0; q < m; ++q)
      r.modeAmplitude = std::max(r.modeAmplitude, std::abs(u[q] - slope * y[q] - icpt) / std::abs(atWet));
    r.wetRowLag = u[9] / atWet - 1.0;
    std::printf("  rows: odd-even amplitude %.4f of the line at the wet row; wet row against the line "
                "%+.4f\n", r.modeAmplitude, r.wetRowLag);
  }
  if (n > 0) r.opening /= n, r.estimate /= n, r.pFace /= n, r.pEnds /= n, r.pLeft /= n, r.pRight /= n;
  r.cpu = clock.seconds();
  r.steps = sim.step;
  std::printf("  %s %.2f f*: front %.3f w at T/2, %.3f w at T; opening %.4e m, estimate %.4e m "
              "(%.2f %%), p face %.2f, ends %.2f (left %.2f, right %.2f) Pa; face opening %.4e m; "
              "f*_el / f* = %.4f; %lld steps, %.1f s\n",
              fixedWalls ? "fixed" : model.c_str(), ratio, r.frontHalf, r.frontEnd, r.opening, r.estimate,
              r.estimate != 0.0 ? 100.0 * (r.opening / r.estimate - 1.0) : 0.0, r.pFace, r.pEnds, r.pLeft,
              r.pRight, r.opening * se::kT / (se::kT - 0.5e-4), se::thresholdRatio(r.opening * se::kT / (se::kT - 0.5e-4)),
              r.steps, r.cpu);
  return r;
}

const char* kRes = "2D, dx = 0.1 mm: slit w = 10 dx, 30 dx long, channel H = 30 dx, loop 80 dx, quintic h = dx, "
                   "clay blocks 10 dx thick on rollers (E 12 kPa), extrapolated pairs, t = 80 ms";

}  // namespace

// Below the threshold of the opened slit (0.9 f* = 0.91 f*_el) the gas stays at the entrance, and
// the blocks open the slit as the elastic estimate at the pressures the water puts on them.
TEST(CouplingSlitEntryLong, GasStaysOutBelowThresholdAndTheSlitOpensAsEstimated) {
  const EntryRun r = runEntry(0.9, false);
  EXPECT_LT(r.frontEnd, 0.5);
  EXPECT_LT(r.frontEnd - r.frontHalf, 0.1);
  // Measured (2026-11-27, clay with hourglass 1): opening 0.942 of the estimate at face 75.8 Pa,
  // ends 111.5 / 76.8 Pa (gas side / water side); with the slit's pressure on the ends too the
  // estimate would be 14 % higher (docs/coupling.md). The rows 1-8 of the block lie on a line to
  // 0.15 % of the wet row's displacement (without hourglass control an odd-even mode of the rows,
  // driven by the pair forces, reached 12.9 %); the wet row lags that line by 5.3 %: the pairs put
  // 0.93 / 0.07 of the traction on the first two solid rows where the TL solid's truncated
  // divergence needs 1.42 / -0.35 / -0.07 to carry a uniform stress to its surface (the
  // consistent load of the blocks-alone test), so the surface layer is under-compressed.
  const double err = std::abs(r.opening / r.estimate - 1.0);
  EXPECT_LT(err, 0.10);
  EXPECT_GT(r.opening, 0.0);
  EXPECT_LT(r.modeAmplitude, 0.01);
  test::recordValidation({"coupling_slit_entry", "odd-even mode of the block's rows at 0.90 f* (largest deviation from their line / wet-row displacement)",
                          r.modeAmplitude, 0.0, r.modeAmplitude, kRes, r.cpu, "< 1 % (hourglass 0: 12.9 %)",
                          "rows linear in Y (uniform strain)"});
  const double fel = se::thresholdRatio(r.opening * se::kT / (se::kT - 0.5e-4));
  test::recordValidation({"coupling_slit_entry", "gas front past the entrance / w at f = 0.90 f* (stays out)",
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.cpu,
                          "< 0.5 w and advance over the second half < 0.1 w",
                          "Young-Laplace entry of the opened slit, f*_el = " + std::to_string(fel) + " f*"});
  test::recordValidation({"coupling_slit_entry", "opening of the slit at 0.90 f* (water pressure on the blocks)",
                          r.opening, r.estimate, err, kRes, r.cpu, "< 10 %",
                          "block on a roller: t (1 + nu)((1 - nu) p_face - nu p_ends) / E (Betti) at the measured pressures"});
}

TEST(CouplingSlitEntryLong, GasEntersAboveThreshold) {
  const EntryRun r = runEntry(1.1, false);
  EXPECT_GT(r.frontEnd, 0.6);
  EXPECT_GT(r.frontEnd - r.frontHalf, 0.15);
  test::recordValidation({"coupling_slit_entry", "gas front past the entrance / w at f = 1.10 f* (enters)",
                          r.frontEnd, 0.0, r.frontEnd, kRes, r.cpu,
                          "> 0.6 w and advance over the second half > 0.15 w",
                          "Young-Laplace entry of the opened slit (f*_el ~ 0.99 f*)"});
}

// Manual bracket (docs/coupling.md): SLIT_ENTRY_RATIO=1.05 [SLIT_ENTRY_FIXED=1]
// [SLIT_ENTRY_MODEL=mirror] ctest -R CouplingSlitEntryLong.Probe -V
TEST(CouplingSlitEntryLong, Probe) {
  const char* ratio = std::getenv("SLIT_ENTRY_RATIO");
  if (!ratio) GTEST_SKIP() << "set SLIT_ENTRY_RATIO";
  const char* model = std::getenv("SLIT_ENTRY_MODEL");
  runEntry(std::atof(ratio), std::getenv("SLIT_ENTRY_FIXED") != nullptr, model ? model : "extrapolated");
}
