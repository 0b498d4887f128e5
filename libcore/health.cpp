#include "libcore/health.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <unordered_map>

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
  h.rollbackEvery = static_cast<Index>(s.integer("rollback_every", 1, 1, 1000000000));
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

namespace poresph {

bool RollbackState::copies(unsigned flags) {
  return (flags & (kFieldCheckpoint | kFieldOutput)) != 0 && (flags & kFieldConstant) == 0;
}

std::size_t RollbackState::bytesPerParticle(const ParticleStore& st) {
  std::size_t b = 0;
  for (const auto& s : st.fields())
    if (copies(s.flags))
      b += static_cast<std::size_t>(s.components) *
           (s.type == FieldType::Real ? sizeof(double) : sizeof(std::int32_t));
  return b;
}

std::size_t RollbackState::bytes() const {
  std::size_t b = 0;
  for (const auto& v : real_) b += v.capacity() * sizeof(double);
  for (const auto& v : int_) b += v.capacity() * sizeof(std::int32_t);
  return b;
}

bool RollbackState::capture(const Simulation& sim) {
  if (valid_ && sim.step != step_ && (sim.step - step_) % every_ != 0) return false;
  const ParticleStore& st = sim.store;
  const auto& specs = st.fields();
  if (real_.size() != specs.size()) {
    real_.resize(specs.size());
    int_.resize(specs.size());
  }
  n_ = st.realCount();
  for (size_t f = 0; f < specs.size(); ++f) {
    if (!everyField_ && !copies(specs[f].flags)) {
      // A field registered since the last capture may need no copy: keep no stale buffer.
      real_[f].clear();
      int_[f].clear();
      continue;
    }
    const size_t count = static_cast<size_t>(n_) * static_cast<size_t>(specs[f].components);
    if (specs[f].type == FieldType::Real) {
      const double* p = st.data(RealField{static_cast<int>(f)});
      real_[f].assign(p, p + count);
    } else {
      const std::int32_t* p = st.data(IntField{static_cast<int>(f)});
      int_[f].assign(p, p + count);
    }
  }
  time_ = sim.time;
  dt_ = sim.dt;
  step_ = sim.step;
  modules_.resize(sim.modules.size());
  for (size_t k = 0; k < sim.modules.size(); ++k) modules_[k] = sim.modules[k]->saveState();
  valid_ = true;
  return true;
}

bool RollbackState::restore(Simulation& sim) const {
  if (!valid_) return false;
  ParticleStore& st = sim.store;
  st.clearGhosts();
  if (st.realCount() != n_) return false;
  const auto& specs = st.fields();
  // Fields that are not copied (constant ones, scratch) follow their particles: put the store
  // back into the captured particle order first (a cell reorder may have happened since), by
  // the ids of the copy. Allocates, but only once, on the way out of a failed run.
  const std::vector<std::int32_t>& capturedIds = int_[static_cast<size_t>(st.id().id)];
  if (capturedIds.size() == static_cast<size_t>(n_)) {
    const std::int32_t* ids = st.data(st.id());
    bool same = true;
    for (Index i = 0; i < n_ && same; ++i) same = ids[i] == capturedIds[static_cast<size_t>(i)];
    if (!same) {
      std::unordered_map<std::int32_t, Index> where;
      where.reserve(static_cast<size_t>(n_));
      for (Index i = 0; i < n_; ++i) where[ids[i]] = i;
      std::vector<Index> newToOld(static_cast<size_t>(n_));
      for (Index k = 0; k < n_; ++k) {
        auto it = where.find(capturedIds[static_cast<size_t>(k)]);
        if (it == where.end()) return false;  // a particle was removed and another added
        newToOld[static_cast<size_t>(k)] = it->second;
      }
      st.permute(newToOld);
    }
  }
  for (size_t f = 0; f < specs.size() && f < real_.size(); ++f) {
    if (!everyField_ && !copies(specs[f].flags)) continue;
    const size_t count = static_cast<size_t>(n_) * static_cast<size_t>(specs[f].components);
    if (specs[f].type == FieldType::Real) {
      if (real_[f].size() == count)
        std::memcpy(st.data(RealField{static_cast<int>(f)}), real_[f].data(),
                    count * sizeof(double));
    } else if (int_[f].size() == count) {
      std::memcpy(st.data(IntField{static_cast<int>(f)}), int_[f].data(),
                  count * sizeof(std::int32_t));
    }
  }
  sim.time = time_;
  sim.dt = dt_;
  sim.step = step_;
  for (size_t k = 0; k < sim.modules.size() && k < modules_.size(); ++k)
    if (!modules_[k].empty()) sim.modules[k]->restoreState(modules_[k]);
  return true;
}

}  // namespace poresph
