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

// Austin's SAG mill power equation (Austin, "A mill power equation for SAG mills", Minerals
// and Metallurgical Processing 7, 1990): the power of the cylindrical section, no cone ends.
// In its units (kW; D, L in m; densities in t/m^3):
//   P = 10.6 D^2.5 L (1 - 1.03 J) [(1 - f) (rho_s / w) J + 0.6 J_b (rho_b - rho_s / w)]
//       phi (1 - 0.1 / 2^(9 - 10 phi))
// with f the charge's porosity and w the solids' mass fraction of the slurry filling it.
struct AustinInput {
  double diameter_m = 0.0;        // inside liners
  double length_m = 0.0;          // belly length
  double filling = 0.0;           // J, the whole charge's fraction of mill volume
  double ball_filling = 0.0;      // J_b, the balls' fraction of mill volume
  double speed_fraction = 0.0;    // phi, fraction of critical
  double ore_density_kg_m3 = 0.0;   // rho_s
  double ball_density_kg_m3 = 0.0;  // rho_b
  double porosity = 0.3;            // f, Austin's value
  double solids_mass_fraction = 0.8;  // w, Austin's value
};
double austin_power_W(const AustinInput& in);

}  // namespace millwear
