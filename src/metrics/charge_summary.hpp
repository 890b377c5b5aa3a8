#pragma once
// What a measured window says about the charge: power, torque, the energy shares, the centre
// of mass, toe and shoulder (from the shell-band occupancy), the packing share; per slice in
// SI (ChargeSummary) and per metre of mill (ChargeFigures). Pure functions of the window's sums.
//
// Toe and shoulder, defined: the shell band is the annulus from the shell inward to one of
// the largest particle diameters inside the lifter tips (the engine's shape band). Each step
// adds every disk's area inside the band to its 5 deg angle bin, so a bin's sum over the
// window is its time-averaged solids area. The bed's value is the fullest bin. Walking from
// 6 o'clock up the rising side, the shoulder is where the solids fall under half the bed's
// value: between the centres of the last bin at or above it and the first below it, by linear
// interpolation (so it moves continuously, not in 5 deg steps); walking down the falling side,
// the toe likewise. A bed that reaches 6 o'clock on neither side (it rides up the shell, or a
// window of a few steps caught it so) is walked from its fullest bin both ways instead, so
// its toe may lie on the rising side (> 0). A window in which no disk reached the band has
// no toe or shoulder: NaN. A charge whose band holds more
// than half the bed's value all the way round covers the whole shell: it is centrifuged, and
// has no toe or shoulder (toe_deg and shoulder_deg then read -180 and 180 in the rising-side
// frame, and `centrifuged` says why).
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/accounting.hpp"
#include "geometry/vec2.hpp"
#include "metrics/power_models.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Derived figures of a window (SI).
struct ChargeSummary {
  double time_s = 0.0;
  double power_W = 0.0;                 // drive work / time (per slice)
  double torque_Nm = 0.0;               // mean torque the drive supplies (per slice)
  double torque_arm_Nm = 0.0;           // M g x_cm from the centre of mass (per slice)
  double collision_power_W = 0.0;       // particle-particle dissipation rate
  double liner_dissipation_W = 0.0;     // particle-liner dissipation rate
  double solver_dissipation_W = 0.0;    // position-correction share
  double kinetic_change_W = 0.0;        // (KE+PE change) / time
  double mass_kg = 0.0;                 // mean active charge mass
  Vec2 centre_of_mass_m;
  double centre_of_mass_deg = 0.0;  // its angle from 6 o'clock, + toward the rising side
  double toe_deg = 0.0;       // from 6 o'clock, + toward the rising side (NaN: none, see above)
  double shoulder_deg = 0.0;  // from 6 o'clock, + toward the rising side (NaN: none)
  bool centrifuged = false;   // the band is full all round: no toe or shoulder
  double shear_work_rate_W = 0.0;       // total on the liner
  double packed_shear_share = 0.0;      // of all liner slip work (packed included), packed disks'
  double mean_packed_disks = 0.0;       // disks riding the liner for over a revolution
  std::int64_t escaped = 0;
  std::int64_t non_finite = 0;
};
ChargeSummary summarize(const Accounting& acc, double mill_speed_rad_s, double gravity_m_s2);

// Figures of a measured window, per metre of mill length, in kW (the unit the stage files,
// CSV files and figures keep them in; the summary's sums are SI).
struct ChargeFigures {
  ChargeSummary summary;          // per slice
  double power_kW_per_m = 0.0;    // drive power / slice thickness
  double torque_arm_kW_per_m = 0.0;  // omega * M g x_cm / thickness
  double collision_kW_per_m = 0.0;
  double liner_kW_per_m = 0.0;
  double solver_kW_per_m = 0.0;
  double liner_shear_kW_per_m = 0.0;  // slip work rate on the liner (what wears it)
};

ChargeFigures charge_figures(const Accounting& acc, const Scene& scene, double omega_rad_s);

// The share of the drive's power that went into the charge's kinetic and potential energy
// over the window (0 when the drive did no work). A steady window puts the power into
// dissipation (rule 2: long enough for the figures to settle); at 75% of critical the lab
// mill's share is 0.1% over 8 revolutions, and a window past kSteadyEnergyShare is not steady.
double energy_share_of_power(const ChargeSummary& s);
constexpr double kSteadyEnergyShare = 0.1;
// What a window past kSteadyEnergyShare is told ("" for a steady one): its figures are those
// of a charge still settling, not of the mill turning steadily.
std::string unsteady_window(const ChargeSummary& s);

// Collisions between disks only take energy out of a real charge. A window whose disk-disk
// contacts gave the charge energy (collision power below 0) has the solver's own error larger
// than that dissipation: in a heavily loaded bed turning fast (a centrifuged charge) the
// contact normals, fixed over a step while the bed turns, move energy from the disk-disk
// contacts to the liner's, in proportion to the time step; the split of the drive's power,
// the utilisation and the drive's power itself are then not sound. So are they when the books
// do not close: the drive's work less the dissipation booked and the charge's energy change
// over a tenth of the drive's work (the soft solver closes them to rounding; the library,
// which books its own restitution, within about 5% in sound scenes, and not at a restitution
// near 1 without friction). Empty for a sound window, else the sentence that says so.
std::string unsound_energy_split(const ChargeFigures& f);
constexpr double kUnbookedPowerShare = 0.1;

// Morrell's C-model (power_models.hpp) for the scene's mill and speed, per metre of mill
// length, at the charge's own filling and with the bulk density of the measured bed: its
// mass per metre over the filled area. An analytic check on a window's power and on its toe
// and shoulder; the 2D bed packs denser than a 3D charge, so the density is the slice's.
// The model's toe and shoulder are fits to mills turning below critical speed: at or above it
// there is no estimate (every field NaN).
MorrellResult morrell_estimate(const Scene& scene, const ChargeSummary& s);

// The scene's inputs to Austin's SAG power equation (power_models.hpp), per metre of mill
// length: its mill, speed, filling and ball filling, the rock species' mean density as the
// ore's and the balls' as the balls' (each species an equal share of its kind, as filled; 0
// for a kind the charge does not have).
AustinInput austin_input(const Scene& scene);
// Its power per metre (W/m). A model of SAG mills turning below critical speed: NaN at or
// above it, and for a charge without rock (a ball mill).
double austin_estimate_W_per_m(const Scene& scene);

// Batch-means standard errors of a window's figures: the spread of the figures of its batches
// (each a stretch of the window measured on its own). The batches are taken as independent,
// so these are lower bounds on the error of a correlated series. NaN with fewer than two
// batches; toe and shoulder NaN when a batch is centrifuged (it has neither).
struct ChargeFigureErrors {
  double power_kW_per_m = std::nan("");
  double collision_kW_per_m = std::nan("");
  double liner_shear_kW_per_m = std::nan("");  // slip work on the liner (the wear's driver)
  double utilization = std::nan("");           // collision / power
  double mass_kg = std::nan("");               // per slice
  double centre_of_mass_deg = std::nan("");
  double toe_deg = std::nan("");
  double shoulder_deg = std::nan("");
  double packed_shear_share = std::nan("");
};
ChargeFigureErrors charge_figure_errors(const std::vector<ChargeFigures>& batches);

// A slice's figures scaled to the whole mill (its length) and set against the energy drawn.
struct MillEnergyFigures {
  double charge_mass_kg = 0.0;           // per mill
  double power_W = 0.0;                  // per mill
  double specific_power_W_per_kg = 0.0;  // power per charge mass
  double liner_wear_kg_per_J = 0.0;      // liner metal lost per energy drawn
};
// liner_loss_rate_m2_per_s: the liner's cross-section lost per operating second (every lifter
// and the shell); liner_density: its metal's.
MillEnergyFigures mill_energy_figures(const ChargeSummary& s, double slice_thickness_m, double mill_length_m,
                                      double liner_loss_rate_m2_per_s, double liner_density_kg_m3);

}  // namespace millwear
