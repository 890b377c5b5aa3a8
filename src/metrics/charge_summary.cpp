// Charge figures from a window's accounting sums.
#include "metrics/charge_summary.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

#include "common/units.hpp"
#include "metrics/batch_means.hpp"

namespace millwear {

namespace {

// A bin is part of the bed while its solids are at least this share of the fullest bin's.
constexpr double kBedThreshold = 0.5;

// Where the occupancy, taken at each bin's centre and linear between centres, crosses the
// threshold on a walk in direction dir (+1 counter-clockwise) from the centre of bin `from`
// (at or above it); deg counter-clockwise from 6 o'clock, in (-180, 180]. dir x 180 when no
// bin is under it.
double edge_from_bin(const std::array<double, kShapeAngleBins>& occ, double threshold, int from, int dir) {
  const double bin_deg = 360.0 / kShapeAngleBins;
  double previous = occ[static_cast<std::size_t>(from)];
  for (int k = 1; k < kShapeAngleBins; ++k) {
    const int bin = ((from + dir * k) % kShapeAngleBins + kShapeAngleBins) % kShapeAngleBins;
    const double o = occ[static_cast<std::size_t>(bin)];
    if (o < threshold) {
      const double edge = std::remainder((from + 0.5) * bin_deg +
                                             dir * ((k - 1) * bin_deg + bin_deg * (previous - threshold) / (previous - o)),
                                         360.0);
      return edge == -180.0 ? 180.0 : edge;
    }
    previous = o;
  }
  return dir * 180.0;
}

// The bed's edge on the side dir of 6 o'clock (+1: the counter-clockwise side), deg from 6
// o'clock signed as above: a walk from the bottom bin of that side until the occupancy drops
// under half the peak. A bed that does not reach 6 o'clock on either side (one riding up
// the shell, or a short window's few samples) is the run of bins around the fullest one,
// walked from there. NaN when nothing reached the band.
double charge_edge_deg(const std::array<double, kShapeAngleBins>& occ, int dir) {
  const auto peak = std::max_element(occ.begin(), occ.end());
  if (!(*peak > 0.0)) return std::nan("");
  const double threshold = kBedThreshold * *peak;
  if (occ.front() < threshold && occ.back() < threshold)
    return edge_from_bin(occ, threshold, static_cast<int>(peak - occ.begin()), dir);
  const double bin_deg = 360.0 / kShapeAngleBins;
  double previous = 0.0;  // the occupancy of the bin before on the walk
  for (int k = 0; k < kShapeAngleBins; ++k) {
    const int bin = ((dir > 0 ? k : -k - 1) % kShapeAngleBins + kShapeAngleBins) % kShapeAngleBins;
    if (occ[bin] < threshold) {
      // Between the centres of the last bin at or above the threshold (k - 1) and this one;
      // a bottom bin already under it (the bed starts on the other side) puts the edge at
      // 6 o'clock.
      const double edge = k == 0 ? 0.0
                                 : (k - 0.5) * bin_deg + bin_deg * (previous - threshold) / (previous - occ[bin]);
      return dir > 0 ? edge : -edge;
    }
    previous = occ[bin];
  }
  return dir * 180.0;
}

}  // namespace

MorrellResult morrell_estimate(const Scene& scene, const ChargeSummary& s) {
  if (!(scene.mill.speed_fraction_critical < 1.0)) {
    const double nan = std::nan("");
    return {nan, nan, nan, nan, nan};
  }
  const double area_m2 = kPi * scene.radius_m() * scene.radius_m();
  MorrellInput in;
  in.diameter_m = scene.mill.diameter_m;
  in.length_m = 1.0;
  in.filling = scene.charge.filling;
  in.speed_fraction = scene.mill.speed_fraction_critical;
  in.charge_density_t_m3 = s.mass_kg / scene.slice_thickness() / (scene.charge.filling * area_m2) / 1000.0;
  return morrell_power(in);
}

AustinInput austin_input(const Scene& scene) {
  double ore = 0.0, balls = 0.0;
  int rocks = 0, ball_species = 0;
  for (const SpeciesDef& sp : scene.charge.species) {
    if (!scene.species_in_use(sp)) continue;
    (sp.is_ball ? balls : ore) += sp.density_kg_m3;
    ++(sp.is_ball ? ball_species : rocks);
  }
  AustinInput in;
  in.diameter_m = scene.mill.diameter_m;
  in.length_m = 1.0;
  in.filling = scene.charge.filling;
  in.ball_filling = scene.charge.ball_filling;
  in.speed_fraction = scene.mill.speed_fraction_critical;
  in.ore_density_kg_m3 = rocks > 0 ? ore / rocks : 0.0;
  in.ball_density_kg_m3 = ball_species > 0 ? balls / ball_species : 0.0;
  return in;
}

double austin_estimate_W_per_m(const Scene& scene) {
  const AustinInput in = austin_input(scene);
  if (!(in.speed_fraction < 1.0) || !(in.ore_density_kg_m3 > 0.0)) return std::nan("");
  return austin_power_W(in);
}

std::string unsound_energy_split(const ChargeFigures& f) {
  const ChargeSummary& s = f.summary;
  const double unbooked_W =
      s.power_W - s.collision_power_W - s.liner_dissipation_W - s.solver_dissipation_W - s.kinetic_change_W;
  char buf[400];
  if (f.collision_kW_per_m >= 0.0 && s.power_W != 0.0 &&
      std::fabs(unbooked_W) > kUnbookedPowerShare * std::fabs(s.power_W)) {
    std::snprintf(buf, sizeof buf,
                  "the energy books do not close in the measured window: %.0f%% of the drive's power is not booked "
                  "as dissipation or as the charge's energy, so the collision power, the utilisation and the split "
                  "of the power are not sound (docs/stability.md)",
                  100.0 * unbooked_W / s.power_W);
    return buf;
  }
  if (!(f.collision_kW_per_m < 0.0)) return "";
  std::snprintf(buf, sizeof buf,
                "the contacts between disks gave the charge energy in the measured window (collision power %.3g "
                "kW/m, the drive's %.3g kW/m): the solver's error is larger than the collisions' dissipation here, "
                "so the collision power, the utilisation and the split of the drive's power are not sound; a "
                "smaller solver.time_step shrinks the error (docs/stability.md)",
                f.collision_kW_per_m, f.power_kW_per_m);
  return buf;
}

double energy_share_of_power(const ChargeSummary& s) {
  return s.power_W != 0.0 ? s.kinetic_change_W / s.power_W : 0.0;
}

std::string unsteady_window(const ChargeSummary& s) {
  const double into_energy = energy_share_of_power(s);
  if (!(std::fabs(into_energy) > kSteadyEnergyShare)) return "";
  // Energy gained is drawn from the drive; energy lost (a charge slowing or settling) comes out
  // on top of it.
  char buf[300];
  char part[120];
  if (into_energy > 0.0)
    std::snprintf(part, sizeof part, "%.0f%% of the drive's power went into its kinetic and potential energy",
                  100.0 * into_energy);
  else
    std::snprintf(part, sizeof part, "its kinetic and potential energy fell by %.0f%% of the drive's power",
                  -100.0 * into_energy);
  std::snprintf(buf, sizeof buf,
                "the charge was not steady in the window: %s; spin it up longer (solver.spinup_revolutions) or "
                "measure more revolutions",
                part);
  return buf;
}

ChargeSummary summarize(const Accounting& acc, double mill_speed_rad_s, double gravity_m_s2) {
  ChargeSummary s;
  s.time_s = acc.time_s;
  s.escaped = acc.escaped;
  s.non_finite = acc.non_finite;
  if (!(acc.time_s > 0.0)) return s;
  const double t = acc.time_s;
  s.power_W = acc.drive_work_J / t;
  s.torque_Nm = acc.torque_impulse_Nms / t;
  s.collision_power_W = (acc.pp_normal_J + acc.pp_tangent_J) / t;
  s.liner_dissipation_W = (acc.pl_normal_J + acc.pl_tangent_J) / t;
  s.solver_dissipation_W = acc.solver_position_J / t;
  s.kinetic_change_W = ((acc.kinetic_J_end - acc.kinetic_J_start) +
                        (acc.potential_J_end - acc.potential_J_start)) / t;
  for (double w : acc.shear_work_J) s.shear_work_rate_W += w;
  const double slip_J = s.shear_work_rate_W + (acc.options.packed_wear ? 0.0 : acc.packed_shear_work_J);
  if (slip_J > 0.0) s.packed_shear_share = acc.packed_shear_work_J / slip_J;
  s.shear_work_rate_W /= t;
  if (acc.steps > 0) s.mean_packed_disks = static_cast<double>(acc.packed_disk_steps) / acc.steps;
  if (acc.mass_time_kg_s > 0.0) {
    s.mass_kg = acc.mass_time_kg_s / acc.shape_time_s;
    s.centre_of_mass_m = acc.moment_time_kg_m_s / acc.mass_time_kg_s;
    // Steady state: the drive holds the charge's weight off-centre, torque = M g x_cm.
    s.torque_arm_Nm = s.mass_kg * gravity_m_s2 * s.centre_of_mass_m.x;
  }
  // Toe and shoulder in the frame where the charge rises on the + side.
  const int dir = mill_speed_rad_s < 0 ? -1 : 1;
  const Vec2 c = s.centre_of_mass_m;
  // Counter-clockwise from 6 o'clock is toward +x at the bottom.
  if (c.x != 0.0 || c.y != 0.0) s.centre_of_mass_deg = dir * deg_from_rad(std::atan2(c.x, -c.y));
  s.shoulder_deg = dir * charge_edge_deg(acc.shell_band_occupancy, dir);
  s.toe_deg = dir * charge_edge_deg(acc.shell_band_occupancy, -dir);
  const auto [lo, hi] = std::minmax_element(acc.shell_band_occupancy.begin(), acc.shell_band_occupancy.end());
  s.centrifuged = *hi > 0.0 && *lo >= kBedThreshold * *hi;
  return s;
}

MillEnergyFigures mill_energy_figures(const ChargeSummary& s, double slice_thickness_m, double mill_length_m,
                                      double liner_loss_rate_m2_per_s, double liner_density_kg_m3) {
  MillEnergyFigures f;
  const double per_mill = mill_length_m / slice_thickness_m;
  f.charge_mass_kg = s.mass_kg * per_mill;
  f.power_W = s.power_W * per_mill;
  if (f.charge_mass_kg > 0.0) f.specific_power_W_per_kg = f.power_W / f.charge_mass_kg;
  // The lost cross-section runs the mill's whole length.
  const double liner_kg_per_s = liner_loss_rate_m2_per_s * mill_length_m * liner_density_kg_m3;
  f.liner_wear_kg_per_J = f.power_W > 0.0 ? liner_kg_per_s / f.power_W : std::nan("");
  return f;
}

ChargeFigures charge_figures(const Accounting& acc, const Scene& scene, double omega_rad_s) {
  ChargeFigures f;
  f.summary = summarize(acc, omega_rad_s, kGravity);
  const double per_m = 1e-3 / scene.slice_thickness();  // W per slice -> kW per metre
  f.power_kW_per_m = f.summary.power_W * per_m;
  f.torque_arm_kW_per_m = omega_rad_s * f.summary.torque_arm_Nm * per_m;
  f.collision_kW_per_m = f.summary.collision_power_W * per_m;
  f.liner_kW_per_m = f.summary.liner_dissipation_W * per_m;
  f.solver_kW_per_m = f.summary.solver_dissipation_W * per_m;
  f.liner_shear_kW_per_m = f.summary.shear_work_rate_W * per_m;
  return f;
}

ChargeFigureErrors charge_figure_errors(const std::vector<ChargeFigures>& batches) {
  ChargeFigureErrors e;
  if (batches.size() < 2) return e;
  const auto sem = [&batches](auto figure) {
    std::vector<double> x;
    x.reserve(batches.size());
    for (const ChargeFigures& b : batches) x.push_back(figure(b));
    return batch_means(x).sem;
  };
  e.power_kW_per_m = sem([](const ChargeFigures& b) { return b.power_kW_per_m; });
  e.collision_kW_per_m = sem([](const ChargeFigures& b) { return b.collision_kW_per_m; });
  e.liner_shear_kW_per_m = sem([](const ChargeFigures& b) { return b.liner_shear_kW_per_m; });
  e.utilization = sem([](const ChargeFigures& b) {
    return b.power_kW_per_m != 0.0 ? b.collision_kW_per_m / b.power_kW_per_m : 0.0;
  });
  e.mass_kg = sem([](const ChargeFigures& b) { return b.summary.mass_kg; });
  e.centre_of_mass_deg = sem([](const ChargeFigures& b) { return b.summary.centre_of_mass_deg; });
  e.packed_shear_share = sem([](const ChargeFigures& b) { return b.summary.packed_shear_share; });
  bool centrifuged = false;
  for (const ChargeFigures& b : batches) centrifuged = centrifuged || b.summary.centrifuged;
  if (!centrifuged) {
    e.toe_deg = sem([](const ChargeFigures& b) { return b.summary.toe_deg; });
    e.shoulder_deg = sem([](const ChargeFigures& b) { return b.summary.shoulder_deg; });
  }
  return e;
}

}  // namespace millwear
