// A measuring window and the mill's operating schedule.
#include "wear/window.hpp"

#include <algorithm>
#include <cmath>

#include "metrics/batch_means.hpp"
#include "wear/archard.hpp"

namespace millwear {

double direction_at(const Scene& scene, double hours) {
  switch (scene.mill.direction) {
    case Direction::Forward: return 1.0;
    case Direction::Reverse: return -1.0;
    case Direction::Bidirectional: {
      const long period = static_cast<long>(std::floor(hours / scene.mill.reverse_every_hours + 1e-9));
      return period % 2 == 0 ? 1.0 : -1.0;
    }
  }
  return 1.0;
}

void turn_mill(Engine& engine, const Scene& scene, double dir, bool reversed,
               const std::function<void()>& check_stop) {
  engine.set_mill_speed(dir * scene.angular_speed_rad_s());
  if (reversed)
    step_checking_stop(engine,
                       steps_for(std::max(0.5, scene.solver.spinup_revolutions) * scene.revolution_time_s(),
                                 engine.time_step_s()),
                       check_stop);
  engine.reset_window();
}

double next_reversal(const Scene& scene, double hours) {
  if (scene.mill.direction != Direction::Bidirectional) return INFINITY;
  const double p = scene.mill.reverse_every_hours;
  return (std::floor(hours / p + 1e-9) + 1.0) * p;
}

void accumulate_work(Accounting& total, const Accounting& part) {
  if (total.steps == 0) {  // the first batch: copied, with its options and start energies
    total = part;
    return;
  }
  for_each_sum(total, part, [](auto& x, const auto& y) { x += y; });
  total.kinetic_J_end = part.kinetic_J_end;
  total.potential_J_end = part.potential_J_end;
}

WindowWork simulate_window(Engine& engine, const Scene& scene, const MillGeometry& mill,
                           const std::function<void()>& check_stop) {
  const double batch_s = scene.wear.window_revolutions * scene.revolution_time_s() / kWindowBatches;
  const int batch_steps = std::max(1, steps_for(batch_s, engine.time_step_s()));
  WindowWork w;
  std::vector<double> batch_power;
  std::vector<ChargeFigures> batch_figures;
  std::vector<std::vector<double>> kind_batch_power(mill.kinds > 1 ? static_cast<std::size_t>(mill.kinds) : 0);
  std::vector<double> batch_top_power;
  std::vector<std::vector<double>> kind_batch_top_power(kind_batch_power.size());
  for (int b = 0; b < kMaxWindowBatches; ++b) {
    check_stop();
    engine.reset_window();
    if (scene.outputs.vtk) {
      // The batch's steps in pieces, a frame after each: the same steps as in one piece. At
      // most a frame a step: more would repeat a state under several times.
      const int pieces = std::min(batch_steps, (scene.outputs.vtk_frames + kWindowBatches - 1) / kWindowBatches);
      for (int k = 1, done = 0; k <= pieces; ++k) {
        const int upto = static_cast<int>(static_cast<long long>(batch_steps) * k / pieces);
        step_checking_stop(engine, upto - done, check_stop);
        done = upto;
        w.frames.push_back(engine.state());
      }
    } else {
      step_checking_stop(engine, batch_steps, check_stop);
    }
    const Accounting& acc = engine.accounting();
    std::vector<double> p(acc.shear_work_J.size());
    for (std::size_t e = 0; e < p.size(); ++e) p[e] = acc.shear_work_J[e] / acc.time_s;
    const auto unit_power = unit_edge_work(mill, p, scene.wear.average_rows);
    batch_power.push_back(lifter_power_W(mill, unit_power));
    batch_figures.push_back(charge_figures(acc, scene, engine.state().mill_speed_rad_s));
    batch_top_power.push_back(lifter_top_power_W(mill, unit_power));
    if (!kind_batch_power.empty()) {
      const std::vector<double> kp = kind_lifter_power_W(mill, unit_power);
      const std::vector<double> kt = kind_lifter_top_power_W(mill, unit_power);
      for (std::size_t k = 0; k < kind_batch_power.size(); ++k) {
        kind_batch_power[k].push_back(kp[k]);
        kind_batch_top_power[k].push_back(kt[k]);
      }
    }
    accumulate_work(w.accounting, acc);
    const int n = static_cast<int>(batch_power.size());
    if (n < kWindowBatches) continue;
    w.lifter_power_rel_sem = batch_means(batch_power).rel_sem;
    if (scene.wear.target_rel_uncertainty <= 0.0 || w.lifter_power_rel_sem <= scene.wear.target_rel_uncertainty)
      break;
  }
  w.charge_errors = charge_figure_errors(batch_figures);
  for (const auto& kb : kind_batch_power) w.kind_lifter_power_rel_sem.push_back(batch_means(kb).rel_sem);
  w.lifter_top_rel_sem = batch_means(batch_top_power).rel_sem;
  for (const auto& kb : kind_batch_top_power) w.kind_lifter_top_rel_sem.push_back(batch_means(kb).rel_sem);
  w.simulated_s = w.accounting.time_s;
  w.edge_power_W.resize(w.accounting.shear_work_J.size());
  for (std::size_t e = 0; e < w.edge_power_W.size(); ++e)
    w.edge_power_W[e] = w.accounting.shear_work_J[e] / w.accounting.time_s;
  w.unit_power_W = unit_edge_work(mill, w.edge_power_W, scene.wear.average_rows);
  w.lifter_power_mean_W = lifter_power_W(mill, w.unit_power_W);
  return w;
}

}  // namespace millwear
