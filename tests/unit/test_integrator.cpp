// Time integrators (thesis Eqs. 2.47, 2.48, Chapter 3's predictor-corrector leapfrog) on a
// harmonic oscillator: x'' = -w^2 (x - anchor), with two integrated scalar fields
// u' = x - anchor (u = u0 + A sin(wt)/w) and c' = -lambda c (c = c0 exp(-lambda t)).
#include <gtest/gtest.h>

#include <cmath>

#include <omp.h>

#include "libcore/checkpoint.hpp"
#include "libcore/integrator.hpp"
#include "libcore/simulation.hpp"

using namespace poresph;

namespace {

constexpr double kPi = 3.14159265358979323846;
// A handful of particles: OpenMP threads would only add fork/join overhead on a shared machine.
const int kOneThread = (omp_set_num_threads(1), 0);

class OscillatorModule : public Module {
 public:
  OscillatorModule(double w, double lambda, std::vector<double> prescribed)
      : w_(w), lambda_(lambda), vPrescribed_(std::move(prescribed)) {}
  std::string name() const override { return "test_oscillator"; }
  std::vector<std::string> materialModels() const override { return {}; }
  void configure(Simulation& sim, const std::vector<const Material*>&,
                 const ParameterSet*) override {
    const int d = sim.dimension();
    anchor = sim.store.addReal("anchor", d, kFieldDefault, name());
    u = sim.store.addReal("u", 1, kFieldDefault, name());
    uRate = sim.store.addReal("u_rate", 1, kFieldNone, name());
    c = sim.store.addReal("c", 1, kFieldDefault, name());
    cRate = sim.store.addReal("c_rate", 1, kFieldNone, name());
    sim.addIntegrated(u, uRate, true);
    sim.addIntegrated(c, cRate, false);
  }
  void forces(Simulation& sim) override {
    ParticleStore& s = sim.store;
    const int d = sim.dimension();
    const double* r = s.data(s.position());
    const double* x0 = s.data(anchor);
    double* a = s.data(sim.acceleration);
    double* ur = s.data(uRate);
    const double* cv = s.data(c);
    double* cr = s.data(cRate);
    for (Index i = 0; i < s.realCount(); ++i) {
      for (int q = 0; q < d; ++q) a[i * d + q] = -w_ * w_ * (r[i * d + q] - x0[i * d + q]);
      ur[i] = r[i * d] - x0[i * d];
      cr[i] = -lambda_ * cv[i];
    }
  }
  void constraints(Simulation& sim) override {
    ParticleStore& s = sim.store;
    const int d = sim.dimension();
    double* v = s.data(s.velocity());
    const std::int32_t* mo = s.data(sim.motion);
    for (Index i = 0; i < s.realCount(); ++i)
      if (mo[i] == kMotionPrescribed)
        for (int q = 0; q < d; ++q) v[i * d + q] = vPrescribed_[static_cast<size_t>(q)];
  }
  RealField anchor, u, uRate, c, cRate;

 private:
  double w_, lambda_;
  std::vector<double> vPrescribed_;
};

struct Rig {
  std::unique_ptr<Simulation> sim;
  OscillatorModule* osc = nullptr;
};

/// n particles along x, anchors 3 apart, displaced by `amp` (the k-th by amp*(1 + 0.1 k)).
Rig makeOscillators(int dim, int n, double w, double lambda, double amp,
                      std::vector<double> vPrescribed = {0.3, -0.2, 0.1}) {
  Rig s;
  s.sim = std::make_unique<Simulation>(dim);
  Simulation& sim = *s.sim;
  sim.kernel = Kernel(KernelType::CubicSpline, dim, 0.5);
  sim.spacing = 1.0;
  for (int a = 0; a < 3; ++a) {
    sim.domain.lo[static_cast<size_t>(a)] = -50.0;
    sim.domain.hi[static_cast<size_t>(a)] = 50.0;
  }
  vPrescribed.resize(static_cast<size_t>(dim));
  auto mod = std::make_unique<OscillatorModule>(w, lambda, vPrescribed);
  s.osc = mod.get();
  mod->configure(sim, {}, nullptr);
  sim.addModule(std::move(mod));
  sim.store.addParticles(n);
  ParticleStore& st = sim.store;
  for (Index i = 0; i < n; ++i) {
    st.data(st.mass())[i] = 1.0;
    for (int q = 0; q < dim; ++q) {
      st.data(s.osc->anchor)[i * dim + q] = (q == 0 ? 3.0 * i : 0.0);
      st.data(st.position())[i * dim + q] = (q == 0 ? 3.0 * i + amp * (1.0 + 0.1 * i) : 0.0);
    }
    st.data(s.osc->u)[i] = 0.5;
    st.data(s.osc->c)[i] = 2.0;
  }
  return s;
}

Index findId(const ParticleStore& s, std::int32_t id) {
  for (Index i = 0; i < s.realCount(); ++i)
    if (s.data(s.id())[i] == id) return i;
  return -1;
}

struct Errors {
  double x, v, u, c;
};

/// Runs one free 1D oscillator (w = 2 pi) to t_end with dt; returns the errors against the
/// closed forms.
Errors runOscillator(const std::string& scheme, double dt, double tEnd) {
  const double w = 2.0 * kPi, lambda = 0.7, amp = 1.0;
  Rig s = makeOscillators(1, 1, w, lambda, amp);
  auto integ = makeIntegrator(scheme);
  const long long n = std::llround(tEnd / dt);
  for (long long k = 0; k < n; ++k) integ->step(*s.sim, dt);
  const ParticleStore& st = s.sim->store;
  const double t = s.sim->time;
  EXPECT_EQ(s.sim->step, n);
  EXPECT_NEAR(t, tEnd, 1e-9);
  EXPECT_EQ(integ->rateEvaluations(), n + 1);  // one per step plus the first
  Errors e;
  e.x = std::abs(st.data(st.position())[0] - amp * std::cos(w * t));
  e.v = std::abs(st.data(st.velocity())[0] + amp * w * std::sin(w * t));
  e.u = std::abs(st.data(s.osc->u)[0] - (0.5 + amp * std::sin(w * t) / w));
  e.c = std::abs(st.data(s.osc->c)[0] - 2.0 * std::exp(-lambda * t));
  return e;
}

class IntegratorScheme : public ::testing::TestWithParam<std::string> {};

TEST_P(IntegratorScheme, SecondOrderOnOscillatorAndFields) {
  const double tEnd = 2.3;
  const double dts[3] = {0.01, 0.005, 0.0025};
  Errors e[3];
  for (int k = 0; k < 3; ++k) e[k] = runOscillator(GetParam(), dts[k], tEnd);
  auto order = [](double a, double b) { return std::log2(a / b); };
  for (int k = 0; k < 2; ++k) {
    SCOPED_TRACE("dt " + std::to_string(dts[k]));
    EXPECT_NEAR(order(e[k].x, e[k + 1].x), 2.0, 0.2);
    EXPECT_NEAR(order(e[k].v, e[k + 1].v), 2.0, 0.2);
    EXPECT_NEAR(order(e[k].u, e[k + 1].u), 2.0, 0.2);
    EXPECT_NEAR(order(e[k].c, e[k + 1].c), 2.0, 0.2);
  }
  // and the errors are small in absolute terms (w dt = 0.016 at the finest dt)
  EXPECT_LT(e[2].x, 2e-3);
  EXPECT_LT(e[2].c, 1e-5);
}

TEST_P(IntegratorScheme, SecondOrderWithVaryingTimeStep) {
  // dt(t) = dt0 (1 + 0.4 sin(3 t)): a smooth step-size function, so halving dt0 halves every
  // step. Leapfrog's kick (dt_{n-1} + dt_n)/2 (Eq. 2.48b) keeps it second order.
  const double w = 2.0 * kPi, tEnd = 1.7;
  double err[3];
  for (int k = 0; k < 3; ++k) {
    const double dt0 = 0.01 / (1 << k);
    Rig s = makeOscillators(1, 1, w, 0.3, 1.0);
    auto integ = makeIntegrator(GetParam());
    while (s.sim->time < tEnd - 1e-12) {
      const double dt = std::min(dt0 * (1.0 + 0.4 * std::sin(3.0 * s.sim->time)),
                                 tEnd - s.sim->time);
      integ->step(*s.sim, dt);
    }
    const ParticleStore& st = s.sim->store;
    err[k] = std::abs(st.data(st.position())[0] - std::cos(w * s.sim->time)) +
             std::abs(st.data(st.velocity())[0] + w * std::sin(w * s.sim->time)) / w;
  }
  EXPECT_NEAR(std::log2(err[0] / err[1]), 2.0, 0.25);
  EXPECT_NEAR(std::log2(err[1] / err[2]), 2.0, 0.25);
}

TEST_P(IntegratorScheme, FixedAndPrescribedParticlesAcrossReorders) {
  const double w = 2.0, lambda = 0.5;
  Rig s = makeOscillators(2, 3, w, lambda, 0.8);
  Simulation& sim = *s.sim;
  ParticleStore& st = sim.store;
  sim.reorderEvery = 1;  // reorder the store at every evaluation
  // id 0 free, id 1 fixed, id 2 prescribed (velocity (0.3, -0.2) set by constraints())
  st.data(sim.motion)[1] = kMotionFixed;
  st.data(sim.motion)[2] = kMotionPrescribed;
  const std::vector<double> r1 = {st.data(st.position())[2], st.data(st.position())[3]};
  const std::vector<double> r2 = {st.data(st.position())[4], st.data(st.position())[5]};
  auto integ = makeIntegrator(GetParam());
  const double dt = 1e-3;
  integ->step(sim, dt);
  const size_t nFields = st.fields().size();
  for (int k = 1; k < 500; ++k) integ->step(sim, dt);
  EXPECT_EQ(st.fields().size(), nFields) << "no field registered after the first step";
  const double t = sim.time;
  const Index i0 = findId(st, 0), i1 = findId(st, 1), i2 = findId(st, 2);
  ASSERT_GE(i0, 0);
  ASSERT_GE(i1, 0);
  ASSERT_GE(i2, 0);
  const double* r = st.data(st.position());
  const double* v = st.data(st.velocity());
  // fixed: never moves, velocity stays zero, freeOnly field u untouched, c (freeOnly=false) decays
  EXPECT_EQ(r[2 * i1], r1[0]);
  EXPECT_EQ(r[2 * i1 + 1], r1[1]);
  EXPECT_EQ(v[2 * i1], 0.0);
  EXPECT_EQ(st.data(s.osc->u)[i1], 0.5);
  EXPECT_NEAR(st.data(s.osc->c)[i1], 2.0 * std::exp(-lambda * t), 1e-6);
  // prescribed: velocity is the imposed one, position follows it, acceleration ignored
  EXPECT_DOUBLE_EQ(v[2 * i2], 0.3);
  EXPECT_DOUBLE_EQ(v[2 * i2 + 1], -0.2);
  EXPECT_NEAR(r[2 * i2], r2[0] + 0.3 * t, 1e-12);
  EXPECT_NEAR(r[2 * i2 + 1], r2[1] - 0.2 * t, 1e-12);
  EXPECT_EQ(st.data(s.osc->u)[i2], 0.5);
  // free: follows the closed form (amplitude 0.8, anchor x = 0)
  EXPECT_NEAR(r[2 * i0], 0.8 * std::cos(w * t), 1e-5);
  EXPECT_NEAR(v[2 * i0], -0.8 * w * std::sin(w * t), 1e-5);
  EXPECT_NEAR(st.data(s.osc->u)[i0], 0.5 + 0.8 * std::sin(w * t) / w, 1e-5);
}

TEST_P(IntegratorScheme, ReEvaluatesRatesWhenStateChangedBehindItsBack) {
  Rig s = makeOscillators(1, 1, 1.0, 0.0, 1.0);
  auto integ = makeIntegrator(GetParam());
  integ->step(*s.sim, 0.01);
  integ->step(*s.sim, 0.01);
  EXPECT_EQ(integ->rateEvaluations(), 3);
  s.sim->step = 0;  // e.g. a checkpoint was read
  s.sim->time = 0.0;
  integ->step(*s.sim, 0.01);
  EXPECT_EQ(integ->rateEvaluations(), 5);
  EXPECT_EQ(s.sim->step, 1);
  EXPECT_DOUBLE_EQ(s.sim->dt, 0.01);
}

TEST_P(IntegratorScheme, RestartFromCheckpointContinuesTheRun) {
  // 300 steps straight vs. 150 steps, checkpoint, a new simulation and integrator, 150 steps.
  const double w = 2.0 * kPi, dt = 1e-3;
  Rig ref = makeOscillators(2, 3, w, 0.4, 0.7);
  auto integ = makeIntegrator(GetParam());
  for (int k = 0; k < 150; ++k) integ->step(*ref.sim, dt);
  const std::string file = std::string(PORESPH_BINARY_DIR) + "/integrator_restart_" + GetParam() +
                           ".h5";
  writeCheckpoint(*ref.sim, file);
  for (int k = 0; k < 150; ++k) integ->step(*ref.sim, dt);

  Rig re = makeOscillators(2, 1, w, 0.4, 0.0);  // configured the same way, other particles
  readCheckpoint(*re.sim, file);
  EXPECT_EQ(re.sim->step, 150);
  auto integ2 = makeIntegrator(GetParam());
  for (int k = 0; k < 150; ++k) integ2->step(*re.sim, dt);
  EXPECT_EQ(re.sim->step, 300);
  EXPECT_DOUBLE_EQ(re.sim->time, ref.sim->time);
  const ParticleStore& a = ref.sim->store;
  const ParticleStore& b = re.sim->store;
  ASSERT_EQ(b.realCount(), 3);
  // Not bit-exact: the uninterrupted run carries rates evaluated at the predicted state
  // (c' = -lambda c at c + c' dt for Verlet/leapfrog; the lagged mid-point rates for the
  // predictor-corrector), the restarted one re-evaluates them at the checkpointed state. Both are
  // second-order consistent; the difference is a local truncation-size term.
  const double tol = GetParam() == "predictor_corrector" ? 1e-7 : 1e-9;
  for (std::int32_t id = 0; id < 3; ++id) {
    const Index i = findId(a, id), j = findId(b, id);
    for (int q = 0; q < 2; ++q) {
      EXPECT_NEAR(b.data(b.position())[2 * j + q], a.data(a.position())[2 * i + q], tol);
      EXPECT_NEAR(b.data(b.velocity())[2 * j + q], a.data(a.velocity())[2 * i + q], w * tol);
    }
    EXPECT_NEAR(b.data(re.osc->u)[j], a.data(ref.osc->u)[i], tol);
    EXPECT_NEAR(b.data(re.osc->c)[j], a.data(ref.osc->c)[i], tol);
  }
}

TEST_P(IntegratorScheme, RejectsBadTimeStep) {
  Rig s = makeOscillators(1, 1, 1.0, 0.0, 1.0);
  auto integ = makeIntegrator(GetParam());
  EXPECT_THROW(integ->step(*s.sim, 0.0), NumericalError);
  EXPECT_THROW(integ->step(*s.sim, -1.0), NumericalError);
  EXPECT_THROW(integ->step(*s.sim, std::nan("")), NumericalError);
}

INSTANTIATE_TEST_SUITE_P(All, IntegratorScheme,
                         ::testing::Values("leapfrog", "verlet", "predictor_corrector"));

TEST(Integrator, SymplecticSchemesHaveNoSecularEnergyDrift) {
  // 1000 periods at dt = T/40. For the harmonic oscillator, velocity Verlet (and leapfrog with
  // synchronised velocities) conserves the modified energy H~ = v^2/2 + w^2 x^2 (1 - (w dt/2)^2)/2
  // exactly, so H~ may change by round-off only, and the true energy error stays bounded by
  // (w dt)^2/4 (no secular drift over 1000 periods).
  const double w = 2.0 * kPi, dt = 1.0 / 40.0;
  for (const std::string scheme : {"leapfrog", "verlet"}) {
    SCOPED_TRACE(scheme);
    Rig s = makeOscillators(1, 1, w, 0.0, 1.0);
    auto integ = makeIntegrator(scheme);
    const ParticleStore& st = s.sim->store;
    auto energy = [&](double shadow) {
      const double x = st.data(st.position())[0], v = st.data(st.velocity())[0];
      return 0.5 * v * v + 0.5 * w * w * x * x * (1.0 - shadow * 0.25 * w * w * dt * dt);
    };
    const double e0 = energy(0.0), m0 = energy(1.0);
    double maxFirst = 0.0, maxLast = 0.0;
    const int periods = 1000, perPeriod = 40;
    for (int p = 0; p < periods; ++p)
      for (int k = 0; k < perPeriod; ++k) {
        integ->step(*s.sim, dt);
        const double err = std::abs(energy(0.0) - e0) / e0;
        if (p < 10) maxFirst = std::max(maxFirst, err);
        if (p >= periods - 10) maxLast = std::max(maxLast, err);
      }
    EXPECT_LT(maxLast, 0.25 * w * w * dt * dt * 1.01);  // (w dt)^2/4 = 0.0062
    EXPECT_LT(maxLast, maxFirst * 1.01);                // the envelope does not grow
    EXPECT_LT(std::abs(energy(1.0) - m0) / m0, 1e-11);  // modified energy: round-off only
  }
}

TEST(Integrator, FactoryNamesAndErrors) {
  EXPECT_EQ(integratorNames().size(), 3u);
  for (const auto& n : integratorNames()) EXPECT_EQ(makeIntegrator(n)->name(), n);
  try {
    makeIntegrator("euler");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("euler"), std::string::npos);
    EXPECT_NE(m.find("leapfrog"), std::string::npos);
    EXPECT_NE(m.find("predictor_corrector"), std::string::npos);
  }
}

TEST(Integrator, CflTimeStepEq249) {
  Rig s = makeOscillators(2, 2, 1.0, 0.0, 1.0);
  ParticleStore& st = s.sim->store;
  const double h = 0.5;
  EXPECT_TRUE(std::isinf(cflTimeStep(*s.sim, h)));
  st.data(st.velocity())[0] = 3.0;
  st.data(st.velocity())[1] = 4.0;  // |v| = 5
  EXPECT_DOUBLE_EQ(cflTimeStep(*s.sim, h), 0.25 * h / 5.0);
  st.data(s.sim->acceleration)[2] = 1e4;  // 0.25 sqrt(h / 1e4) = 1.77e-3 < 0.025
  EXPECT_DOUBLE_EQ(cflTimeStep(*s.sim, h), 0.25 * std::sqrt(h / 1e4));
  st.data(s.sim->motion)[1] = kMotionFixed;  // fixed particles do not limit the step
  EXPECT_DOUBLE_EQ(cflTimeStep(*s.sim, h), 0.25 * h / 5.0);
}

}  // namespace

// One rate per integrated field: registering the same pair twice is harmless, a second rate for
// the same field is refused loudly (the integrators keep one scratch copy per field, so it would
// otherwise be lost without a word).
TEST(IntegratedFields, SecondRateForOneFieldIsRefused) {
  Simulation sim(2);
  const RealField r1 = sim.store.addReal("correction_a", 2, kFieldNone, "test");
  const RealField r2 = sim.store.addReal("correction_b", 2, kFieldNone, "test");
  sim.addIntegrated(sim.store.position(), r1);
  EXPECT_NO_THROW(sim.addIntegrated(sim.store.position(), r1));
  EXPECT_EQ(sim.integrated.size(), 1u);
  EXPECT_THROW(sim.addIntegrated(sim.store.position(), r2), std::logic_error);
}
