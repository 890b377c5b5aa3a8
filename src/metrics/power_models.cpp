#include "common/units.hpp"
#include "metrics/power_models.hpp"

#include <algorithm>
#include <cmath>

namespace millwear {

MorrellResult morrell_power(const MorrellInput& in) {
  constexpr double g = kGravity;
  const double J = in.filling, phi = in.speed_fraction;
  const double rm = 0.5 * in.diameter_m, L = in.length_m, rho_c = in.charge_density_t_m3;
  const double Nc_rps = 42.3 / std::sqrt(in.diameter_m) / 60.0;
  const double Nm = phi * Nc_rps;  // rev/s
  const double phi_c = std::max(phi, 0.35 * (3.364 - J));
  const double thT = 2.5307 * (1.2796 - J) * (1.0 - std::exp(-19.42 * (phi_c - phi))) + kPi / 2.0;
  const double thS =
      kPi / 2.0 - (thT - kPi / 2.0) * ((0.3386 + 0.1041 * phi) + (1.54 - 2.5673 * phi) * J);
  const double z = std::pow(1.0 - J, 0.4532);
  const double r_bar = 0.5 * rm * (1.0 + std::sqrt(1.0 - 2.0 * kPi * J / (2.0 * kPi + thS - thT)));
  const double N_bar = 0.5 * Nm;
  const double tc = (2.0 * kPi - thT + thS) / (2.0 * kPi * N_bar);
  const double tf = std::sqrt(2.0 * r_bar * (std::sin(thS) - std::sin(thT)) / g);
  const double beta = tc / (tc + tf);
  const double ri = rm * std::sqrt(1.0 - 2.0 * kPi * beta * J / (2.0 * kPi + thS - thT));
  const double a = rm - z * ri;
  const double potential = kPi * g * L * Nm * rm / (3.0 * a) *
                           (2.0 * rm * rm * rm - 3.0 * z * rm * rm * ri + ri * ri * ri * (3.0 * z - 2.0)) *
                           (rho_c * (std::sin(thS) - std::sin(thT)));
  const double kinetic = L * rho_c * std::pow(Nm * rm * kPi / a, 3.0) *
                         (std::pow(a, 4.0) - std::pow(ri, 4.0) * std::pow(z - 1.0, 4.0));
  MorrellResult r;
  r.toe_rad = thT;
  r.shoulder_rad = thS;
  r.toe_deg_from_bottom = deg_from_rad(thT) - 270.0;  // toe lies on the falling side (< 0)
  r.shoulder_deg_from_bottom = deg_from_rad(thS) + 90.0;
  r.net_power_kW = potential + kinetic;
  return r;
}

double austin_power_W(const AustinInput& in) {
  const double J = in.filling, Jb = in.ball_filling, phi = in.speed_fraction;
  const double rho_s = in.ore_density_kg_m3 / 1000.0, rho_b = in.ball_density_kg_m3 / 1000.0;  // t/m^3
  const double slurry = rho_s / in.solids_mass_fraction;
  const double load = (1.0 - in.porosity) * slurry * J + 0.6 * Jb * (rho_b - slurry);
  const double speed = phi * (1.0 - 0.1 / std::pow(2.0, 9.0 - 10.0 * phi));
  const double kW = 10.6 * std::pow(in.diameter_m, 2.5) * in.length_m * (1.0 - 1.03 * J) * load * speed;
  return 1000.0 * kW;
}

}  // namespace millwear
