// Validation of the time integrators (thesis Sec. 2.2: Verlet 2.47, leapfrog 2.48, and the
// predictor-corrector leapfrog of Chapter 3) on the undamped harmonic oscillator
// x'' = -w^2 x, x(0) = A, v(0) = 0, with closed form x = A cos(wt), v = -A w sin(wt), and an
// integrated field u' = x (u = A sin(wt)/w). Records the observed order of accuracy and the
// energy behaviour over 1000 periods.
#include <gtest/gtest.h>

#include <omp.h>

#include <cmath>
#include <sstream>

#include "libcore/integrator.hpp"
#include "libcore/simulation.hpp"
#include "tests/support/validation_record.hpp"

using namespace poresph;
using poresph::test::recordValidation;
using poresph::test::Stopwatch;
using poresph::test::ValidationRecord;

namespace {

constexpr double kPi = 3.14159265358979323846;
const int kOneThread = (omp_set_num_threads(1), 0);  // one particle: no threads needed

class Spring : public Module {
 public:
  explicit Spring(double w) : w_(w) {}
  std::string name() const override { return "spring"; }
  std::vector<std::string> materialModels() const override { return {}; }
  void configure(Simulation& sim, const std::vector<const Material*>&,
                 const ParameterSet*) override {
    u = sim.store.addReal("u", 1, kFieldDefault, name());
    uRate = sim.store.addReal("u_rate", 1, kFieldNone, name());
    sim.addIntegrated(u, uRate);
  }
  void forces(Simulation& sim) override {
    ParticleStore& s = sim.store;
    const double* r = s.data(s.position());
    double* a = s.data(sim.acceleration);
    double* ur = s.data(uRate);
    for (Index i = 0; i < s.realCount(); ++i) {
      a[i] = -w_ * w_ * r[i];
      ur[i] = r[i];
    }
  }
  RealField u, uRate;

 private:
  double w_;
};

std::unique_ptr<Simulation> makeSpring(double w, double amp, Spring** spring) {
  auto sim = std::make_unique<Simulation>(1);
  sim->kernel = Kernel(KernelType::CubicSpline, 1, 0.5);
  sim->domain.lo = {-10.0, 0.0, 0.0};
  sim->domain.hi = {10.0, 1.0, 1.0};
  auto m = std::make_unique<Spring>(w);
  *spring = m.get();
  m->configure(*sim, {}, nullptr);
  sim->addModule(std::move(m));
  sim->store.addParticles(1);
  sim->store.data(sim->store.mass())[0] = 1.0;
  sim->store.data(sim->store.position())[0] = amp;
  return sim;
}

struct Result {
  double order = 0.0;        // observed order from position errors at dt, dt/2, dt/4
  double orderField = 0.0;   // same for the integrated field u
  double errFine = 0.0;      // |x - A cos wt| / A at the finest dt
  double maxFirst = 0.0;     // max |E - E0| / E0 over the first 10 periods
  double maxLast = 0.0;      // ... over the last 10 of 1000 periods
  double modifiedDrift = 0;  // |H~(end) - H~(0)| / H~(0), H~ = v^2/2 + w^2 x^2 (1 - (w dt/2)^2)/2
  double seconds = 0.0;
};

Result measure(const std::string& scheme) {
  Stopwatch clock;
  Result r;
  const double w = 2.0 * kPi, amp = 1.0, tEnd = 2.3;
  double ex[3], eu[3];
  for (int k = 0; k < 3; ++k) {
    const double dt = 0.01 / (1 << k);
    Spring* sp = nullptr;
    auto sim = makeSpring(w, amp, &sp);
    auto integ = makeIntegrator(scheme);
    const long long n = std::llround(tEnd / dt);
    for (long long s = 0; s < n; ++s) integ->step(*sim, dt);
    const double t = sim->time;
    ex[k] = std::abs(sim->store.data(sim->store.position())[0] - amp * std::cos(w * t)) / amp;
    eu[k] = std::abs(sim->store.data(sp->u)[0] - amp * std::sin(w * t) / w) / (amp / w);
  }
  r.order = 0.5 * std::log2(ex[0] / ex[2]);
  r.orderField = 0.5 * std::log2(eu[0] / eu[2]);
  r.errFine = ex[2];

  const double dt = 1.0 / 40.0;
  Spring* sp = nullptr;
  auto sim = makeSpring(w, amp, &sp);
  auto integ = makeIntegrator(scheme);
  const ParticleStore& st = sim->store;
  auto energy = [&](double shadow) {
    const double x = st.data(st.position())[0], v = st.data(st.velocity())[0];
    return 0.5 * v * v + 0.5 * w * w * x * x * (1.0 - shadow * 0.25 * w * w * dt * dt);
  };
  const double e0 = energy(0.0), m0 = energy(1.0);
  const int periods = 1000, perPeriod = 40;
  for (int p = 0; p < periods; ++p)
    for (int k = 0; k < perPeriod; ++k) {
      integ->step(*sim, dt);
      const double err = std::abs(energy(0.0) - e0) / e0;
      if (p < 10) r.maxFirst = std::max(r.maxFirst, err);
      if (p >= periods - 10) r.maxLast = std::max(r.maxLast, err);
    }
  r.modifiedDrift = std::abs(energy(1.0) - m0) / m0;
  r.seconds = clock.seconds();
  return r;
}

void record(const std::string& scheme, const Result& r) {
  ValidationRecord order;
  order.caseName = "oscillator_" + scheme;
  order.quantity = "observed order of accuracy of x(t) (dt = T/100, T/200, T/400, t = 2.3 T)";
  order.measured = r.order;
  order.reference = 2.0;
  order.relativeError = std::abs(r.order - 2.0) / 2.0;
  order.resolution = "1 particle, w dt = 0.063 .. 0.016";
  order.wallSeconds = r.seconds;
  order.tolerance = "|p - 2| < 0.1";
  order.reference_source = "closed form x = A cos(wt); 2nd-order schemes Eqs. 2.47/2.48";
  recordValidation(order);

  ValidationRecord drift;
  drift.caseName = "oscillator_" + scheme;
  drift.quantity = "max relative energy error over periods 991-1000 (dt = T/40)";
  drift.measured = r.maxLast;
  drift.reference = r.maxFirst;  // the same envelope as over periods 1-10: no secular drift
  drift.relativeError = std::abs(r.maxLast - r.maxFirst) / r.maxFirst;
  drift.resolution = "1 particle, 40 steps per period, 40000 steps";
  drift.wallSeconds = r.seconds;
  std::ostringstream tol;
  tol << "envelope growth < 1 %"
      << (scheme == "predictor_corrector" ? "" : ", below (w dt)^2/4, modified energy to 1e-11");
  drift.tolerance = tol.str();
  drift.reference_source = "energy E0 = w^2 A^2 / 2; reference = envelope over periods 1-10";
  recordValidation(drift);
}

TEST(Oscillator, LeapfrogAndVerletSecondOrderNoDrift) {
  for (const std::string scheme : {"leapfrog", "verlet"}) {
    SCOPED_TRACE(scheme);
    const Result r = measure(scheme);
    std::printf("%s: order %.4f (field %.4f), err %.3e, energy first %.4e last %.4e, H~ drift %.2e\n",
                scheme.c_str(), r.order, r.orderField, r.errFine, r.maxFirst, r.maxLast,
                r.modifiedDrift);
    record(scheme, r);
    EXPECT_NEAR(r.order, 2.0, 0.1);
    EXPECT_NEAR(r.orderField, 2.0, 0.1);
    const double wdt = 2.0 * kPi / 40.0;
    EXPECT_LT(r.maxLast, 0.25 * wdt * wdt * 1.01);
    EXPECT_LT(r.maxLast, 1.01 * r.maxFirst);
    EXPECT_LT(r.modifiedDrift, 1e-11);
  }
}

TEST(Oscillator, PredictorCorrectorSecondOrder) {
  const Result r = measure("predictor_corrector");
  std::printf("predictor_corrector: order %.4f (field %.4f), err %.3e, energy first %.4e last %.4e\n",
              r.order, r.orderField, r.errFine, r.maxFirst, r.maxLast);
  record("predictor_corrector", r);
  EXPECT_NEAR(r.order, 2.0, 0.1);
  EXPECT_NEAR(r.orderField, 2.0, 0.1);
  // not symplectic in general, but on the linear oscillator its energy error stays bounded too
  EXPECT_LT(r.maxLast, 1.01 * r.maxFirst);
  EXPECT_LT(r.maxLast, 0.01);
}

}  // namespace
