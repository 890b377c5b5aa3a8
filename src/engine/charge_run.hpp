#pragma once
// Running the charge alone (no wear): fill, settle, spin up, measure some revolutions.
#include <vector>

#include "engine/engine.hpp"
#include "metrics/charge_summary.hpp"

namespace millwear {


struct ChargeRunResult {
  ChargeFigures figures;
  Accounting accounting;        // the measured window
  ChargeState final_state;
  MillGeometry mill;
  std::vector<EngineEvent> events;
  std::size_t disks = 0;
  std::size_t lost_disks = 0;   // escaped or non-finite at any time, settling included
  std::int64_t disk_steps = 0;  // measured window only
  double window_wall_s = 0.0;   // wall time of the measured window (speed figure)
  Engine::Timing timing;
};

// Fill, settle and spin up, then run scene.run.revolutions at the scene's speed
// (forward for bidirectional mills).
ChargeRunResult run_charge_only(const Scene& scene);

// +1 forward (counter-clockwise), -1 reverse; bidirectional starts forward.
double initial_direction_sign(const Scene& scene);

}  // namespace millwear
