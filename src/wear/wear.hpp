#pragma once
// Wear: Archard's law per liner edge, the staged and continuous wear loops, stage metrics,
// lifter life and the C_model rules. The loop is a fixed sequence of named stages:
//   simulate_window -> accumulate_work -> archard_depths -> apply_wear -> resmooth ->
//   stage_metrics -> (caller) write_stage
#include <functional>
#include <string>
#include <vector>

#include "engine/charge_run.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Archard: A dh = C dw, with A = edge length x slice thickness.
inline double archard_depth_m(double shear_work_J, double edge_length_m, double thickness_m,
                              double wear_rate_m3_per_J) {
  return wear_rate_m3_per_J * shear_work_J / (edge_length_m * thickness_m);
}

// The real wear rate C (m^3/J) the scene asks for: given, or calibrated from a measured
// area or height loss rate against the new liner's shear-work field (work per edge, J/s).
double real_wear_rate(const Scene& scene, const MillGeometry& mill,
                      const std::vector<double>& shear_power_W);

// Work per edge of the liner unit(s) in lifter-local order: averaged over rows (one unit)
// or one vector per row when the scene wears rows on their own.
std::vector<std::vector<double>> unit_edge_work(const MillGeometry& mill,
                                                const std::vector<double>& edge_work,
                                                bool average_rows);

// Move every edge of a unit into the metal by its depth (edge depths become vertex
// displacements along the vertex normals), re-smooth (open and close with a disk of radius
// smoothing_m, with the neighbouring units either side), resample to the mesh, cut back
// whatever lies outside the unit before the update (wear never adds metal) and check the
// result is simple. Throws RunError if the worn surface is not a valid liner any more.
LinerUnit apply_wear(const LinerUnit& unit, const std::vector<double>& edge_depth_m,
                     double radius_m, double smoothing_m, const MillMeshDef& mesh);

// What one re-smoothing at smoothing_m does to the new lifter (apply_wear with no wear):
// the share of its area and of its height it removes. Corners round off a little; a
// feature narrower than 2 x smoothing_m goes entirely.
struct SmoothingLoss {
  double area_fraction = 0.0, height_fraction = 0.0;
};
SmoothingLoss smoothing_loss(const Scene& scene, double smoothing_m);

// The largest share of the new lifter one re-smoothing may remove before the scene is
// refused: more means the radius is wider than the lifter's narrowest part and would wear
// it away without any shear work.
constexpr double kMaxSmoothingAreaLoss = 0.05;
constexpr double kMaxSmoothingHeightLoss = 0.05;
// apply_wear merges points closer than this fraction of the lifter edge (mesh.lifter_edge_m):
// the bound on how far a worn surface can stand outside the one before (rounding aside).
constexpr double kSliverEdgeFraction = 0.01;

// Throw InputError(file, "wear.smoothing_radius", ...) if re-smoothing the new lifter at the
// scene's radius removes more than the bounds above; the message gives the largest radius
// that keeps within them.
void check_smoothing_radius(const Scene& scene, const std::string& file);

// Lifter area one wear update removed beyond its Archard depths (m^2): the area the
// re-smoothing took (the corners it rounded; negative: Archard's edge strips overstate what
// the vertex moves remove on a strongly curved lifter). Near zero while the radius is under
// half the lifter's narrowest part; large when a worn lifter has grown a feature the
// smoothing cuts away (a thin ridge). `before` is the unit the depths were applied to,
// `after` apply_wear's result. The wear loop stops when it removes over
// kMaxSmoothingAreaLoss of the new area.
double resmoothing_loss_m2(const LinerUnit& before, const LinerUnit& after, const std::vector<double>& edge_depth_m,
                           double radius_m);

// Wear a unit under a synthetic load field in place of the engine: `shear_power_W_per_m2`
// gives the shear power per unit area at a lifter-local point. The unit wears for
// sim_time_s of simulated time with C_model, in `updates` equal geometry updates.
// Without feedback from a real charge rule 1 is exact: C_model * n and time / n agree.
LinerUnit wear_under_load_field(const LinerUnit& unit, double radius_m,
                                const std::function<double(Vec2)>& shear_power_W_per_m2,
                                double c_model_m3_per_J, double sim_time_s, int updates,
                                double smoothing_m, const MillMeshDef& mesh);

// One finished stage: the liner at `hours` and what the charge does with it.
struct StageRecord {
  int stage = 0;                  // 0 = new
  double hours = 0.0;
  std::vector<LinerUnit> units;   // exact geometry (resume restarts from it)
  LifterMetrics lifter;           // of row 0 (or the shared unit)
  ChargeFigures charge;           // measured on this geometry
  double area_loss_rate_mm2_per_h = 0.0;      // of the lifter, at this geometry
  double area_loss_rate_rel_sem = 0.0;        // rule 2: batch-means relative error
  // Collision spectrum measured on this geometry (per log bin, see engine/accounting.hpp).
  std::vector<double> spectrum_count_per_s, spectrum_energy_W;
  // Wear rate of every mill boundary edge at this geometry (m per operating hour), and the
  // charge at the end of the measuring window (for snapshot figures).
  std::vector<double> edge_wear_rate_m_per_h;
  ChargeState snapshot;
  double mill_angle_rad = 0.0;    // mill rotation at the snapshot
  // The charge this stage started from: the previous stage's charge as its wear ended
  // (empty for a fresh, settled fill). A resumed stage restarts from it exactly.
  ChargeState start_charge;
  double wall_s = 0.0;
  double simulated_s = 0.0;
  std::int64_t disk_steps = 0;
  bool worn_out = false;          // the lifter reached the shell in this stage
};

struct WearHistory {
  std::vector<StageRecord> stages;
  double life_h = 0.0;            // hours to the replacement height
  bool life_extrapolated = false;
  double wear_rate_m3_per_J = 0.0;   // real C used
  std::vector<std::string> events;   // worn flat, escaped disks, NaN, rule-1 bound
};

struct WearProgress {
  int stage = 0;
  double hours = 0.0;             // operating hours reached
  double simulated_s = 0.0;
  double disk_steps_per_s = 0.0;
};

struct WearCallbacks {
  // Called after each stage record is complete (stage 0 first). Persist it here.
  std::function<void(const StageRecord&)> on_stage;
  std::function<void(const WearProgress&)> on_progress;
  // Cancellation hook (Ctrl-C, SIGTERM, `run --stop-after-stage`): polled before each
  // simulated window; when it returns true the loop stops and throws
  // RunError("interrupted"). Stages already passed to on_stage stay valid for resume_from.
  std::function<bool()> should_stop;
};

// Run a scene's wear history (scene.wear.mode: staged or continuous). `resume_from` holds
// the stages already finished by an earlier run (stage 0..K, exact geometry); the loop
// continues from K and gives the same results as an uninterrupted run.
WearHistory run_wear_history(const Scene& scene, const WearCallbacks& callbacks = {},
                             const std::vector<StageRecord>& resume_from = {});

// Lifter life from stage heights: interpolated where the height crosses the replacement
// height, otherwise extrapolated from the last stages' trend.
void compute_life(WearHistory& history, double replacement_height_m);

}  // namespace millwear

namespace millwear {

// Rule 1 check: the wear history in continuous mode at several factors (C_model = factor
// * C, simulated time scaled by 1/factor), and the profile deviation between neighbours.
struct Rule1Row {
  double factor = 0.0;
  double simulated_s = 0.0;
  double wall_s = 0.0;
  Polyline profile;                 // final unit surface (lifter-local, m)
  double deviation_m = 0.0;         // largest normal distance to the previous (smaller) factor
  double deviation_pct_height = 0.0;
  std::vector<std::string> events;
};
struct Rule1Report {
  std::vector<Rule1Row> rows;       // increasing factor
  double recommended_factor = 0.0;  // largest factor whose deviation stays under tolerance
  double tolerance_pct_height = 0.0;
};
Rule1Report rule1_check(const Scene& scene, std::vector<double> factors, double tolerance_pct_height);

}  // namespace millwear
