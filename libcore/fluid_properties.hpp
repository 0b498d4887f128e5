#pragma once
// What every module needs to know of a fluid material (reference density, sound speed, equation
// of state, viscosity): kept in libcore, in the scene's Material (Material::fluid), so that the
// coupling of fluids with solids and rigid bodies reads it from there and never from the fluid
// module's private members. The fluid module fills it in configure().
namespace poresph {

struct FluidProperties {
  enum class Eos { Linear, Tait };
  double rho0 = 0.0;                ///< reference density [kg/m^3]
  double soundSpeed = 0.0;          ///< c0 [m/s]
  double viscosity = 0.0;           ///< dynamic viscosity [Pa s]
  Eos eos = Eos::Linear;
  double taitGamma = 7.0;
  double backgroundPressure = 0.0;  ///< p_b [Pa]
  bool valid() const { return rho0 > 0.0 && soundSpeed > 0.0; }
};

/// Pressure from the equation of state: Eq. 1.4, p = c0^2 (rho - rho0) + p_b, or Tait,
/// p = rho0 c0^2 / gamma ((rho / rho0)^gamma - 1) + p_b.
double pressureOf(const FluidProperties& f, double rho);
/// The inverse: the density of the fluid at pressure p (bounded below by 1e-3 rho0).
double densityOf(const FluidProperties& f, double p);

/// Internal (compression) energy per unit mass relative to rho0, e(rho) = int_rho0^rho p/r^2 dr:
/// linear EOS c0^2 (ln(rho/rho0) + rho0/rho - 1) + p_b (1/rho0 - 1/rho); Tait likewise. With it
/// the energy of a weakly compressible fluid closes (kinetic + e + gravity potential).
double internalEnergyOf(const FluidProperties& f, double rho);

}  // namespace poresph
