#pragma once
// A sweep: `millwear charge` over the values of one scene key (`millwear sweep`), the points
// in parallel threads, into one folder:
//
//   OUT/sweep.csv         one row per value: the key's value, speed, charge mass, power per
//                         mill and specific power (kW/t of charge), toe and shoulder, collision
//                         power, liner shear power, each with its standard error (batch means
//                         over the measured window, metrics/batch_means.hpp, a lower bound; or
//                         with replicates, the standard error of their mean); toe and shoulder
//                         read "centrifuged" where the charge covers the whole shell; the
//                         liner-damage share (liner_impact_share, docs/trajectories.md)
//   OUT/points/NN/        each point's `millwear charge` files (charge_summary.csv, ...);
//                         with --replicates N, replicate K's in OUT/points/NN.rK/
//   OUT/plots/            sweep_power, sweep_toe_shoulder, sweep_collision_shear (PNG, SVG)
//   OUT/manifest.json     program, scene, key, values, --set overrides, fidelity, points
//
// Every point's scene (the file, the --set overrides, then KEY=VALUE) is read and checked
// before anything runs or is written. A point is the same run as `millwear charge` of its
// scene: the same figures, bit for bit, whatever the number of threads.
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear::study {

// The values of a --vary: KEY=FIRST:LAST:STEP (LAST included when the steps reach it within
// a millionth of STEP) or KEY=V1,V2,... Values are numbers, kept as written for the scene.
struct SweepAxis {
  std::string key;
  std::vector<std::string> texts;  // as put into the scene ("0.7")
  std::vector<double> values;
};
// Throws InputError("", "--vary", ...) for a malformed text, a non-number, a step that is
// not positive, LAST below FIRST, or more than 1000 values.
SweepAxis parse_vary(const std::string& text);

struct SweepRequest {
  std::string scene_file;
  std::string out;
  std::string vary;                    // KEY=FIRST:LAST:STEP or KEY=V1,V2,...
  std::vector<std::string> overrides;  // --set KEY=VALUE, before the varied key
  std::string fidelity;                // "": the scene's own
  double revolutions = 0.0;            // measured revolutions per point (0: the scene's)
  int jobs = 0;                        // points at once (0: the hardware's cores)
  // Charges per value, seeds s .. s+N-1: the figures are their mean and its standard error
  // (1: one charge, errors from its batch means, a lower bound).
  int replicates = 1;
  bool figures = true;
  std::string commit;                  // the program's git commit, for the manifest
};

// One value's results, per mill (kW, t), with standard errors (*_sem) from batch means.
struct SweepPoint {
  int index = 0;
  std::string text;
  double value = 0.0;
  double speed_fraction_critical = 0.0, speed_rpm = 0.0, filling = 0.0;
  std::size_t disks = 0, lost_disks = 0;
  double charge_t = 0.0;                       // mean charge mass in the mill
  double power_kW = 0.0, power_kW_sem = 0.0;   // drive power
  double specific_kW_per_t = 0.0, specific_kW_per_t_sem = 0.0;
  double collision_kW = 0.0, collision_kW_sem = 0.0;    // particle-particle dissipation
  double shear_kW = 0.0, shear_kW_sem = 0.0;            // liner shear (Archard) power
  double toe_deg = 0.0, toe_deg_sem = 0.0;              // from 6 o'clock, + rising side
  double shoulder_deg = 0.0, shoulder_deg_sem = 0.0;
  bool centrifuged = false;   // over the window: no toe or shoulder (metrics/charge_summary.hpp)
  // Of the first-impact energy of the flights from the lifters, the share on the bare liner
  // above the toe (metrics/trajectories.hpp; NaN without a landed flight or a toe).
  double liner_impact_share = 0.0, liner_impact_share_sem = 0.0;
  double simulated_s = 0.0, wall_s = 0.0;
  int replicates = 1;                          // charges folded into the figures
  std::string error;                           // a lost disk or a failed run: figures suspect
  std::string unsound;  // the window's split of the power not sound (unsound_energy_split; "": sound)
  std::string unsteady;  // the charge still settling in the window (unsteady_window; "": steady)
};

// Replicates of one value folded: each figure's mean over them, its error the standard error
// of that mean; centrifuged if any replicate was; the first error kept.
SweepPoint fold_replicates(const std::vector<SweepPoint>& replicates);

struct SweepResult {
  std::string scene_name;
  SweepAxis axis;
  std::vector<SweepPoint> points;              // in the order of the values
  int jobs = 1;
  double wall_s = 0.0;
  std::vector<std::string> figure_files;
  std::string figure_error;                    // figures failed (the tables are written)
  bool figures_failed = false;                 // ... with gnuplot installed (exit 1, as run's)
  bool failed() const;                         // a point has an error
};

struct SweepCallbacks {
  // Once every point's scene is checked, before anything runs: the points' count and jobs.
  std::function<void(const SweepAxis&, int jobs)> on_start;
  // After each point, from its thread, one call at a time.
  std::function<void(const SweepPoint&, int done, int total)> on_point;
};

// Validates (InputError, nothing written), locks OUT (io/folder_lock.hpp), runs the points,
// writes the files above into OUT's staging folder and moves them into OUT once the sweep has
// ended (io/staging.hpp): until then an earlier sweep's files stay as they were. Figures need
// gnuplot; their failure is reported in figure_error, never thrown.
SweepResult run_sweep(const SweepRequest& request, const SweepCallbacks& callbacks = {});

// The scenes of a sweep's points, checked as run_sweep checks them (InputError naming
// "--vary" or "--set" and the key).
std::vector<Scene> sweep_scenes(const SweepRequest& request, const SweepAxis& axis);

}  // namespace millwear::study
