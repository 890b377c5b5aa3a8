// Engine benchmark: disk-steps per second of the charge on a 5 m mill slice (the probe
// scene of probe_scene.hpp) at about 1k, 3k and 10k disks, the share of
// time in collision, solve and our accounting, and the cost of the optional accounting.
// Prints a table; asserts nothing (speed is measured here, never in tests).
//   build/bench_engine [seconds_measured]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "engine/engine.hpp"
#include "probe_scene.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"

using namespace millwear;

namespace {

// The probe scene at 1/600 s, or the largest step inside the time-step limit
// (scene/limits.hpp) when the disks are too small for it (the 10k case: 1/600 s would move
// 2.5 radii a step, and the probe lost a disk there): rounded down to a whole number of
// steps per second.
Scene probe_scene(double r_min_m) {
  Scene s = bench::probe_scene(r_min_m);
  const double allowed = kMaxStepTravelRadii * r_min_m / impact_speed_m_s(s);
  if (allowed < s.solver.time_step_s) s.solver.time_step_s = 1.0 / std::ceil(1.0 / allowed);
  return s;
}

struct Row {
  std::size_t disks;
  double rate, collide, solve, account;
  long long escaped;
};

Row measure(const Scene& scene, const AccountingOptions& opts, double seconds) {
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, fill_charge(scene, mill), opts);
  settle_and_spin_up(*engine, scene, 1.0);
  const auto t0 = std::chrono::steady_clock::now();
  engine->step(steps_for(seconds, engine->time_step_s()));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& tm = engine->timing();
  return {engine->state().size(), tm.disk_steps / wall, tm.collide_s / wall, tm.solve_s / wall,
          tm.account_s / wall, static_cast<long long>(engine->accounting().escaped)};
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 1.0;
  std::printf("Box2D 2.4 backend, 5 m mill, 24 lifters, 75%% critical, dt 1/600 s (or the time-step limit), "
              "8/3 iterations, %.2f s measured\n", seconds);
  std::printf("%8s %8s %14s %9s %9s %9s %8s   %s\n", "disks", "dt", "disk-steps/s", "collide", "solve", "account",
              "escaped", "accounting");
  for (double r : {0.0287, 0.0166, 0.0091}) {
    const Scene scene = probe_scene(r);
    AccountingOptions full;
    full.collision_spectrum = true;
    AccountingOptions lean;
    lean.collision_spectrum = false;
    lean.shell_work = false;
    lean.charge_shape = false;
    AccountingOptions no_spectrum = full;
    no_spectrum.collision_spectrum = false;
    AccountingOptions with_log = full;
    with_log.contact_log = true;
    for (auto [opts, label] : {std::pair{full, "spectrum + shell + shape (default)"},
                               std::pair{no_spectrum, "without the spectrum"},
                               std::pair{lean, "lifter work only"},
                               std::pair{with_log, "default + contact log"}}) {
      const Row row = measure(scene, opts, seconds);
      std::printf("%8zu   1/%-4.0f %14.3g %8.0f%% %8.0f%% %8.0f%% %8lld   %s\n", row.disks,
                  1.0 / scene.solver.time_step_s, row.rate, 100 * row.collide,
                  100 * row.solve, 100 * row.account, row.escaped, label);
    }
  }
  return 0;
}
