#pragma once
// The scene's `reference:` section (docs/choosing-settings.md, docs/scene-format.md): the one
// quantity a run is judged by, and optionally its closed-form value. `poresph run` evaluates it on
// the final state and the run's timeseries.csv and writes DIR/reference.yaml; `poresph study`
// (libcore/study.hpp) reads that file to measure each run's error.
//
//   reference: {quantity: laplace_jump, centre: [x, y], radius: R, value: 33.33}
//   reference: {quantity: fluid_max_speed, at: end}          # any timeseries column
//   reference: {quantity: kinetic_energy, at: max}           # ... at end | max | min | <time>
//   reference: {quantity: time, at: first drainage_percolated}          # ... | first COLUMN
//   reference: {quantity: time, at: 'first solid_damage_max >= 0.1'}    #   [>= VALUE | <= VALUE]
//
// Quantities (computed here, from the store's fields, by the code every run executes):
//   <timeseries column>         a column of timeseries.csv at `at` (end, max, min, or a time in s:
//                               linear interpolation between the rows around it), or, with
//                               `at: first COLUMN [>= VALUE]` (or `<=`), the time of the first row
//                               where timeseries COLUMN is nonzero (an event; the run is not
//                               measured when it did not happen) or first reaches VALUE
//                               (interpolated between that row and the one before)
//   laplace_jump                mean pressure of the fluid particles with colour > 0 within
//                               R - 3h of `centre` minus that of the fluid particles beyond R + 3h
//                               (Young-Laplace, thesis Eq. 1.5: gamma / R in 2D, 2 gamma / R in 3D)
//   spurious_capillary_number   Ca = mu u_max / gamma: the largest fluid speed times the largest
//                               fluid viscosity over the surface tension (`surface_tension`, else
//                               the scene's fluid.surface_tension); the spurious currents of a
//                               static drop (CSF, thesis Eqs. 5.6-5.8); its reference value is 0
//   hoop_stress, radial_stress  sigma_tt / sigma_rr about `centre` at `point`: a Shepard kernel
//                               average of the stress of the solid particles around `point`
//                               (Kirsch, Lame); place it more than a kernel support away from
//                               mirror layers
//   period                      the period of the oscillation of timeseries `column` (mean spacing
//                               of the crossings of its mean, linear interpolation), times
//                               `factor` (2 for an energy column: energy oscillates at twice the
//                               displacement frequency); the vibrating bar (thesis Ch. 3, Eq. 4)
//   material_volume             sum of m / rho of the particles of `material` inside `box`
//                               {min, max}, times `scale` (default 1; 1/w turns the gas area in a
//                               slit of width w into its penetration length)
// State quantities are taken at the end of the run (`at: end`, the default; a failed run: the last
// state that passed every check). `value` (optional): the closed-form value; the error is
// |measured - value| / |value|, or |measured| when value is 0. Without `value` a study measures
// each run against its finest run.
#include <array>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace poresph {

class ParameterSet;
struct Scene;

struct ReferenceSpec {
  bool declared = false;     ///< the scene has a `reference:` section
  std::string quantity;      ///< a named quantity (above) or a timeseries column
  std::string at = "end";    ///< end | max | min | a time (s) as text
  double atTime = -1.0;      ///< the time when `at` is a number
  bool hasValue = false;
  double value = 0.0;
  std::array<double, 3> centre{0, 0, 0}, point{0, 0, 0}, boxMin{0, 0, 0}, boxMax{0, 0, 0};
  double radius = 0.0;
  double surfaceTension = 0.0;  ///< 0: the scene's fluid.surface_tension
  std::string column;           ///< `period`: the oscillating column
  double factor = 1.0;          ///< `period`: multiplies the period of the column
  std::string material;         ///< `material_volume`
  double scale = 1.0;           ///< `material_volume`
  YAML::Node echo;              ///< what run.yaml shows
  bool isStateQuantity() const;
};

/// Names of the quantities computed from the state (the others are timeseries columns).
const std::vector<std::string>& referenceQuantityNames();

/// Reads and checks the `reference:` section (unknown keys and missing ones are InputErrors naming
/// file, line, key and value). `dimension`: the scene's.
ReferenceSpec readReference(const ParameterSet& section, int dimension);

struct ReferenceResult {
  bool ok = false;          ///< measured (false: `note` says why)
  double measured = 0.0;
  bool hasValue = false;
  double value = 0.0;
  double error = 0.0;       ///< relative, or absolute when value is 0
  bool relative = true;
  std::string note;
};

/// Evaluates the scene's reference on the scene's current state and the run's timeseries.csv
/// (`timeseries`: its path; "" when there is none).
ReferenceResult evaluateReference(const Scene& scene, const std::string& timeseries);
/// DIR/reference.yaml: quantity, at, measured, value, error, relative, ok, note.
std::string referenceYaml(const ReferenceSpec& spec, const ReferenceResult& r);

/// The error of `measured` against `value`: relative, or absolute when value is 0.
double referenceError(double measured, double value, bool* relative = nullptr);

}  // namespace poresph
