// Explicit time integrators, thesis Sec. 2.2 (Eqs. 2.47, 2.48) and the Predict-Evaluate-Correct
// leapfrog of Chapter 3. See libcore/integrator.hpp and docs/time-integration.md.
#include "libcore/integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "libcore/simulation.hpp"

namespace poresph {

Integrator::~Integrator() = default;

namespace {

void checkDt(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt)) {
    std::ostringstream m;
    m << "integrator: time step must be positive and finite, got dt = " << dt;
    throw NumericalError(m.str());
  }
}

/// Whether particle i is advanced for a field with the given freeOnly flag.
inline bool advances(std::int32_t motion, bool freeOnly) {
  return freeOnly ? motion == kMotionFree : true;
}

}  // namespace

void Integrator::evaluate(Simulation& sim) {
  sim.evaluateRates();
  ++evaluations_;
}

void Integrator::bindScratch(Simulation& sim) {
  bool same = bound_ == &sim && boundIntegrated_.size() == sim.integrated.size();
  if (same)
    for (size_t k = 0; k < sim.integrated.size(); ++k)
      if (boundIntegrated_[k] != sim.integrated[k].value.id) same = false;
  if (same && scratchV_.valid()) return;
  if (bound_ != &sim) primed_ = false;
  bound_ = &sim;
  const int d = sim.dimension();
  ParticleStore& s = sim.store;
  scratchV_ = s.addReal("integrator_velocity", d, kFieldNone, "integrator");
  // The position copy r^n is read by the predictor-corrector only (verlet and leapfrog advance
  // r in place: issue 17, memory, 8 D B per particle). Registered here, with the other scratch,
  // so that a restart finds the fields its checkpoint's store state names.
  scratchR_ = name() == "predictor_corrector"
                  ? s.addReal("integrator_position", d, kFieldNone, "integrator")
                  : RealField{};
  scratchF_.clear();
  boundIntegrated_.clear();
  for (const auto& f : sim.integrated) {
    const FieldSpec& spec = s.spec(f.value.id);
    if (s.components(f.rate.id) != spec.components)
      throw std::logic_error("integrated field '" + spec.name + "' has " +
                             std::to_string(spec.components) + " components but its rate '" +
                             s.spec(f.rate.id).name + "' has " +
                             std::to_string(s.components(f.rate.id)));
    scratchF_.push_back(s.addReal(spec.name + "@integrator", spec.components, kFieldNone,
                                  "integrator"));
    boundIntegrated_.push_back(f.value.id);
  }
  primed_ = false;  // a new field list: rates of the new fields are not known yet
}

void Integrator::prime(Simulation& sim) {
  bindScratch(sim);
  const bool current = primed_ && lastStep_ == sim.step && lastTime_ == sim.time &&
                       lastCount_ == sim.store.realCount();
  if (!current) {
    evaluate(sim);
    primed_ = false;  // the scheme's own state (e.g. leapfrog's v^{n-1/2}) must restart
  }
}

void Integrator::finishStep(Simulation& sim, double dt) {
  sim.time += dt;
  sim.dt = dt;
  sim.step += 1;
  primed_ = true;
  lastStep_ = sim.step;
  lastTime_ = sim.time;
  lastCount_ = sim.store.realCount();
  // History variables and self-integrated bodies (Module::endOfStep); a module that moves
  // particles here invalidates nothing: the next step's evaluation sees the new positions.
  for (auto& m : sim.modules) m->endOfStep(sim, dt);
  lastCount_ = sim.store.realCount();
}

ModuleState packStoreFields(const ParticleStore& s, bool checkpointed) {
  const Index n = s.realCount();
  ModuleState state;
  std::vector<double> ids(static_cast<size_t>(n));
  const std::int32_t* id = s.data(s.id());
  for (Index i = 0; i < n; ++i) ids[static_cast<size_t>(i)] = id[i];
  state.emplace_back("id", std::move(ids));
  for (size_t k = 0; k < s.fields().size(); ++k) {
    const FieldSpec& spec = s.fields()[k];
    if (((spec.flags & kFieldCheckpoint) != 0) != checkpointed) continue;
    const int f = static_cast<int>(k);
    const size_t count = static_cast<size_t>(n) * static_cast<size_t>(s.components(f));
    std::vector<double> values(count);
    if (spec.type == FieldType::Real) {
      const double* v = s.data(RealField{f});
      std::copy(v, v + count, values.begin());
    } else {
      const std::int32_t* v = s.data(IntField{f});
      std::copy(v, v + count, values.begin());  // int32 is exact in a double
    }
    state.emplace_back("field:" + spec.name, std::move(values));
  }
  return state;
}

void unpackStoreFields(ParticleStore& s, const ModuleState& state) {
  const Index n = s.realCount();
  const std::vector<double>* ids = nullptr;
  for (const auto& [key, values] : state)
    if (key == "id") ids = &values;
  if (!ids) throw std::invalid_argument("store state: entry 'id' is missing");
  if (static_cast<Index>(ids->size()) != n)
    throw std::invalid_argument("store state: " + std::to_string(ids->size()) +
                                " particles saved, the simulation has " + std::to_string(n));
  // Saved row k belongs to the particle with id ids[k]: map it to that particle's row now.
  std::int32_t maxId = 0;
  const std::int32_t* id = s.data(s.id());
  for (Index i = 0; i < n; ++i) maxId = std::max(maxId, id[i]);
  std::vector<Index> rowOfId(static_cast<size_t>(maxId) + 1, -1);
  for (Index i = 0; i < n; ++i) rowOfId[static_cast<size_t>(id[i])] = i;
  std::vector<Index> rowOf(static_cast<size_t>(n));
  for (Index k = 0; k < n; ++k) {
    const double v = (*ids)[static_cast<size_t>(k)];
    const Index row = v >= 0 && v <= maxId ? rowOfId[static_cast<size_t>(v)] : -1;
    if (row < 0)
      throw std::invalid_argument("store state: particle id " + std::to_string(v) +
                                  " is not in the simulation");
    rowOf[static_cast<size_t>(k)] = row;
  }
  for (const auto& [key, values] : state) {
    if (key.rfind("field:", 0) != 0) continue;
    const std::string name = key.substr(6);
    int f = -1;
    for (size_t k = 0; k < s.fields().size(); ++k)
      if (s.fields()[k].name == name) f = static_cast<int>(k);
    if (f < 0)
      throw std::invalid_argument("store state: field '" + name +
                                  "' is not registered in this simulation");
    const int c = s.components(f);
    if (static_cast<Index>(values.size()) != n * c)
      throw std::invalid_argument("store state: field '" + name + "' has " +
                                  std::to_string(values.size()) + " values, " +
                                  std::to_string(n * c) + " expected");
    const bool real = s.spec(f).type == FieldType::Real;
    double* outR = real ? s.data(RealField{f}) : nullptr;
    std::int32_t* outI = real ? nullptr : s.data(IntField{f});
    for (Index k = 0; k < n; ++k)
      for (int q = 0; q < c; ++q) {
        const double v = values[static_cast<size_t>(k * c + q)];
        const Index at = rowOf[static_cast<size_t>(k)] * c + q;
        if (real)
          outR[at] = v;
        else
          outI[at] = static_cast<std::int32_t>(v);
      }
  }
}

ModuleState Integrator::saveState(const Simulation& sim) const {
  const ParticleStore& s = sim.store;
  const bool current = primed_ && bound_ == &sim && lastStep_ == sim.step &&
                       lastTime_ == sim.time && lastCount_ == s.realCount();
  if (!current) return {};
  ModuleState state = packStoreFields(s, false);
  state.emplace_back("numbers", schemeNumbers());
  return state;
}

void Integrator::restoreState(Simulation& sim, const ModuleState& state) {
  bindScratch(sim);
  unpackStoreFields(sim.store, state);
  std::vector<double> numbers;
  bool found = false;
  for (const auto& [key, values] : state)
    if (key == "numbers") {
      numbers = values;
      found = true;
    }
  if (!found) throw std::invalid_argument("integrator state: entry 'numbers' is missing");
  setSchemeNumbers(numbers);
  primed_ = true;
  lastStep_ = sim.step;
  lastTime_ = sim.time;
  lastCount_ = sim.store.realCount();
}

namespace {

// ---------------------------------------------------------------------------------------------
// Shared pieces of the kick-drift-kick family (Verlet and leapfrog).
//   fields: w = f + rate dt/2 (kept in scratch), f = f + rate dt (prediction for the evaluation);
//   after the evaluation f = w + rate_new dt/2, i.e. the trapezoidal rule of Eq. 2.47b.
void predictFields(Simulation& sim, const std::vector<RealField>& scratch, double dt) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mo = s.data(sim.motion);
  for (size_t k = 0; k < sim.integrated.size(); ++k) {
    const IntegratedField& f = sim.integrated[k];
    const int c = s.components(f.value.id);
    double* val = s.data(f.value);
    const double* rate = s.data(f.rate);
    double* w = s.data(scratch[k]);
    const bool freeOnly = f.freeOnly;
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (!advances(mo[i], freeOnly)) continue;
      for (Index q = i * c; q < (i + 1) * c; ++q) {
        w[q] = val[q] + 0.5 * dt * rate[q];
        val[q] += dt * rate[q];
      }
    }
  }
}

void correctFields(Simulation& sim, const std::vector<RealField>& scratch, double dt) {
  ParticleStore& s = sim.store;
  const Index n = s.realCount();
  const std::int32_t* mo = s.data(sim.motion);
  for (size_t k = 0; k < sim.integrated.size(); ++k) {
    const IntegratedField& f = sim.integrated[k];
    const int c = s.components(f.value.id);
    double* val = s.data(f.value);
    const double* rate = s.data(f.rate);
    const double* w = s.data(scratch[k]);
    const bool freeOnly = f.freeOnly;
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (!advances(mo[i], freeOnly)) continue;
      for (Index q = i * c; q < (i + 1) * c; ++q) val[q] = w[q] + 0.5 * dt * rate[q];
    }
  }
}

// ---------------------------------------------------------------------------------------------
/// Velocity Verlet, Eq. 2.47:
///   r^{n+1} = r^n + v^n dt + a^n dt^2/2                                   (2.47a)
///   v^{n+1} = v^n + (a^n + a^{n+1}) dt/2                                  (2.47b)
/// a^{n+1} is evaluated with the predicted velocity v^n + a^n dt (and predicted fields
/// f^n + rate^n dt), so velocity-dependent forces stay second order (Heun's rule).
class VerletIntegrator final : public Integrator {
 public:
  std::string name() const override { return "verlet"; }
  void step(Simulation& sim, double dt) override {
    checkDt(dt);
    prime(sim);
    ParticleStore& s = sim.store;
    const int d = sim.dimension();
    const Index n = s.realCount();
    {
      double* r = s.data(s.position());
      double* v = s.data(s.velocity());
      const double* a = s.data(sim.acceleration);
      double* w = s.data(scratchV_);
      const std::int32_t* mo = s.data(sim.motion);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (mo[i] == kMotionFixed) continue;
        for (Index q = i * d; q < (i + 1) * d; ++q) {
          if (mo[i] == kMotionPrescribed) {
            r[q] += v[q] * dt;
          } else {
            r[q] += v[q] * dt + 0.5 * a[q] * dt * dt;  // (2.47a)
            w[q] = v[q] + 0.5 * dt * a[q];
            v[q] += dt * a[q];  // predicted v^{n+1} for the evaluation
          }
        }
      }
    }
    predictFields(sim, scratchF_, dt);
    evaluate(sim);
    {
      double* v = s.data(s.velocity());
      const double* a = s.data(sim.acceleration);
      const double* w = s.data(scratchV_);
      const std::int32_t* mo = s.data(sim.motion);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (mo[i] != kMotionFree) continue;
        for (Index q = i * d; q < (i + 1) * d; ++q) v[q] = w[q] + 0.5 * dt * a[q];  // (2.47b)
      }
    }
    correctFields(sim, scratchF_, dt);
    finishStep(sim, dt);
  }
};

// ---------------------------------------------------------------------------------------------
/// Leapfrog, Eq. 2.48, with the velocity at half steps as its state:
///   v^{n+1/2} = v^{n-1/2} + a^n (dt_{n-1} + dt_n)/2    (2.48b; = a^n dt for a constant dt)
///   r^{n+1}   = r^n + v^{n+1/2} dt_n                   (2.48a)
/// The first step starts with v^{1/2} = v^0 + a^0 dt/2. The store's "velocity" holds the
/// synchronised velocity v^{n+1} = v^{n+1/2} + a^{n+1} dt/2 (for output, energies and
/// velocity-dependent forces; during the evaluation it is the prediction v^{n+1/2} + a^n dt/2).
/// v^{n+1/2} lives in the store field "integrator_velocity" (permuted on reorder).
class LeapfrogIntegrator final : public Integrator {
 public:
  std::string name() const override { return "leapfrog"; }
  void step(Simulation& sim, double dt) override {
    checkDt(dt);
    const bool continuing = primed_ && bound_ == &sim && lastStep_ == sim.step &&
                            lastTime_ == sim.time && lastCount_ == sim.store.realCount();
    prime(sim);
    const bool staggered = continuing && primed_;  // v^{n-1/2} in the scratch is valid
    const double kick = staggered ? 0.5 * (dtPrev_ + dt) : 0.5 * dt;
    ParticleStore& s = sim.store;
    const int d = sim.dimension();
    const Index n = s.realCount();
    {
      double* r = s.data(s.position());
      double* v = s.data(s.velocity());
      const double* a = s.data(sim.acceleration);
      double* vh = s.data(scratchV_);
      const std::int32_t* mo = s.data(sim.motion);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (mo[i] == kMotionFixed) continue;
        for (Index q = i * d; q < (i + 1) * d; ++q) {
          if (mo[i] == kMotionPrescribed) {
            r[q] += v[q] * dt;
            vh[q] = v[q];
          } else {
            vh[q] = (staggered ? vh[q] : v[q]) + kick * a[q];  // (2.48b)
            r[q] += vh[q] * dt;                                // (2.48a)
            v[q] = vh[q] + 0.5 * dt * a[q];  // predicted synchronised velocity
          }
        }
      }
    }
    predictFields(sim, scratchF_, dt);
    evaluate(sim);
    {
      double* v = s.data(s.velocity());
      const double* a = s.data(sim.acceleration);
      const double* vh = s.data(scratchV_);
      const std::int32_t* mo = s.data(sim.motion);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (mo[i] != kMotionFree) continue;
        for (Index q = i * d; q < (i + 1) * d; ++q) v[q] = vh[q] + 0.5 * dt * a[q];
      }
    }
    correctFields(sim, scratchF_, dt);
    finishStep(sim, dt);
    dtPrev_ = dt;
  }

 protected:
  std::vector<double> schemeNumbers() const override { return {dtPrev_}; }
  void setSchemeNumbers(const std::vector<double>& v) override {
    if (v.size() != 1)
      throw std::invalid_argument("integrator state: leapfrog expects 1 number (dt_n), got " +
                                  std::to_string(v.size()));
    dtPrev_ = v[0];
  }

 private:
  double dtPrev_ = 0.0;
};

// ---------------------------------------------------------------------------------------------
/// Predict-Evaluate-Correct leapfrog (Chapter 3, after Young 2018 / Monaghan):
///   predict   r^{n+1/2} = r^n + v^n dt/2,  v^{n+1/2} = v^n + a^* dt/2,  f^{n+1/2} = f^n + rate^* dt/2
///   evaluate  a^{n+1/2}, rate^{n+1/2}
///   correct   v^{n+1} = v^n + a^{n+1/2} dt,  r^{n+1} = r^n + (v^n + v^{n+1}) dt/2,
///             f^{n+1} = f^n + rate^{n+1/2} dt
/// a^*, rate^* are the rates held in the store: those of the previous step's mid-point (or of
/// t^n at the first step). One evaluation per step; second order. Prescribed particles:
/// r^{n+1} = r^n + (v^n + v^{n+1/2}_imposed) dt/2.
class PredictorCorrectorIntegrator final : public Integrator {
 public:
  std::string name() const override { return "predictor_corrector"; }
  void step(Simulation& sim, double dt) override {
    checkDt(dt);
    prime(sim);
    ParticleStore& s = sim.store;
    const int d = sim.dimension();
    const Index n = s.realCount();
    const double h = 0.5 * dt;
    {
      double* r = s.data(s.position());
      double* v = s.data(s.velocity());
      const double* a = s.data(sim.acceleration);
      double* r0 = s.data(scratchR_);
      double* v0 = s.data(scratchV_);
      const std::int32_t* mo = s.data(sim.motion);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (mo[i] == kMotionFixed) continue;
        for (Index q = i * d; q < (i + 1) * d; ++q) {
          r0[q] = r[q];
          v0[q] = v[q];
          r[q] += h * v[q];
          if (mo[i] == kMotionFree) v[q] += h * a[q];
        }
      }
    }
    for (size_t k = 0; k < sim.integrated.size(); ++k) {
      const IntegratedField& f = sim.integrated[k];
      const int c = s.components(f.value.id);
      double* val = s.data(f.value);
      const double* rate = s.data(f.rate);
      double* f0 = s.data(scratchF_[k]);
      const std::int32_t* mo = s.data(sim.motion);
      const bool freeOnly = f.freeOnly;
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (!advances(mo[i], freeOnly)) continue;
        for (Index q = i * c; q < (i + 1) * c; ++q) {
          f0[q] = val[q];
          val[q] += h * rate[q];
        }
      }
    }
    evaluate(sim);
    {
      double* r = s.data(s.position());
      double* v = s.data(s.velocity());
      const double* a = s.data(sim.acceleration);
      const double* r0 = s.data(scratchR_);
      const double* v0 = s.data(scratchV_);
      const std::int32_t* mo = s.data(sim.motion);
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (mo[i] == kMotionFixed) continue;
        for (Index q = i * d; q < (i + 1) * d; ++q) {
          if (mo[i] == kMotionFree) v[q] = v0[q] + dt * a[q];
          r[q] = r0[q] + h * (v0[q] + v[q]);
        }
      }
    }
    for (size_t k = 0; k < sim.integrated.size(); ++k) {
      const IntegratedField& f = sim.integrated[k];
      const int c = s.components(f.value.id);
      double* val = s.data(f.value);
      const double* rate = s.data(f.rate);
      const double* f0 = s.data(scratchF_[k]);
      const std::int32_t* mo = s.data(sim.motion);
      const bool freeOnly = f.freeOnly;
#pragma omp parallel for schedule(static)
      for (Index i = 0; i < n; ++i) {
        if (!advances(mo[i], freeOnly)) continue;
        for (Index q = i * c; q < (i + 1) * c; ++q) val[q] = f0[q] + dt * rate[q];
      }
    }
    finishStep(sim, dt);
  }
};

}  // namespace

std::vector<std::string> integratorNames() {
  return {"leapfrog", "verlet", "predictor_corrector"};
}

std::unique_ptr<Integrator> makeIntegrator(const std::string& name) {
  if (name == "leapfrog") return std::make_unique<LeapfrogIntegrator>();
  if (name == "verlet") return std::make_unique<VerletIntegrator>();
  if (name == "predictor_corrector") return std::make_unique<PredictorCorrectorIntegrator>();
  std::string list;
  for (const auto& n : integratorNames()) list += (list.empty() ? "" : ", ") + n;
  throw InputError("unknown integrator '" + name + "' (valid: " + list + ")");
}

double cflTimeStep(const Simulation& sim, double h) {
  const ParticleStore& s = sim.store;
  const int d = sim.dimension();
  const Index n = s.realCount();
  const double* v = s.data(s.velocity());
  const double* a = s.data(sim.acceleration);
  const std::int32_t* mo = s.data(sim.motion);
  double v2max = 0.0, a2max = 0.0;
#pragma omp parallel for reduction(max : v2max, a2max) schedule(static)
  for (Index i = 0; i < n; ++i) {
    if (mo[i] == kMotionFixed) continue;
    double v2 = 0.0, a2 = 0.0;
    for (Index q = i * d; q < (i + 1) * d; ++q) {
      v2 += v[q] * v[q];
      a2 += a[q] * a[q];
    }
    v2max = std::max(v2max, v2);
    a2max = std::max(a2max, a2);
  }
  double dt = std::numeric_limits<double>::infinity();
  if (v2max > 0.0) dt = std::min(dt, 0.25 * h / std::sqrt(v2max));        // (2.49)
  if (a2max > 0.0) dt = std::min(dt, 0.25 * std::sqrt(h / std::sqrt(a2max)));  // (2.49)
  return dt;
}

}  // namespace poresph
