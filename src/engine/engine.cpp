// Backend dispatch and the settle / spin-up sequence shared by every backend.
#include "engine/engine.hpp"

#include <algorithm>
#include <limits>
#include <string>

#include "common/errors.hpp"
#include "engine/box2d/box2d_engine.hpp"
#include "engine/soft/soft_engine.hpp"
#include "scene/limits.hpp"

namespace millwear {

int steps_for(double seconds, double dt_s) {
  const std::int64_t n = steps_in(seconds, dt_s);
  // The scene's limits keep every phase far below this; a count past it is a caller's bug.
  if (n > std::numeric_limits<int>::max())
    throw RunError("a phase of " + std::to_string(seconds) + " s needs more time steps than one call can take");
  return static_cast<int>(n);
}

AccountingOptions accounting_options_for(const Scene& scene) {
  AccountingOptions o;
  o.per_edge = true;
  o.shell_work = scene.outputs.shell_work || scene.wear.shell_wear;
  o.collision_spectrum = scene.outputs.collision_spectrum;
  o.charge_shape = true;
  o.contact_log = scene.outputs.contact_log;
  o.packed_wear = scene.wear.packed_wear;
  return o;
}

std::unique_ptr<Engine> make_engine(const Scene& scene, const MillGeometry& mill,
                                    const ChargeState& initial, const AccountingOptions& opts) {
  switch (scene.solver.backend) {
    case Backend::Box2D:
      return make_box2d_engine(scene, mill, initial, opts);
    case Backend::Soft:
      return make_soft_engine(scene, mill, initial, opts);
  }
  throw InputError(scene.source_file, "solver.backend", "\"box2d\" or \"soft\"");
}

void step_checking_stop(Engine& engine, int n, const std::function<void()>& check_stop) {
  if (!check_stop || n <= 0) {
    if (check_stop) check_stop();
    engine.step(n);
    return;
  }
  const auto disks = std::max<std::int64_t>(1, static_cast<std::int64_t>(engine.state().size()));
  const int piece = static_cast<int>(std::clamp<std::int64_t>(kStopCheckDiskSteps / disks, 1, n));
  for (int done = 0; done < n;) {
    check_stop();
    const int k = std::min(piece, n - done);
    engine.step(k);
    done += k;
  }
}

void settle_and_spin_up(Engine& engine, const Scene& scene, double direction_sign,
                        const std::function<void()>& check_stop) {
  // Before anything moves: a time step too large for the smallest disk, or a lifter thinner
  // than it, leaks disks through the liner, and a phase too long never ends
  // (scene/limits.hpp); stop with the limit named rather than report escapes.
  check_run_limits(scene, scene.source_file);
  const double dt = engine.time_step_s();
  engine.set_mill_speed(0.0);
  step_checking_stop(engine, steps_for(scene.solver.settle_time_s, dt), check_stop);
  const double omega = scene.angular_speed_rad_s();
  engine.set_mill_speed(direction_sign * omega);
  if (omega > 0.0)
    step_checking_stop(engine, steps_for(scene.solver.spinup_revolutions * scene.revolution_time_s(), dt),
                       check_stop);
  engine.reset_window();
}

void Engine::reset_window() {
  reset_accounting(accounting_, edge_count_);
  const ChargeState& s = state();
  accounting_.kinetic_J_start = accounting_.kinetic_J_end = charge_kinetic_J(s);
  accounting_.potential_J_start = accounting_.potential_J_end = charge_potential_J(s, kGravity);
  timing_ = Timing{};
}

double charge_kinetic_J(const ChargeState& s) {
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.active[i]) continue;
    // A disk's moment of inertia is m r^2 / 2.
    e += 0.5 * s.mass_kg[i] * (length_sq(s.velocity_m_s[i]) +
                               0.5 * s.radius_m[i] * s.radius_m[i] * s.spin_rad_s[i] * s.spin_rad_s[i]);
  }
  return e;
}

double charge_potential_J(const ChargeState& s, double gravity_m_s2) {
  double e = 0.0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.active[i]) e += s.mass_kg[i] * gravity_m_s2 * s.position_m[i].y;
  return e;
}

int step_thread_count(const SolverDef& solver, std::size_t disks) {
  const int threads = std::max(1, solver.threads);
  if (!solver.threads_fit_size) return threads;
  const auto fit = static_cast<int>(std::min<std::size_t>(disks / kDisksPerStepThread, 1024));
  return std::max(1, std::min(threads, fit));
}

}  // namespace millwear
