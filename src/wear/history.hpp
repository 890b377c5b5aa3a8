#pragma once
// A wear history: the liner of a design stage by stage, from new to its last stage or the
// shell. Each stage measures the charge on a frozen geometry (wear/window.hpp), then wears
// the liner through the stage in updates (wear/wear_step.hpp: staged or continuous),
// reshaping it after each (wear/reshape.hpp), and hands the finished record to the caller.
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/charge.hpp"
#include "metrics/charge_summary.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// The standard errors of a lifter's area and height lost in a stage.
struct WornError {
  double area_m2 = std::nan(""), height_m = std::nan("");
};

// One finished stage: the liner at `hours` and what the charge does with it.
struct StageRecord {
  int stage = 0;                  // 0 = new
  double hours = 0.0;
  std::vector<LinerUnit> units;   // exact geometry (resume restarts from it)
  LifterMetrics lifter;           // of row 0 (or the shared unit; the first kind of a pattern)
  // A pattern of kinds of lifter ([lifters] pattern): each kind's metrics (its shared unit,
  // or the mean over its rows when rows wear on their own) and its lifters' area loss rate
  // (m^2 per operating s, at this geometry). One entry for a plain liner.
  std::vector<LifterMetrics> kinds;
  std::vector<double> kind_area_loss_rate_m2_per_s;
  std::vector<double> kind_area_loss_rate_rel_sem;  // rule 2's error of each (a pattern only)
  ChargeFigures charge;           // measured on this geometry
  double area_loss_rate_m2_per_s = 0.0;       // of the lifter, at this geometry (per operating s)
  double area_loss_rate_rel_sem = 0.0;        // rule 2: batch-means relative error
  // The standard errors of the lifter area and height this stage's wear removed (to the next
  // stage's geometry): each wear update's loss times the batch-means relative error of its
  // window's shear power, on the lifters for the area and on their tops for the height, the
  // updates taken as independent. NaN where no wear update ran from the stage (the last stage,
  // which only measures) or where a stage file has no such keys. A pattern: the same for each
  // kind.
  WornError worn_se;
  std::vector<WornError> kind_worn_se;
  ChargeFigureErrors charge_errors;           // batch-means errors of `charge`
  double liner_loss_rate_m2_per_s = 0.0;      // the whole liner's cross-section lost (every
                                              // lifter and the shell), per operating s
  // Collision spectrum measured on this geometry (per log bin, see engine/accounting.hpp).
  std::vector<double> spectrum_count_per_s, spectrum_energy_W;
  // Wear rate of every mill boundary edge at this geometry (m per operating second), and the
  // charge at the end of the measuring window (for snapshot figures).
  std::vector<double> edge_wear_rate_m_per_s;
  ChargeState snapshot;
  double mill_angle_rad = 0.0;    // mill rotation at the snapshot
  // With scene.outputs.vtk: the charge over the measuring window and the shear and impact
  // power per mill boundary edge in it (W/m^2), for the ParaView files. Not kept on disk.
  std::vector<ChargeState> frames;
  std::vector<double> edge_shear_W_per_m2, edge_impact_W_per_m2;
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
  double start_hours = 0.0;       // operating hours of its first stage
  double life_h = 0.0;            // hours to the replacement height (on the stages' clock);
                                  // a pattern: its shortest-lived kind's
  bool life_extrapolated = false;
  // Per kind of a pattern (one entry for a plain liner): life of that kind's lifters.
  std::vector<double> kind_life_h;
  std::vector<bool> kind_life_extrapolated;
  double wear_rate_m3_per_J = 0.0;   // real C used
  std::vector<std::string> events;   // worn flat, escaped disks, NaN, rule-1 bound
  // The first event that makes the history's figures suspect (a disk lost, rule 1's bound
  // stopping the loop); empty when the history ran to its end or the shell. The history
  // keeps every stage finished before it; a caller reports it as a failed run (exit 1).
  std::string failure;
};

// Metrics of every kind of lifter of a liner (units: one per kind, or one per row with
// row k of kind k % kinds: then the mean over the rows of each kind).
std::vector<LifterMetrics> kind_metrics(const std::vector<LinerUnit>& units, int kinds, double radius_m);

// Throws RunError(history.failure) if the history has one.
void throw_if_failed(const WearHistory& history);

struct WearProgress {
  int stage = 0;
  double hours = 0.0;             // operating hours reached
  double simulated_s = 0.0;
  double disk_steps_per_s = 0.0;
};

// The liner just reshaped by a wear update, for a caller that draws it as it goes.
struct WearUpdate {
  int stage = 0;                      // the stage being worn through
  double hours = 0.0;                 // operating hours the liner now stands at
  const MillGeometry* mill = nullptr;
  const ChargeState* charge = nullptr;  // the charge as the update was computed
};

struct WearCallbacks {
  // Called after each stage record is complete (stage 0 first). Persist it here. The last
  // stage of resume_from is heard of once more when it has been worn through again, with the
  // errors of that wear (worn_se, kind_worn_se) in it.
  std::function<void(const StageRecord&)> on_stage;
  std::function<void(const WearProgress&)> on_progress;
  // Called after every wear update (the liner reshaped, the hours moved on).
  std::function<void(const WearUpdate&)> on_update;
  // Cancellation hook (Ctrl-C, SIGTERM, `run --stop-after-stage`): polled before each
  // simulated window and between pieces of every phase's steps (step_checking_stop); when it
  // returns true the loop stops and throws
  // RunError("interrupted"). Stages already passed to on_stage stay valid for resume_from.
  std::function<bool()> should_stop;
};

// The stages of stage_hours a history needs to reach `hours`: at least one, and a boundary
// within a billionth of a stage of `hours` reaches it (sums of stage lengths round).
int stages_to_reach(double hours, double stage_hours);

// The mill a history's stage 0 turns: every row's liner as it starts (new, or the measured
// profile resampled and re-smoothed), the geometry its charge is filled into.
MillGeometry starting_mill(const Scene& scene);

// Run a scene's wear history (scene.wear.mode: staged or continuous). `resume_from` holds
// the stages already finished by an earlier run (stage 0..K, exact geometry); the loop
// continues from K and gives the same results as an uninterrupted run.
WearHistory run_wear_history(const Scene& scene, const WearCallbacks& callbacks = {},
                             const std::vector<StageRecord>& resume_from = {});

}  // namespace millwear
