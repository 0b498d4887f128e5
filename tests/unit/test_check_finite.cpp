// Unit test of Simulation::checkFinite (libcore/simulation.cpp): after every step it names the
// first particle whose value is not finite in any non-constant real field. Since 2026-11-27 each
// field is first tested by the sum of x - x over its values (0 exactly when all are finite, NaN
// otherwise; issue 17, docs/performance.md "Instruction counts"), and only a field that fails it
// is scanned particle by particle. This test checks that the fast test misses nothing: NaN, +Inf
// and -Inf in any component of any particle, among the largest finite values (whose sums would
// overflow: x - x of them is still 0) and subnormals, are reported with the field and the first
// bad particle; constant fields are not scanned.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "libcore/simulation.hpp"
#include "libcore/types.hpp"

using namespace poresph;

namespace {

// The message of checkFinite, or "" when it does not throw.
std::string failure(const Simulation& sim) {
  try {
    sim.checkFinite();
  } catch (const NumericalError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(CheckFinite, EveryNonFiniteValueIsFoundWithItsFieldAndFirstParticle) {
  constexpr Index n = 1001;  // odd: the vectorised loop's remainder is tested too
  Simulation sim(3);
  ParticleStore& st = sim.store;
  st.addParticles(n);
  const RealField probe = st.addReal("probe", 3);
  const RealField fixed = st.addReal("fixed", 1, kFieldDefault | kFieldConstant);
  double* p = st.data(probe);
  const double big = std::numeric_limits<double>::max();
  const double tiny = std::numeric_limits<double>::denorm_min();
  for (Index k = 0; k < 3 * n; ++k) p[k] = k % 3 == 0 ? big : k % 3 == 1 ? -big : tiny;
  EXPECT_EQ(failure(sim), "");  // finite extremes pass

  const double bad[] = {std::numeric_limits<double>::quiet_NaN(),
                        std::numeric_limits<double>::infinity(),
                        -std::numeric_limits<double>::infinity()};
  const Index where[] = {0, 1, 500, n - 1};
  for (double b : bad)
    for (Index i : where)
      for (int q = 0; q < 3; ++q) {
        const double keep = p[3 * i + q];
        p[3 * i + q] = b;
        const std::string m = failure(sim);
        EXPECT_NE(m.find("field 'probe' of particle " + std::to_string(i) + " "), std::string::npos)
            << "value " << b << " at particle " << i << ", component " << q << ": '" << m << "'";
        p[3 * i + q] = keep;
      }
  EXPECT_EQ(failure(sim), "");

  // Two bad particles: the first is named.
  p[3 * 700 + 2] = bad[1];
  p[3 * 42 + 0] = bad[0];
  EXPECT_NE(failure(sim).find("of particle 42 "), std::string::npos) << failure(sim);
  p[3 * 700 + 2] = 0.0;
  p[3 * 42 + 0] = 0.0;

  // A constant field is set once and not scanned.
  st.data(fixed)[7] = bad[0];
  EXPECT_EQ(failure(sim), "");
}
