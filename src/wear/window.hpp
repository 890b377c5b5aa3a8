#pragma once
// A measuring window: the charge turns on a frozen liner while the engine books the shear
// work on every edge, in batches whose means give the error of the lifter's shear power
// (rule 2: the window grows until that error meets the scene's target). Also the mill's
// operating schedule (direction, reversals), which decides how each window turns.
#include <functional>
#include <vector>

#include "engine/engine.hpp"
#include "metrics/batch_means.hpp"
#include "metrics/charge_summary.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// What one window measured on one geometry.
struct WindowWork {
  std::vector<double> edge_power_W;                 // shear power per mill edge
  std::vector<std::vector<double>> unit_power_W;    // per unit (1 or rows), per unit edge
  Accounting accounting;                            // the whole window
  double lifter_power_mean_W = 0.0;                 // per row, summed over lifter edges
  double lifter_power_rel_sem = 0.0;                // batch-means relative standard error
  ChargeFigureErrors charge_errors;                 // batch-means errors of the charge figures
  std::vector<double> kind_lifter_power_rel_sem;    // a pattern: the same for each kind's lifters
  // The same for the shear power on the lifters' tops (wear/archard.hpp), which sets the height
  // a wear update takes; per kind for a pattern.
  double lifter_top_rel_sem = 0.0;
  std::vector<double> kind_lifter_top_rel_sem;
  double simulated_s = 0.0;
  // With scene.outputs.vtk: the charge at vtk_frames even times over the window (rounded up
  // to whole frames per batch), for the ParaView files.
  std::vector<ChargeState> frames;
};

// Run a window on the engine's current liner: batches of window_revolutions / kWindowBatches,
// each accumulated into the window's sums, extended while the lifter's shear power is less
// certain than wear.target_uncertainty. check_stop is called before every batch, and within
// a batch as step_checking_stop does.
WindowWork simulate_window(Engine& engine, const Scene& scene, const MillGeometry& mill,
                           const std::function<void()>& check_stop);

// Add one batch's sums into a window's (the first batch is copied).
void accumulate_work(Accounting& total, const Accounting& part);

// Direction of rotation at an operating time: +1 forward (counter-clockwise), -1 reverse;
// a bidirectional mill starts forward.
double direction_at(const Scene& scene, double hours);
// Operating hours of the next reversal after `hours` (infinity for one-way mills).
double next_reversal(const Scene& scene, double hours);
// Turn the mill at the direction's speed; after a reversal the charge turns for the scene's
// spin-up (solver.spinup_revolutions, at least half a revolution) before anything is
// measured, as after the first fill: it falls over to the other side and needs about a
// revolution to become steady; check_stop is called as step_checking_stop does. Starts a new
// measuring window.
void turn_mill(Engine& engine, const Scene& scene, double direction, bool reversed,
               const std::function<void()>& check_stop);

}  // namespace millwear
