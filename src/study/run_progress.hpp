#pragma once
// What a caller of run_designs shows of the run: each design's progress while it runs (the
// stage, the hours, the speed, the time left), and its finished stages as table rows at the
// end. Plain numbers: the caller formats and prints them.
#include <cstddef>
#include <string>
#include <vector>

#include "study/run_designs.hpp"

namespace millwear::study {

struct DesignProgress {
  DesignStatus status = DesignStatus::Waiting;
  int stages = 0;                   // of the scene's history
  int stage = 0;                    // the last reported stage
  int resumed_stage = 0;            // stages 0..resumed_stage were read back (0: none or the new one)
  bool measuring = false;           // no report yet this run: the first window is being measured
  double start_hours = 0.0;         // operating hours this run started from
  double hours = 0.0;               // reached
  double simulated_s = 0.0;
  double disk_steps_per_s = 0.0;
  double elapsed_s = 0.0;           // running: since the design started
  double left_s = 0.0;              // running: time left (NaN before any stage advanced the hours)
  double wall_s = 0.0;              // finished: its wall time
  std::string error;
};

// Design i's progress now. Time left: the rate up to the last report, less the time since
// that report. Caller holds state.mutex.
DesignProgress design_progress(const RunState& state, std::size_t i);

// A finished stage of a design, as the final table shows it.
struct StageLine {
  int stage = 0;
  double hours = 0.0;
  double area_m2 = 0.0, height_m = 0.0;  // lifter of row 0
  double area_loss_fraction = 0.0;       // since the design's own stage 0 (NaN without it)
  // Each kind of lifter of a pattern (empty for a plain liner): area and the lifters' area
  // loss rate at this stage's geometry (m^2 per operating s).
  std::vector<double> kind_area_m2, kind_area_loss_rate_m2_per_s;
};

struct DesignLines {
  std::string name;
  std::vector<StageLine> stages;
  double life_h = 0.0;
  bool life_extrapolated = true;
  double life_from_hours = 0.0;          // the start (or continued-from stage) the life counts from
  std::vector<std::string> kind_names;   // profiles of a pattern's kinds (empty: plain liner)
  std::vector<double> kind_life_h;
  std::vector<bool> kind_life_extrapolated;
  std::string continued_from;            // "RUN stage N (H h)" for `run --continue`
  std::vector<std::string> changes;      // settings changed from that run's
  DesignStatus status = DesignStatus::Waiting;
  std::string error;
  std::vector<std::string> events;
};

// Every design's finished stages and how it ended, in the plan's order.
std::vector<DesignLines> design_lines(const RunState& state);

}  // namespace millwear::study
