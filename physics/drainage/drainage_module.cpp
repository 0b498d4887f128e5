#include "physics/drainage/drainage_module.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

#include "libcore/phases.hpp"
#include "libcore/simulation.hpp"
#include "libcore/time_schedule.hpp"

namespace poresph {

namespace {

int materialId(const Simulation& sim, const ParameterSet& s, const std::string& key) {
  const std::string name = s.string(key);
  std::vector<std::string> fluids;
  for (const Material& m : sim.materials) {
    if (m.phase == kPhaseFluid) fluids.push_back(m.name);
    if (m.name != name) continue;
    if (m.phase != kPhaseFluid)
      s.fail(key, "material '" + name + "' is a " + phaseName(m.phase) +
                      " material; the invading and defending phases must be fluids");
    return m.id;
  }
  std::string known;
  for (const auto& f : fluids) known += (known.empty() ? "'" : ", '") + f + "'";
  const std::string close = closestMatch(name, fluids);
  s.fail(key, "no material is named '" + name + "'" +
                  (close.empty() ? " (fluid materials: " + (known.empty() ? "none" : known) + ")"
                                 : " (did you mean '" + close + "'?)"));
}

/// Eqs. 5.11a-5.14a for one set of parameters; NaN where an input is missing or zero.
struct DimensionlessNumbers {
  double bond, capillary, viscosityRatio, reynolds;
};
template <class P>
DimensionlessNumbers numbersOf(const P& p) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto ok = [](double v) { return std::isfinite(v) && v > 0.0; };
  DimensionlessNumbers n{nan, nan, nan, nan};
  if (ok(p.surfaceTension) && ok(p.poreSize) && std::isfinite(p.gravity))
    n.bond = std::abs(p.defendingDensity - p.invadingDensity) * p.gravity * p.poreSize *
             p.poreSize / p.surfaceTension;  // 5.11a
  if (ok(p.surfaceTension) && std::isfinite(p.invadingViscosity) && std::isfinite(p.velocity))
    n.capillary = p.invadingViscosity * p.velocity / p.surfaceTension;  // 5.12a
  if (ok(p.defendingViscosity) && std::isfinite(p.invadingViscosity))
    n.viscosityRatio = p.invadingViscosity / p.defendingViscosity;  // 5.13a
  if (ok(p.invadingViscosity) && ok(p.poreSize) && std::isfinite(p.velocity))
    n.reynolds = p.invadingDensity * p.velocity * p.poreSize / p.invadingViscosity;  // 5.14a
  return n;
}

std::string number(double v) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream o;
  o.precision(3);
  o << v;
  return o.str();
}

std::int64_t find(std::vector<std::int64_t>& p, std::int64_t i) {
  while (p[static_cast<size_t>(i)] != i) {
    p[static_cast<size_t>(i)] = p[static_cast<size_t>(p[static_cast<size_t>(i)])];
    i = p[static_cast<size_t>(i)];
  }
  return i;
}

}  // namespace

void DrainageModule::configure(Simulation& sim, const std::vector<const Material*>&,
                               const ParameterSet* section) {
  if (!section)
    throw InputError("drainage: the module needs a scene section `drainage:` (invading, "
                     "defending, sample)");
  const ParameterSet& s = *section;
  where_ = s.where("sample");
  const int d = sim.dimension();
  std::vector<std::string> axes = {"x", "y", "z"};
  axes.resize(static_cast<size_t>(d));
  const std::string axisName = s.choice("axis", axes.back(), axes);
  axisDefault_ = axes.back();
  axis_ = static_cast<int>(std::find(axes.begin(), axes.end(), axisName) - axes.begin());
  invading_ = materialId(sim, s, "invading");
  defending_ = materialId(sim, s, "defending");
  if (invading_ == defending_)
    s.fail("defending", "the defending fluid must differ from the invading one ('" +
                            sim.materials[static_cast<size_t>(invading_)].name + "')");
  const std::vector<double> slab = s.reals("sample", 2);
  sampleLo_ = slab[0];
  sampleHi_ = slab[1];
  const double lo = sim.domain.lo[static_cast<size_t>(axis_)];
  const double hi = sim.domain.hi[static_cast<size_t>(axis_)];
  if (!(sampleLo_ < sampleHi_) || sampleLo_ <= lo || sampleHi_ >= hi)
    s.fail("sample", "the sample slab [" + std::to_string(sampleLo_) + ", " +
                         std::to_string(sampleHi_) + "] along " + axisName +
                         " must be increasing and lie strictly inside the domain (" +
                         std::to_string(lo) + ", " + std::to_string(hi) +
                         "), leaving room for the reservoirs on both sides");
  // Rigid bodies are boundaries (plates) unless named as inclusions of the sample.
  inclusion_.assign(sim.materials.size(), 0);
  if (s.has("inclusions")) {
    const YAML::Node list = s.raw("inclusions");
    if (!list.IsSequence()) s.fail("inclusions", "a list of rigid material names, e.g. [quartz]");
    for (const auto& item : list) {
      const std::string name = item.as<std::string>();
      bool found = false;
      for (const Material& m : sim.materials)
        if (m.name == name) {
          if (m.phase != kPhaseRigid)
            s.fail("inclusions", "material '" + name + "' is a " + phaseName(m.phase) +
                                     " material; list rigid inclusions only (solid materials "
                                     "count as the sample's solid anyway)");
          inclusion_[static_cast<size_t>(m.id)] = 1;
          found = true;
        }
      if (!found) s.fail("inclusions", "no material is named '" + name + "'");
    }
  }
  pressureDrop_ = s.real("pressure_drop", 0.0, Range::nonNegative());
  const std::string push = s.choice("push", "negative", {"negative", "positive"});
  push_ = push;
  rampTime_ = s.real("ramp_time", 0.0, Range::nonNegative());
  linkDistance_ = s.real("link_distance", 1.5, Range::closed(1.0, 2.0));
  checkEvery_ = s.integer("percolation_every", 10, 1, 1000000);
  // A study of drainage up to breakthrough (issue 16, the thesis' numbers "at percolation")
  // need not run to an end_time guessed in advance: the run ends this long after it.
  stopAfterPercolation_ =
      s.has("stop_after_percolation") ? s.real("stop_after_percolation", Range::nonNegative()) : -1.0;
  poreSizeGiven_ = s.has("pore_size");
  poreSize_ = poreSizeGiven_ ? s.real("pore_size", Range::positive()) : 0.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  physical_ = {nan, nan, nan, nan, nan, nan, nan, nan};
  hasPhysical_ = s.has("physical");
  if (hasPhysical_) {
    // The real system's parameters (thesis Table 5.3 "physical"), for the numbers beside the
    // simulated ones; each optional, a number is printed when its inputs are given.
    const ParameterSet p = s.section("physical");
    auto get = [&](const char* key, Range r) { return p.has(key) ? p.real(key, r) : nan; };
    physical_.invadingDensity = get("invading_density", Range::positive());
    physical_.defendingDensity = get("defending_density", Range::positive());
    physical_.invadingViscosity = get("invading_viscosity", Range::positive());
    physical_.defendingViscosity = get("defending_viscosity", Range::positive());
    physical_.surfaceTension = get("surface_tension", Range::positive());
    physical_.poreSize = get("pore_size", Range::positive());
    physical_.velocity = get("velocity", Range::nonNegative());
    physical_.gravity = p.real("gravity", 9.81, Range::nonNegative());
    p.finish();
  }
  if (pressureDrop_ > 0.0 && !sim.domain.periodic[static_cast<size_t>(axis_)])
    s.fail("pressure_drop", std::to_string(pressureDrop_) +
                                ": the body-force pressure drop needs a domain periodic along "
                                "the flow axis " + axisName + " (domain.periodic)");
  // f = dP / (rho_g L_r): the gas columns of both reservoirs at rest carry dP (Sec. 5.2).
  const double reservoirs = (hi - lo) - (sampleHi_ - sampleLo_);
  const double rho = sim.materials[static_cast<size_t>(invading_)].density;
  force_ = pressureDrop_ / (rho * reservoirs) * (push == "negative" ? -1.0 : 1.0);
}

void DrainageModule::initialise(Simulation& sim) {
  parent_.assign(static_cast<size_t>(sim.store.realCount()), 0);
  // Measured once on the initial lattice (a restart keeps the value: module state).
  if (!poreSizeGiven_) poreSize_ = measurePoreSize(sim);
}

double DrainageModule::measurePoreSize(const Simulation& sim) const {
  const ParticleStore& st = sim.store;
  const NeighbourList& nl = sim.neighbours;
  const Index n = std::min<Index>(st.realCount(), nl.realCount());
  if (n == 0) return 0.0;
  const int d = sim.dimension();
  const double* x = st.data(st.position());
  const std::int32_t* ph = st.data(st.phase());
  const double dx = sim.spacing;
  const double face = 1.01 * dx * 1.01 * dx;  // lattice face neighbours: distance dx
  double fluid = 0.0, faces = 0.0;
#pragma omp parallel for schedule(static) reduction(+ : fluid, faces)
  for (Index i = 0; i < n; ++i) {
    const double s = x[i * d + axis_];
    if (ph[i] != kPhaseFluid || s < sampleLo_ || s > sampleHi_) continue;
    fluid += 1.0;
    for (auto p = nl.offset[static_cast<size_t>(i)]; p < nl.offset[static_cast<size_t>(i) + 1];
         ++p) {
      const Index j = nl.index[static_cast<size_t>(p)];
      if (ph[j] == kPhaseFluid) continue;
      double r2 = 0.0;
      for (int a = 0; a < d; ++a) r2 += (x[i * d + a] - x[j * d + a]) * (x[i * d + a] - x[j * d + a]);
      if (r2 <= face) faces += 1.0;
    }
  }
  // 4 V / S with V = N dx^D and S = faces dx^(D-1) (a staircase wall counts its voxel faces).
  return faces > 0.0 ? 4.0 * fluid * dx / faces : 0.0;
}

void DrainageModule::forces(Simulation& sim) {
  if (force_ == 0.0) return;
  ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const int d = sim.dimension();
  const double* x = st.data(st.position());
  const std::int32_t* mt = st.data(st.material());
  const std::int32_t* mo = st.data(sim.motion);
  double* acc = st.data(sim.acceleration);
  const int a = axis_;
  // Ramped like the solid's loads: f min(1, t / ramp_time), so that the start sends no
  // pressure shock through weakly compressible fluids.
  const double ramp = linearRamp(sim.time, rampTime_);  // libcore/time_schedule.hpp
  const double lo = sampleLo_, hi = sampleHi_, f = force_ * ramp;
  const std::int32_t inv = invading_;
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) {
    if (mt[i] != inv || mo[i] != kMotionFree) continue;
    const double s = x[i * d + a];
    if (s < lo || s > hi) acc[i * d + a] += f;
  }
}

bool DrainageModule::percolates(const Simulation& sim) const {
  const std::int32_t* mt = sim.store.data(sim.store.material());
  return spans(sim, [&](Index i) { return mt[i] == invading_; });
}

bool DrainageModule::flowPathSpans(const Simulation& sim) const {
  const ParticleStore& st = sim.store;
  const std::int32_t* ph = st.data(st.phase());
  const double* dmg = st.has("damage") ? st.data(st.real("damage")) : nullptr;
  return spans(sim, [&](Index i) {
    return ph[i] == kPhaseFluid || (dmg && ph[i] == kPhaseSolid && dmg[i] > 0.5);
  });
}

template <class Member>
bool DrainageModule::spans(const Simulation& sim, Member member) const {
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const int d = sim.dimension();
  const double* x = st.data(st.position());
  const auto& nl = sim.neighbours;
  if (static_cast<Index>(nl.offset.size()) < n + 1) return false;  // no list built yet
  parent_.resize(static_cast<size_t>(n));
  std::iota(parent_.begin(), parent_.end(), std::int64_t{0});
  const double link2 = std::pow(linkDistance_ * sim.spacing, 2);
  // Serial union-find over the members' short links (real pairs only: a periodic image would
  // join the two reservoirs through the periodic face, not through the sample).
  for (Index i = 0; i < n; ++i) {
    if (!member(i)) continue;
    for (auto q = nl.offset[i]; q < nl.offset[i + 1]; ++q) {
      const Index j = nl.index[static_cast<size_t>(q)];
      if (j >= n || j <= i || !member(j)) continue;
      double r2 = 0.0;
      for (int c = 0; c < d; ++c) r2 += std::pow(x[i * d + c] - x[j * d + c], 2);
      if (r2 > link2) continue;
      const std::int64_t ri = find(parent_, i), rj = find(parent_, j);
      if (ri != rj) parent_[static_cast<size_t>(std::max(ri, rj))] = std::min(ri, rj);
    }
  }
  // Breakthrough: one cluster reaches within dx of both faces of the slab (or beyond them).
  // Not "touches both reservoirs": the displaced water collects on the outlet face (it wets the
  // solid), so the gas that crossed the sample may meet water, not the outlet reservoir's gas.
  const double lowFace = sampleLo_ + sim.spacing, highFace = sampleHi_ - sim.spacing;
  std::vector<char> low(static_cast<size_t>(n), 0);
  for (Index i = 0; i < n; ++i)
    if (member(i) && x[i * d + axis_] < lowFace) low[static_cast<size_t>(find(parent_, i))] = 1;
  for (Index i = 0; i < n; ++i)
    if (member(i) && x[i * d + axis_] > highFace &&
        low[static_cast<size_t>(find(parent_, i))])
      return true;
  return false;
}

void DrainageModule::endOfStep(Simulation& sim, double) {
  if (sim.step % checkEvery_ != 0) return;
  if (percolationTime_ < 0.0 && percolates(sim)) percolationTime_ = sim.time;
  if (flowPathTime_ < 0.0 && flowPathSpans(sim)) flowPathTime_ = sim.time;
}

std::string DrainageModule::endCondition(const Simulation& sim) const {
  if (stopAfterPercolation_ < 0.0 || percolationTime_ < 0.0) return {};
  if (sim.time < (percolationTime_ + stopAfterPercolation_) * (1.0 - 1e-12)) return {};
  std::ostringstream o;
  o << "drainage.stop_after_percolation: " << stopAfterPercolation_ << " s after percolation at "
    << percolationTime_ << " s";
  return o.str();
}

ModuleState DrainageModule::saveState() const {
  return {{"percolation_time", {percolationTime_}},
          {"flow_path_time", {flowPathTime_}},
          {"pore_size", {poreSize_}}};
}

void DrainageModule::restoreState(const ModuleState& state) {
  for (const auto& [name, v] : state) {
    if (name == "percolation_time" && !v.empty()) percolationTime_ = v[0];
    if (name == "flow_path_time" && !v.empty()) flowPathTime_ = v[0];
    if (name == "pore_size" && !v.empty()) poreSize_ = v[0];
  }
}

void DrainageModule::diagnostics(const Simulation& sim,
                                 std::vector<std::pair<std::string, double>>& columns) const {
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const int d = sim.dimension();
  const double* x = st.data(st.position());
  const double* m = st.data(st.mass());
  const double* rho = st.data(st.density());
  const std::int32_t* mt = st.data(st.material());
  const std::int32_t* ph = st.data(st.phase());
  const char* incl = inclusion_.data();
  const double* dmg = st.has("damage") ? st.data(st.real("damage")) : nullptr;
  const double* sig = st.has("stress") && st.components(st.real("stress").id) == d * d
                          ? st.data(st.real("stress"))
                          : nullptr;
  double vInv = 0, vDef = 0, vFluid = 0, vSolid = 0, vDamaged = 0, vStressed = 0, meanStress = 0;
  double maxDamage = 0, maxPrincipal = -std::numeric_limits<double>::infinity();
  double momInv = 0;  // sum V v.e of the invading fluid, e the push direction
  const double push = force_ < 0.0 ? -1.0 : 1.0;
  const double* vel = st.data(st.velocity());
#pragma omp parallel for schedule(static) reduction(+ : vInv, vDef, vFluid, vSolid, vDamaged, \
    vStressed, meanStress, momInv) reduction(max : maxDamage, maxPrincipal)
  for (Index i = 0; i < n; ++i) {
    const double s = x[i * d + axis_];
    if (s < sampleLo_ || s > sampleHi_) continue;
    const double v = m[i] / rho[i];
    if (ph[i] == kPhaseFluid) {
      vFluid += v;
      if (mt[i] == invading_) {
        vInv += v;
        momInv += v * push * vel[i * d + axis_];
      }
      if (mt[i] == defending_) vDef += v;
    } else if (ph[i] == kPhaseSolid || (ph[i] == kPhaseRigid && incl[mt[i]])) {
      vSolid += v;
      if (ph[i] != kPhaseSolid) continue;
      if (dmg) {
        maxDamage = std::max(maxDamage, dmg[i]);
        if (dmg[i] > 0.5) vDamaged += v;
      }
      if (sig) {
        double tr = 0.0, top = 0.0;
        const double* S = sig + i * d * d;
        for (int c = 0; c < d; ++c) tr += S[c * d + c];
        if (d == 1) {
          top = S[0];
        } else if (d == 2) {
          const double c = 0.5 * (S[0] + S[3]), r = std::hypot(0.5 * (S[0] - S[3]), S[1]);
          top = c + r;
        } else {
          Eigen::Matrix3d M;
          for (int p = 0; p < 3; ++p)
            for (int q = 0; q < 3; ++q) M(p, q) = 0.5 * (S[p * 3 + q] + S[q * 3 + p]);
          Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
          es.computeDirect(M, Eigen::EigenvaluesOnly);
          top = es.eigenvalues()[2];
        }
        vStressed += v;
        meanStress += v * tr / d;
        maxPrincipal = std::max(maxPrincipal, top);
      }
    }
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  columns.emplace_back("drainage_porosity", vFluid + vSolid > 0 ? vFluid / (vFluid + vSolid) : nan);
  columns.emplace_back("drainage_gas_saturation", vFluid > 0 ? vInv / vFluid : nan);
  columns.emplace_back("drainage_water_saturation", vFluid > 0 ? vDef / vFluid : nan);
  // endOfStep looks every `percolation_every` steps; an output row looks now, so that a row
  // never says "not percolated" after a percolation it could see.
  if (percolationTime_ < 0.0 && percolates(sim)) percolationTime_ = sim.time;
  columns.emplace_back("drainage_percolated", percolationTime_ >= 0.0 ? 1.0 : 0.0);
  columns.emplace_back("drainage_percolation_time", percolationTime_);
  if (flowPathTime_ < 0.0 && flowPathSpans(sim)) flowPathTime_ = sim.time;
  columns.emplace_back("drainage_flow_path", flowPathTime_ >= 0.0 ? 1.0 : 0.0);
  columns.emplace_back("drainage_flow_path_time", flowPathTime_);
  if (dmg) {
    columns.emplace_back("drainage_damaged_fraction", vSolid > 0 ? vDamaged / vSolid : nan);
    columns.emplace_back("drainage_max_damage", maxDamage);
  }
  // Eqs. 5.12a / 5.14a at the measured gas velocity (the thesis quotes Ca_sim ~ 1.25e-4 and
  // Re_sim ~ 0.5 for its runs).
  const Material& inv = sim.materials[static_cast<size_t>(invading_)];
  const double vg = vInv > 0 ? momInv / vInv : nan;
  columns.emplace_back("drainage_gas_velocity", vg);
  if (sim.published.surfaceTension > 0.0)
    columns.emplace_back("drainage_capillary_number",
                         inv.fluid.viscosity * vg / sim.published.surfaceTension);
  if (inv.fluid.viscosity > 0.0 && poreSize_ > 0.0)
    columns.emplace_back("drainage_reynolds_number",
                         inv.fluid.rho0 * vg * poreSize_ / inv.fluid.viscosity);
  if (sig) {
    columns.emplace_back("drainage_solid_mean_stress", vStressed > 0 ? meanStress / vStressed : nan);
    columns.emplace_back("drainage_solid_max_principal_stress",
                         vStressed > 0 ? maxPrincipal : nan);
  }
}

std::string DrainageModule::describe(const Simulation& sim) const {
  const Material& inv = sim.materials[static_cast<size_t>(invading_)];
  const Material& def = sim.materials[static_cast<size_t>(defending_)];
  const double lo = sim.domain.lo[static_cast<size_t>(axis_)];
  const double hi = sim.domain.hi[static_cast<size_t>(axis_)];
  std::ostringstream o;
  o.precision(4);
  o << "drainage:     " << inv.name << " pushed into " << def.name << " along "
    << "xyz"[axis_] << ", sample [" << sampleLo_ << ", " << sampleHi_ << "] m, reservoirs "
    << (hi - lo) - (sampleHi_ - sampleLo_) << " m in all\n"
    << "              dP = " << pressureDrop_ << " Pa: body force " << force_
    << " m/s^2 on the " << inv.name << " in the reservoirs"
    << (rampTime_ > 0.0 ? ", ramped over " + std::to_string(rampTime_) + " s" : "") << "\n";
  if (stopAfterPercolation_ >= 0.0)
    o << "              the run ends " << stopAfterPercolation_
      << " s after percolation (stop_after_percolation), or at end_time\n";
  if (inv.fluid.rho0 > 0.0 && def.fluid.viscosity > 0.0)
    o << "              density ratio " << def.name << "/" << inv.name << " = "
      << def.fluid.rho0 / inv.fluid.rho0 << ", viscosity ratio M = mu_" << inv.name << "/mu_"
      << def.name << " = " << inv.fluid.viscosity / def.fluid.viscosity << " (Eq. 5.13)\n";
  // Dimensionless numbers (Eqs. 5.11-5.14), simulated and, with `physical:`, real. Before the
  // run the gas velocity is estimated as the mean Poiseuille velocity of the defending fluid in a
  // pore of hydraulic diameter L under the slab's pressure gradient (tube in 3D: dP L^2 /
  // (32 mu l); slit in 2D: dP L^2 / (48 mu l)); the run measures it (drainage_gas_velocity and
  // the Ca / Re columns of timeseries.csv).
  const double L = poreSize_ > 0.0 ? poreSize_ : measurePoreSize(sim);
  const double slab = sampleHi_ - sampleLo_;
  double g = 0.0;
  for (double c : sim.published.fluidGravity) g += c * c;
  Parameters simulated{inv.fluid.rho0, def.fluid.rho0, inv.fluid.viscosity, def.fluid.viscosity,
                       sim.published.surfaceTension, L, 0.0, std::sqrt(g)};
  if (def.fluid.viscosity > 0.0 && L > 0.0)
    simulated.velocity = pressureDrop_ * L * L /
                         ((sim.dimension() == 3 ? 32.0 : 48.0) * def.fluid.viscosity * slab);
  const DimensionlessNumbers ns = numbersOf(simulated);
  o << "              pore size L = " << number(L) << " m ("
    << (poreSizeGiven_ ? "drainage.pore_size" : "hydraulic diameter 4 V / S of the slab's pores")
    << "), gas velocity v_g ~ " << number(simulated.velocity)
    << " m/s (Poiseuille estimate; measured in timeseries.csv)\n";
  o << "              numbers       simulated   physical\n";
  const DimensionlessNumbers np =
      hasPhysical_ ? numbersOf(physical_) : DimensionlessNumbers{NAN, NAN, NAN, NAN};
  auto row = [&](const char* what, double a, double b) {
    o << "              " << std::left << std::setw(14) << what << std::setw(12) << number(a)
      << (hasPhysical_ ? number(b) : std::string("(drainage.physical not given)")) << "\n";
  };
  row("Bo (5.11a)", ns.bond, np.bond);
  row("Ca (5.12a)", ns.capillary, np.capillary);
  row("M (5.13a)", ns.viscosityRatio, np.viscosityRatio);
  row("Re (5.14a)", ns.reynolds, np.reynolds);
  return o.str();
}

PORESPH_REGISTER_MODULE(DrainageModule, "drainage")

}  // namespace poresph
