#pragma once
// Analytic mill power and charge-shape models, for checking the engine.
namespace millwear {

// Morrell's C-model (continuum) for the cylindrical section (Morrell, "Power draw of wet
// tumbling mills and its relationship to charge dynamics", Parts 1 and 2, Trans. Instn Min.
// Metall. C 105, 1996): empirical toe and shoulder angles, then net charge-motion power.
// Dry charge: the slurry term is dropped (rho_p = 0).
struct MorrellInput {
  double diameter_m = 0.0;        // inside liners
  double length_m = 0.0;          // belly length
  double filling = 0.0;           // J, fraction of mill volume
  double speed_fraction = 0.0;    // phi, fraction of critical (Nc = 42.3/sqrt(D) rpm)
  double charge_density_t_m3 = 0.0;  // bulk density of the charge
};
struct MorrellResult {
  double toe_rad = 0.0;       // Morrell's angle convention (anticlockwise from horizontal)
  double shoulder_rad = 0.0;
  double toe_deg_from_bottom = 0.0;       // + toward the rising side
  double shoulder_deg_from_bottom = 0.0;  // + toward the rising side
  double net_power_kW = 0.0;
};
MorrellResult morrell_power(const MorrellInput& in);

}  // namespace millwear
