#include "engine/charge_run.hpp"

#include <chrono>
#include <cmath>

namespace millwear {

double initial_direction_sign(const Scene& scene) {
  return scene.mill.direction == Direction::Reverse ? -1.0 : 1.0;
}

ChargeRunResult run_charge_only(const Scene& scene) {
  ChargeRunResult r;
  r.mill = build_scene_mill(scene);
  const ChargeState initial = fill_charge(scene, r.mill);
  auto engine = make_engine(scene, r.mill, initial, accounting_options_for(scene));
  const double sign = initial_direction_sign(scene);
  settle_and_spin_up(*engine, scene, sign);
  const auto t0 = std::chrono::steady_clock::now();
  engine->step(steps_for(scene.run.revolutions * scene.revolution_time_s(), engine->time_step_s()));
  r.window_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.accounting = engine->accounting();
  r.figures = charge_figures(r.accounting, scene, sign * scene.angular_speed_rad_s());
  r.final_state = engine->state();
  r.events = engine->events();
  r.disks = initial.size();
  for (std::size_t i = 0; i < r.final_state.size(); ++i) r.lost_disks += r.final_state.active[i] ? 0 : 1;
  r.timing = engine->timing();
  r.disk_steps = r.timing.disk_steps;
  return r;
}

}  // namespace millwear
