#pragma once
// Running the charge alone (no wear): fill, settle, spin up, measure some revolutions.
#include <functional>
#include <vector>

#include "engine/engine.hpp"
#include "metrics/charge_summary.hpp"
#include "metrics/trajectories.hpp"

namespace millwear {


struct ChargeRunResult {
  ChargeFigures figures;
  Accounting accounting;        // the measured window
  // The window's figures in kWindowBatches equal batches, in order (their spread gives the
  // statistical error of the window's figures: metrics/batch_means.hpp).
  std::vector<ChargeFigures> batches;
  // With scene.outputs.vtk: the charge at vtk_frames even times over the window (its end
  // included), for the ParaView files.
  std::vector<ChargeState> frames;
  ChargeState final_state;
  // Flights from the lifters over the window, the charge followed at every step
  // (metrics/trajectories.hpp): every first impact, tagged with its batch, and the paths of
  // the flights launched in the window's last half revolution (the trajectory envelope,
  // ending at final_state).
  std::vector<Impact> impacts;
  std::vector<FlightPath> flight_paths;
  MillGeometry mill;
  std::vector<EngineEvent> events;
  std::size_t disks = 0;
  std::size_t lost_disks = 0;   // escaped or non-finite at any time, settling included
  std::int64_t disk_steps = 0;  // measured window only
  double window_wall_s = 0.0;   // wall time of the measured window (speed figure)
  Engine::Timing timing;
};

// Where a charge run stands: the phase ("settling": settling and spinning up; "measuring":
// the window) and the simulated seconds done of the phase's.
struct ChargeProgress {
  const char* phase = "";
  double done_s = 0.0, of_s = 0.0;
};

// Fill, settle and spin up, then run scene.run.revolutions at the scene's speed
// (forward for bidirectional mills). The window is stepped one step at a time, each step's
// charge shown to a FlightTracker, and cut into batches (and frames); the steps are the same
// as in one piece, so the figures do not depend on them. `on_progress` (if any) is called
// about every kStopCheckDiskSteps disk-steps; it changes no step.
ChargeRunResult run_charge_only(const Scene& scene,
                                const std::function<void(const ChargeProgress&)>& on_progress = {});

// The sums of a window between two readings of the same engine's accounting (`before` taken
// earlier, no reset between): a batch of it.
Accounting accounting_since(const Accounting& now, const Accounting& before);

}  // namespace millwear
