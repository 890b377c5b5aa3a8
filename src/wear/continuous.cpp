// Continuous wear (the paper's): the mill keeps turning and every update_interval of
// simulated time the accumulated work wears the liner with C_model = factor * C, so one
// simulated second stands for `factor` seconds of operation (rule 1: C_model * n and time
// / n give the same profiles while one update stays a small change of the geometry).
#include <algorithm>
#include <cstdio>
#include <string>

#include "common/units.hpp"
#include "wear/archard.hpp"
#include "wear/wear_step.hpp"

namespace millwear {

// The largest share of the new lifter's height one update may wear before C_model counts as
// too large for rule 1 (the geometry would change within one update).
constexpr double kMaxUpdateHeightFraction = 0.25;

WearStep continuous_step(const Scene& scene, const MillGeometry& mill, Engine& engine, double rate_m3_per_J,
                         double max_hours, double new_height_m, int stage,
                         const std::function<void()>& check_stop) {
  const WearDef& w = scene.wear;
  const double sim_s = std::min(w.update_interval_s, max_hours * kSecondsPerHour / w.factor);
  engine.reset_window();
  step_checking_stop(engine, std::max(1, steps_for(sim_s, engine.time_step_s())), check_stop);
  const Accounting& acc = engine.accounting();
  WearStep step;
  step.simulated_s = acc.time_s;
  step.disk_steps = acc.steps * static_cast<std::int64_t>(engine.state().size());
  step.hours = acc.time_s * w.factor / kSecondsPerHour;
  const auto work = unit_edge_work(mill, acc.shear_work_J, w.average_rows);
  step.depths = archard_depths(scene, mill, work, rate_m3_per_J, w.factor);
  const double worst = deepest(step.depths);
  if (worst > kMaxUpdateHeightFraction * new_height_m) {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "stage %d: wear.factor %g wore %.3g mm in one update (over a quarter of the lifter): C_model is "
                  "too large for rule 1; lower wear.factor",
                  stage, w.factor, worst * 1e3);
    step.stop_event = buf;
    step.depths.clear();
  }
  return step;
}

}  // namespace millwear
