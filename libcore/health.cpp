#include "libcore/health.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "libcore/parameters.hpp"
#include "libcore/simulation.hpp"

namespace poresph {

HealthLimits readHealthLimits(const ParameterSet* section) {
  HealthLimits h;
  if (!section) return h;
  const ParameterSet& s = *section;
  h.densityVariation = s.real("density_variation", h.densityVariation, Range::positive());
  h.maxMach = s.real("max_mach", h.maxMach, Range::positive());
  h.dtFloor = s.real("dt_floor", h.dtFloor, Range{0.0, 1.0, false, true});
  h.energyGrowth = s.real("energy_growth", h.energyGrowth, Range::positive());
  h.domainMargin = s.real("domain_margin", h.domainMargin, Range::nonNegative());
  h.keepGoing = s.boolean("keep_going", false);
  s.finish();
  return h;
}

double HealthMonitor::energyBalance(const Simulation& sim, EnergyAccount& total) const {
  total = EnergyAccount{};
  bool complete = true;
  for (const auto& m : sim.modules) complete = m->energyAccount(sim, total) && complete;
  total.complete = complete;
  return sim.kineticEnergy() + total.stored + total.dissipated - total.workIn;
}

void HealthMonitor::start(const Simulation& sim, double initialStableTimeStep) {
  initialStable_ = initialStableTimeStep;
  const int d = sim.dimension();
  // The box particles may occupy: the domain and the initial particles (wall layers may lie
  // outside the domain along non-periodic axes).
  for (int a = 0; a < 3; ++a) {
    boxLo_[static_cast<size_t>(a)] = sim.domain.lo[static_cast<size_t>(a)];
    boxHi_[static_cast<size_t>(a)] = sim.domain.hi[static_cast<size_t>(a)];
  }
  const double* x = sim.store.data(sim.store.position());
  const Index n = sim.store.realCount();
  for (int a = 0; a < d; ++a) {
    double lo = boxLo_[static_cast<size_t>(a)], hi = boxHi_[static_cast<size_t>(a)];
#pragma omp parallel for schedule(static) reduction(min : lo) reduction(max : hi)
    for (Index i = 0; i < n; ++i) {
      lo = std::min(lo, x[i * d + a]);
      hi = std::max(hi, x[i * d + a]);
    }
    boxLo_[static_cast<size_t>(a)] = lo;
    boxHi_[static_cast<size_t>(a)] = hi;
  }
  EnergyAccount account;
  energy0_ = energyBalance(sim, account);
  kinetic0_ = sim.kineticEnergy();
  stored0_ = account.stored;
  energyScale0_ = kinetic0_ + account.storedRange + account.untrackedScale;
  energyChecked_ = account.complete && !sim.modules.empty();
  workIn0_ = account.workIn;
  started_ = true;
}

std::vector<HealthIssue> HealthMonitor::check(const Simulation& sim) {
  std::vector<HealthIssue> issues;
  const ParticleStore& st = sim.store;
  const Index n = st.realCount();
  const int d = sim.dimension();

  // Density <= 0 in any phase: the continuity equation went through zero (Eq. 2.29 / 5.1a).
  {
    const double* rho = st.data(st.density());
    MaxAt worst;
#pragma omp parallel for schedule(static) reduction(maxAt : worst)
    for (Index i = 0; i < n; ++i)
      if (-rho[i] > worst.value || (-rho[i] == worst.value && i < worst.particle))
        worst = MaxAt{-rho[i], i};
    if (worst.particle >= 0 && worst.value >= 0.0)
      issues.push_back({"density_variation", "density", worst.particle, -worst.value, 0.0,
                        "a density that is not positive: the state has blown up"});
  }

  // The time step has collapsed (adaptive steps follow the fastest particle).
  if (started_ && initialStable_ > 0.0 && std::isfinite(initialStable_) && sim.dt > 0.0 &&
      sim.dt < limits_.dtFloor * initialStable_)
    issues.push_back({"dt_floor", "dt", -1, sim.dt, limits_.dtFloor * initialStable_,
                      "the time step fell below dt_floor x the initial stable step " +
                          std::to_string(initialStable_) +
                          " s: a particle is accelerating without bound"});

  // Particles flying off the box along a non-periodic axis.
  if (started_) {
    const double* x = st.data(st.position());
    MaxAt worst;
    double margin[3] = {0, 0, 0};
    for (int a = 0; a < d; ++a)
      margin[a] = limits_.domainMargin *
                  std::max(boxHi_[static_cast<size_t>(a)] - boxLo_[static_cast<size_t>(a)],
                           sim.spacing);
    const auto periodic = sim.domain.periodic;
    const auto lo = boxLo_, hi = boxHi_;
#pragma omp parallel for schedule(static) reduction(maxAt : worst)
    for (Index i = 0; i < n; ++i) {
      for (int a = 0; a < d; ++a) {
        if (periodic[static_cast<size_t>(a)]) continue;
        const double out = std::max(lo[static_cast<size_t>(a)] - x[i * d + a],
                                    x[i * d + a] - hi[static_cast<size_t>(a)]) -
                           margin[a];
        if (out > worst.value || (out == worst.value && i < worst.particle))
          worst = MaxAt{out, i};
      }
    }
    if (worst.particle >= 0 && worst.value > 0.0)
      issues.push_back({"domain_margin", "position", worst.particle, worst.value, 0.0,
                        "m beyond the box of the domain and the initial particles enlarged by "
                        "domain_margin: the particle has left the domain"});
  }

  // Energy put into the system without work (a numerical instability feeds itself).
  if (started_ && energyChecked_) {
    EnergyAccount account;
    const double e = energyBalance(sim, account);
    const double scale = energyScale0_ + std::abs(account.workIn - workIn0_);
    const double growth = e - energy0_;
    if (scale > 0.0 && growth > limits_.energyGrowth * scale)
      issues.push_back({"energy_growth", "energy", -1, growth / scale, limits_.energyGrowth,
                        "the energy (kinetic + stored + dissipated - work put in) grew by this "
                        "many times the scene's energy scale " + std::to_string(scale) +
                            " J without work input"});
  }

  for (const auto& m : sim.modules) m->checkHealth(sim, limits_, issues);
  return issues;
}

std::string HealthMonitor::describe(const Simulation& sim, const HealthIssue& issue) {
  std::ostringstream o;
  o.precision(6);
  o << "health check '" << issue.check << "' (field '" << issue.field << "'): ";
  if (issue.particle >= 0) {
    const ParticleStore& st = sim.store;
    const Index i = issue.particle;
    o << "particle " << i << " (id " << st.data(st.id())[i] << ", material "
      << st.data(st.material())[i] << ", at";
    const double* x = st.data(st.position());
    for (int a = 0; a < sim.dimension(); ++a) o << " " << x[i * sim.dimension() + a];
    o << " m) ";
  }
  o << "value " << issue.value << ", limit " << issue.limit;
  if (!issue.detail.empty()) o << " (" << issue.detail << ")";
  o << " at step " << sim.step << ", time " << sim.time << " s";
  return o.str();
}

}  // namespace poresph
