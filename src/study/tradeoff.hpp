#pragma once
// Speed against accuracy: the wear history of one design, or of every design of a
// comparison, over a ladder of numerical settings, each measured against the reference run.
//
// The ladder starts from the `standard` preset and moves one knob at a time to the values
// the other presets use (and a few beyond), then adds the three presets themselves and two
// reseeded runs (reference and standard with seed + 1: the noise floor and standard's own
// scatter):
//   backend            solver.backend            the other backend (box2d or soft)
//   time_step          solver.time_step          half standard's, draft's, reference's
//   substeps           solver.substeps           half and twice standard's (soft backend)
//   iterations         solver.*_iterations       draft's, reference's (box2d backend)
//   window             wear.window_revolutions   draft's, reference's
//   depth_step         wear.max_depth_step       draft's, reference's
//   size_cutoff        solver.size_cutoff        25 and 50 mm (where above the smallest rock),
//                                                1.25 and 1.5 x the smallest rock size
//   mesh               lifters.*_edge            draft's, half standard's
//   smoothing          wear.smoothing_radius     0.5 and 2 x the default (smallest radius)
//   factor             wear.factor               draft's, reference's (continuous mode only)
// A knob a scene file sets itself is held (the scene's value is part of the design, as
// for apply_fidelity); the report lists the held knobs. A knob that means nothing for
// standard's backend (iterations for soft, substeps for box2d) is left out.
//
// Measured against the reference run (each design at `reference` fidelity), with each
// design's new lifter height and area as its scales; with several designs every error is
// the worst over the designs and the costs are summed (the comparison on one thread):
//   final-profile deviation   largest and mean normal distance between the final liner
//                             unit surfaces (symmetric, mm and % of the new lifter height)
//   area-history error        largest |A_k - A_ref,k| over stages, % of the new lifter area
//   power error               largest |P_k - P_ref,k| / P_ref,k over stages, %
//   life error                |life - life_ref| / life_ref, %
//   comparison                (two or more designs) whether the designs come out in the
//                             reference's order of life, and the largest error of a
//                             design's life relative to the first design's, %
//   wall time, CPU time       of the whole history, s; the speed-up over the reference is
//                             of CPU time (a history runs on one thread, and its CPU time
//                             does not grow when other jobs share the cores)
// The Pareto front is over (CPU time, largest final-profile deviation).
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "wear/wear.hpp"

namespace millwear {

struct TradeoffSetting {
  std::string label;          // "reference", "time_step=1/300", ...
  std::string knob;           // "preset", "seed" or the knob name above
  std::string value;          // the knob's value as text, in file units
  std::vector<Scene> scenes;  // one per design, in the designs' order
};

struct TradeoffOptions {
  bool quick = false;        // the three presets only
  int stages = 0;            // > 0: override wear.stages (a shorter history)
  double stage_hours = 0.0;  // > 0: override wear.stage_hours
  std::vector<std::string> only;  // non-empty: these labels only (and the reference)
};

struct TradeoffLadder {
  std::vector<TradeoffSetting> settings;  // settings[0] is the reference
  std::vector<std::string> held_knobs;    // knobs the scene file fixes (not laddered)
};

// The ladder for loaded scenes, one per design (their own fidelity is ignored; every setting
// is built from the standard or a named preset). Throws InputError for an unknown fidelity.
TradeoffLadder tradeoff_ladder(const std::vector<Scene>& designs, const TradeoffOptions& options);
inline TradeoffLadder tradeoff_ladder(const Scene& scene, const TradeoffOptions& options) {
  return tradeoff_ladder(std::vector<Scene>{scene}, options);
}

// One design's outcome under one setting.
struct TradeoffDesign {
  std::string name;
  double final_hours = 0.0;
  double final_area_m2 = 0.0, final_height_m = 0.0;  // lifter of row 0 at the last stage
  double life_h = 0.0;
  bool life_extrapolated = false;
  double dev_max_pct = 0.0;          // final profile against the reference, % of its height
  double life_err_pct = 0.0;
  Polyline final_profile;            // lifter-local unit surface, m
};

struct TradeoffRow {
  std::string label, knob, value;
  // Costs: summed over the designs.
  double wall_s = 0.0;
  double cpu_s = 0.0;                // CPU time of the run's thread: the cost measure, as
                                     // wall time on a shared machine varies with the load
  double speedup = 0.0;              // reference CPU time / this CPU time
  std::int64_t disk_steps = 0;
  double simulated_s = 0.0;
  // Errors: the worst over the designs.
  double dev_max_m = 0.0, dev_max_pct = 0.0;     // final profile, % of the new lifter height
  double dev_mean_m = 0.0, dev_mean_pct = 0.0;
  double area_err_pct = 0.0;         // % of the new lifter area
  double power_err_pct = 0.0;        // % of the reference's power
  double life_err_pct = 0.0;
  bool life_order_same = true;       // designs in the reference's order of life
  double life_ratio_err_pct = 0.0;   // worst error of life_d / life_0 (NaN: one design)
  std::vector<std::string> events;   // "design: event"
  std::string error;                 // a run failed (RunError text); errors are NaN
  bool pareto = false;
  std::vector<TradeoffDesign> designs;
};

struct TradeoffReport {
  std::string scene_name;             // the design, or the designs joined by " + "
  std::vector<std::string> design_names;
  std::vector<double> lifter_height_m, lifter_area_m2;  // each design's new lifter (the scales)
  int stages = 0;
  double stage_hours = 0.0;
  std::vector<std::string> held_knobs;
  std::vector<TradeoffRow> rows;      // rows[0] is the reference
};

struct TradeoffCallbacks {
  std::function<void(const TradeoffSetting&)> on_start;   // may be called from workers
  std::function<void(const TradeoffSetting&, const TradeoffDesign&, double wall_s, double cpu_s,
                     const std::string& error)>
      on_design;                                           // ditto; serialised by a mutex
};

// Run every setting on every design (jobs threads at once; the reference first so it is
// known early), compare each with the reference and mark the Pareto front. A setting one of
// whose runs throws becomes a row with `error` set and NaN errors; the others still run.
TradeoffReport run_tradeoff(const TradeoffLadder& ladder, int jobs = 1,
                            const TradeoffCallbacks& callbacks = {});

// Largest and mean symmetric normal distance between two open polylines (m). The mean is
// over points sampled every `step_m` along both lines.
void profile_deviation(const Polyline& a, const Polyline& b, double step_m, double& max_m,
                       double& mean_m);


// Mark the rows on the Pareto front of (cpu_s, dev_max_pct): no other finished row is at
// least as fast and as accurate and strictly better in one of the two.
void mark_pareto(std::vector<TradeoffRow>& rows);

}  // namespace millwear
