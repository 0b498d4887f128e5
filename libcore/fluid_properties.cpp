#include "libcore/fluid_properties.hpp"

#include <algorithm>
#include <cmath>

namespace poresph {

double pressureOf(const FluidProperties& m, double rho) {
  const double c2 = m.soundSpeed * m.soundSpeed;
  if (m.eos == FluidProperties::Eos::Tait)
    return m.rho0 * c2 / m.taitGamma * (std::pow(rho / m.rho0, m.taitGamma) - 1.0) +
           m.backgroundPressure;
  return c2 * (rho - m.rho0) + m.backgroundPressure;  // Eq. 1.4
}

double densityOf(const FluidProperties& m, double p) {
  const double c2 = m.soundSpeed * m.soundSpeed;
  if (m.eos == FluidProperties::Eos::Tait) {
    const double base =
        std::max(1e-3, 1.0 + (p - m.backgroundPressure) * m.taitGamma / (m.rho0 * c2));
    return m.rho0 * std::pow(base, 1.0 / m.taitGamma);
  }
  return std::max(1e-3 * m.rho0, m.rho0 + (p - m.backgroundPressure) / c2);
}

double internalEnergyOf(const FluidProperties& m, double rho) {
  const double c2 = m.soundSpeed * m.soundSpeed;
  const double background = m.backgroundPressure * (1.0 / m.rho0 - 1.0 / rho);
  if (m.eos == FluidProperties::Eos::Tait) {
    const double B = m.rho0 * c2 / m.taitGamma, g = m.taitGamma;
    // rho0^gamma of the last material asked on this thread: the energy account calls this for
    // every fluid particle of one material, and the pow of a constant was half of its cost
    // (issue 17, docs/performance.md "Instruction counts, case A"); the same value.
    thread_local double lastRho0 = -1.0, lastGamma = -1.0, lastPow = 0.0;
    if (m.rho0 != lastRho0 || g != lastGamma) {
      lastPow = std::pow(m.rho0, g);
      lastRho0 = m.rho0;
      lastGamma = g;
    }
    return B / (g - 1.0) * (std::pow(rho, g - 1.0) / lastPow - 1.0 / m.rho0) +
           B * (1.0 / rho - 1.0 / m.rho0) + background;
  }
  return c2 * (std::log(rho / m.rho0) + m.rho0 / rho - 1.0) + background;
}

}  // namespace poresph
