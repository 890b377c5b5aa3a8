#pragma once
// One wear update: the depths every unit edge wears by, and the operating hours they stand
// for. The two modes differ only here.
//   staged      the depth rates of the last window (geometry frozen), over the hours that
//               keep the deepest increment under wear.max_depth_step (rule 1 as a bound);
//   continuous  the paper's: the charge turns for wear.update_interval of simulated time and
//               its own shear work wears the liner at C_model = factor x C, so one simulated
//               second stands for `factor` seconds of operation.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/engine.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"
#include "wear/window.hpp"

namespace millwear {

struct WearStep {
  std::vector<std::vector<double>> depths;  // m, per unit edge
  double hours = 0.0;                       // operating hours the depths stand for
  double simulated_s = 0.0;                 // simulated time the step ran (continuous)
  std::int64_t disk_steps = 0;
  std::string stop_event;                   // non-empty: the step refused to wear (rule 1)
};

// Staged: depth rates of `window` for real C, over at most max_hours.
WearStep staged_step(const Scene& scene, const MillGeometry& mill, const WindowWork& window,
                     double rate_m3_per_J, double max_hours);

// Continuous: the engine turns for the update interval (at most max_hours of operation).
// A step that would wear more than a quarter of the new lifter's height (new_height_m) is
// refused with stop_event naming `stage`: C_model is then too large for rule 1. check_stop
// is called as step_checking_stop does.
WearStep continuous_step(const Scene& scene, const MillGeometry& mill, Engine& engine, double rate_m3_per_J,
                         double max_hours, double new_height_m, int stage,
                         const std::function<void()>& check_stop);

}  // namespace millwear
