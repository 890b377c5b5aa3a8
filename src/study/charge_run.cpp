#include "study/charge_run.hpp"

#include <algorithm>
#include <chrono>

#include "wear/window.hpp"

namespace millwear {

namespace {

// The trajectory envelope: flights launched in the window's last half revolution, a point
// every half degree of the mill's turn (a flight of a quarter turn gets about 180).
constexpr double kPathRevolutions = 0.5;
constexpr double kPathPointsPerRevolution = 720.0;

}  // namespace

Accounting accounting_since(const Accounting& now, const Accounting& before) {
  Accounting d = now;
  for_each_sum(d, before, [](auto& x, const auto& y) { x -= y; });
  d.kinetic_J_start = before.kinetic_J_end;
  d.potential_J_start = before.potential_J_end;
  d.contact_log.clear();
  return d;
}

ChargeRunResult run_charge_only(const Scene& scene, const std::function<void(const ChargeProgress&)>& on_progress) {
  ChargeRunResult r;
  r.mill = build_scene_mill(scene);
  const ChargeState initial = fill_charge(scene, r.mill);
  auto engine = make_engine(scene, r.mill, initial, accounting_options_for(scene));
  const double sign = direction_at(scene, 0.0);
  const double settle_s = scene.solver.settle_time_s + scene.solver.spinup_revolutions * scene.revolution_time_s();
  const double t_start = engine->state().time_s;
  std::function<void()> settling;
  if (on_progress)
    settling = [&] { on_progress({"settling", engine->state().time_s - t_start, settle_s}); };
  settle_and_spin_up(*engine, scene, sign, settling);
  const auto t0 = std::chrono::steady_clock::now();
  const long long steps = steps_for(scene.run.revolutions * scene.revolution_time_s(), engine->time_step_s());
  // A progress call about every kStopCheckDiskSteps disk-steps, as the settling's.
  const long long report_every =
      std::max<long long>(1, kStopCheckDiskSteps / std::max<long long>(1, static_cast<long long>(initial.size())));
  const double dt_s = engine->time_step_s();
  // Pieces: kWindowBatches batches, each cut into frames_per_batch when frames are kept, at
  // most a frame a step (more would repeat a state under several times).
  const int frames_per_batch =
      scene.outputs.vtk ? static_cast<int>(std::max<long long>(
                              1, std::min<long long>((scene.outputs.vtk_frames + kWindowBatches - 1) / kWindowBatches,
                                                     steps / kWindowBatches)))
                        : 1;
  const long long pieces = static_cast<long long>(kWindowBatches) * frames_per_batch;
  // Flights: the charge at every step; the paths of the last half revolution's launches.
  FlightOptions flight;
  flight.gravity_m_s2 = kGravity;
  const double revolution_s = scene.revolution_time_s();
  const double window_end_s = engine->state().time_s + static_cast<double>(steps) * engine->time_step_s();
  flight.path_from_s = std::max(engine->state().time_s, window_end_s - kPathRevolutions * revolution_s);
  flight.path_to_s = window_end_s;
  flight.path_interval_s = revolution_s / kPathPointsPerRevolution;
  FlightTracker tracker(r.mill.boundary, engine->state(), flight);
  Accounting batch_start = engine->accounting();
  long long done = 0;
  for (long long k = 1; k <= pieces; ++k) {
    const long long upto = steps * k / pieces;
    for (; done < upto; ++done) {
      if (on_progress && done % report_every == 0)
        on_progress({"measuring", static_cast<double>(done) * dt_s, static_cast<double>(steps) * dt_s});
      engine->step(1);
      tracker.observe(engine->state());
    }
    // A piece without a step (a window of fewer steps than batches) has no frame of its own.
    if (scene.outputs.vtk && (r.frames.empty() || r.frames.back().time_s != engine->state().time_s))
      r.frames.push_back(engine->state());
    if (k % frames_per_batch != 0) continue;
    r.batches.push_back(charge_figures(accounting_since(engine->accounting(), batch_start), scene,
                                       sign * scene.angular_speed_rad_s()));
    batch_start = engine->accounting();
    tracker.set_batch(static_cast<int>(r.batches.size()));
  }
  r.impacts = tracker.impacts();
  r.flight_paths = tracker.paths();
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
