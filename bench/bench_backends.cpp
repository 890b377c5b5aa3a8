// Backend benchmark and comparison.
//
//   build/bench_backends [seconds_measured]
//     Both backends on the probe scene of probe_scene.hpp (5 m mill, 24
//     lifters, 75% critical) at about 1k, 3k and 10k disks, at equal time step (1/600 s) and
//     substeps (4; Box2D 2.4 has none: 8 velocity / 3 position iterations), one thread:
//     disk-steps per CPU second (and per wall second), simulated seconds per CPU second, the
//     time share of broad phase, narrow phase, solve and accounting, escapes beside every
//     figure.
//   build/bench_backends --equal-size [seconds_measured]
//     The soft backend with the 1k probe's disks in mills widened to hold about 1k, 3k and
//     10k of them: cost per disk-step at equal disk size (linearity in the count).
//   build/bench_backends --compare scene.toml [revolutions] [batches] [box2d|soft]
//     Runs a scene on both backends and prints power, torque arm, toe and shoulder, energy
//     shares and the lifter shear work, each with its batch-means standard error.
//   build/bench_backends --snapshot [rest-]1k|3k|10k|eq1k|eq3k|eq10k|eq30k|eq100k FILE [--threads N]
//     Settles and spins up the probe scene on the soft backend and writes the charge state
//     (exact bits) to FILE, so a profiler can start from a running mill; eq*: the
//     --equal-size mills; rest-: the mill at rest (the settled bed).
//   build/bench_backends --run FILE steps [box2d|soft] [--threads N]
//     Loads a snapshot, runs kWarmupSteps steps untimed and then that many timed, and prints
//     a fingerprint (a hash of the final state and of the accounting sums; equal fingerprints
//     = bit-identical results) and the rate of the timed steps. The first steps after a
//     load are not the mill's steady cost: the contact arrays grow to their high-water mark
//     (every page touched for the first time) and the contacts start cold. Short and
//     repeatable: the target for valgrind --tool=callgrind and perf stat.
//   build/bench_backends --pool [--threads N]
//     The soft step's worker pool alone: wall time to hand out and collect one stage of R
//     ranges (R = 1 .. 64), each range empty or a fixed piece of arithmetic, against the same
//     work on the caller alone. What a stage costs beyond its work, which the step pays once
//     per colour of each pass of each substep.
// Prints tables; asserts nothing (speed is measured here, never in tests).
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "engine/engine.hpp"
#include "engine/soft/workers.hpp"
#include "probe_scene.hpp"
#include "scene/scene.hpp"
#include "study/charge_run.hpp"

using namespace millwear;

namespace {

int g_threads = 1;  // --threads

// CPU time of this thread: on a shared machine the wall clock counts the time other jobs
// hold the core; the CPU time is what one core gives this run.
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The probe scene with rolling resistance (the soft backend has it) and 4 substeps.
Scene probe_scene(double r_min_m) {
  Scene s = bench::probe_scene(r_min_m);
  s.charge.species[0].rolling_resistance = 0.05;
  s.solver.substeps = 4;
  return s;
}

struct Row {
  std::size_t disks;
  double rate, cpu_rate, sim_per_cpu, broad, narrow, solve, account;
  long long escaped;
  double pairs, live, liner;  // contact rows per disk-step (soft backend)
};

// Contact rows per disk-step since the timing was last reset.
struct RowsPerDisk {
  double pairs = 0, live = 0, liner = 0;
};
RowsPerDisk rows_per_disk(const Engine::Timing& tm) {
  const double n = tm.disk_steps > 0 ? static_cast<double>(tm.disk_steps) : 1.0;
  return {tm.pair_rows / n, tm.live_pair_rows / n, tm.liner_rows / n};
}

// settle_and_spin_up without its numerical-limit check: the 10k probe (9 mm disks at
// 1/600 s) is past scene/limits' leak bound at the SAG impact speed, but the benchmark runs
// every size at the same time step on purpose; lost disks are counted in the table instead.
void settle_unchecked(Engine& engine, const Scene& scene) {
  const double dt = engine.time_step_s();
  engine.set_mill_speed(0.0);
  engine.step(steps_for(scene.solver.settle_time_s, dt));
  engine.set_mill_speed(scene.angular_speed_rad_s());
  // A mill at rest (the settled-bed probes) has no revolution to spin up for.
  if (scene.angular_speed_rad_s() > 0.0)
    engine.step(steps_for(scene.solver.spinup_revolutions * scene.revolution_time_s(), dt));
  engine.reset_window();
}

Row measure(const Scene& scene, double seconds) {
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
  settle_unchecked(*engine, scene);
  const long long escaped_before = engine->accounting().escaped;
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  const int steps = steps_for(seconds, engine->time_step_s());
  engine->step(steps);
  const double cpu = cpu_seconds() - c0;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& tm = engine->timing();
  // Escapes over the whole run (settling included): reset_window zeroes the counter, so
  // count the disks that are no longer active.
  long long lost = 0;
  for (auto a : engine->state().active) lost += a ? 0 : 1;
  (void)escaped_before;
  const RowsPerDisk rows = rows_per_disk(tm);
  return {engine->state().size(), tm.disk_steps / wall, tm.disk_steps / cpu,
          steps * engine->time_step_s() / cpu, tm.broad_s / wall, tm.collide_s / wall,
          tm.solve_s / wall, tm.account_s / wall, lost, rows.pairs, rows.live, rows.liner};
}

int speed_table(double seconds) {
  std::printf("Probe scene: 5 m mill, 24 lifters, 75%% critical, dt 1/600 s, one thread, %.2f s measured\n"
              "soft: 4 substeps + relax; box2d: 8 velocity / 3 position iterations\n", seconds);
  std::printf("disk-steps/s per CPU second of this thread (the wall-clock rate beside it counts\n"
              "the time other jobs held the core); sim s/s: simulated seconds per CPU second\n");
  std::printf("%8s %8s %14s %10s %8s %8s %8s %8s %8s %8s\n", "backend", "disks", "disk-steps/s",
              "(wall)", "sim s/s", "broad", "narrow", "solve", "account", "lost");
  for (double r : {0.0287, 0.0166, 0.0091}) {
    Scene scene = probe_scene(r);
    double box2d_rate = 0.0;
    for (Backend b : {Backend::Box2D, Backend::Soft}) {
      scene.solver.backend = b;
      const Row row = measure(scene, seconds);
      std::printf("%8s %8zu %14.3g %10.3g %8.3g %7.0f%% %7.0f%% %7.0f%% %7.0f%% %8lld",
                  b == Backend::Box2D ? "box2d" : "soft", row.disks, row.cpu_rate, row.rate,
                  row.sim_per_cpu, 100 * row.broad, 100 * row.narrow, 100 * row.solve,
                  100 * row.account, row.escaped);
      if (b == Backend::Box2D) box2d_rate = row.cpu_rate;
      else std::printf("   soft/box2d %.2fx", row.cpu_rate / box2d_rate);
      std::printf("\n");
      std::fflush(stdout);
    }
  }
  return 0;
}

// Linearity at equal physics per disk: the 1k probe's disks (r_min 28.7 mm) in mills 1,
// sqrt 3 and sqrt 10 times as wide (rows in proportion, so the lifter pitch stays), about
// 1k, 3k and 10k disks, soft backend. The fixed probe shrinks its disks to fit more, which
// raises the speculative pairs per disk (a margin of 1.5 |v| dt against a smaller radius);
// here each disk meets about the same neighbourhood, so the cost per disk-step shows what
// the algorithm itself does with the count. (The shell runs faster in a wider mill at the
// same fraction of critical: the impact speed grows as sqrt(D), which this table also shows.)
Scene equal_size_scene(double k) {
  Scene scene = probe_scene(0.0287);
  scene.mill.diameter_m *= k;
  scene.mill.rows = static_cast<int>(std::lround(24 * k));
  scene.solver.backend = Backend::Soft;
  scene.solver.threads = g_threads;
  return scene;
}

int equal_size_table(double seconds) {
  std::printf("Equal disk size (r_min 28.7 mm), mill 5 m x {1, sqrt 3, sqrt 10}, 75%% critical, dt 1/600 s, soft, "
              "%.2f s measured\n", seconds);
  std::printf("rows per disk-step: candidate pairs, pairs carrying an impulse (live), liner rows\n");
  std::printf("%8s %8s %14s %14s %8s %8s %8s %8s %8s %7s %7s %7s\n", "mill_m", "disks", "disk-steps/s",
              "ns/disk-step", "broad", "narrow", "solve", "account", "lost", "pairs", "live", "liner");
  // Turning, the wider mill's charge has more disks in the bed and fewer in flight, so more
  // contacts per disk; at rest every disk is in the bed and the contacts per disk barely
  // change with the count: the algorithm's own scaling.
  for (const bool turning : {true, false}) {
    std::printf("%s\n", turning ? "turning at 75% critical:" : "at rest (speed 0, the settled bed):");
    for (double k : {1.0, std::sqrt(3.0), std::sqrt(10.0)}) {
      Scene scene = equal_size_scene(k);
      if (!turning) scene.mill.speed_fraction_critical = 0.0;
      const Row row = measure(scene, seconds);
      std::printf("%8.2f %8zu %14.3g %14.0f %7.0f%% %7.0f%% %7.0f%% %7.0f%% %8lld %7.2f %7.2f %7.2f\n",
                  scene.mill.diameter_m, row.disks, row.cpu_rate, 1e9 / row.cpu_rate, 100 * row.broad,
                  100 * row.narrow, 100 * row.solve, 100 * row.account, row.escaped, row.pairs, row.live,
                  row.liner);
      std::fflush(stdout);
    }
  }
  return 0;
}

struct Stat {
  std::vector<double> x;
  double mean() const { double m = 0; for (double v : x) m += v / x.size(); return m; }
  double sem() const {
    if (x.size() < 2) return 0.0;
    const double m = mean();
    double var = 0;
    for (double v : x) var += (v - m) * (v - m) / (x.size() - 1);
    return std::sqrt(var / x.size());
  }
};

int compare(const std::string& path, double revolutions, int batches, const char* only) {
  std::printf("%s: %d batches of %.2f revolutions after settle and spin-up (mean +- batch-means SE)\n",
              path.c_str(), batches, revolutions / batches);
  for (Backend b : {Backend::Box2D, Backend::Soft}) {
    const char* name = b == Backend::Box2D ? "box2d" : "soft";
    if (only && std::strcmp(only, name) != 0) continue;
    // Each backend as the scene file naming it: the fidelity preset's time step is the backend's.
    Scene scene = load_scene(path, {std::string("solver.backend=") + name});
    scene.mill.direction = Direction::Forward;
    const MillGeometry mill = build_scene_mill(scene);
    auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
    settle_and_spin_up(*engine, scene, 1.0);
    const double omega = scene.angular_speed_rad_s();
    Stat power, arm, toe, shoulder, pp, pl, solver, lifter_work, lead_share;
    std::vector<Stat> unit_profile;  // shear-work share per lifter edge of the unit
    const auto t0 = std::chrono::steady_clock::now();
    long long escaped = 0;
    for (int k = 0; k < batches; ++k) {
      engine->reset_window();
      engine->step(steps_for(revolutions / batches * scene.revolution_time_s(), engine->time_step_s()));
      const Accounting& acc = engine->accounting();
      const ChargeFigures f = charge_figures(acc, scene, omega);
      escaped += acc.escaped;
      power.x.push_back(f.power_kW_per_m);
      arm.x.push_back(f.torque_arm_kW_per_m);
      toe.x.push_back(f.summary.toe_deg);
      shoulder.x.push_back(f.summary.shoulder_deg);
      pp.x.push_back(f.collision_kW_per_m);
      pl.x.push_back(f.liner_kW_per_m);
      solver.x.push_back(f.solver_kW_per_m);
      double lifter = 0, lead = 0;
      std::vector<double> per_unit_edge;
      for (std::size_t e = 0; e < acc.shear_work_J.size(); ++e) {
        const auto& info = mill.edges[e];
        if (info.owner != EdgeOwner::Lifter) continue;
        lifter += acc.shear_work_J[e];
        const auto& surf = mill.units[mill.units.size() == 1 ? 0 : info.row].surface;
        if (0.5 * (surf[info.unit_edge].x + surf[info.unit_edge + 1].x) > 0) lead += acc.shear_work_J[e];
        if (per_unit_edge.size() <= static_cast<std::size_t>(info.unit_edge))
          per_unit_edge.resize(info.unit_edge + 1, 0.0);
        per_unit_edge[info.unit_edge] += acc.shear_work_J[e];
      }
      lifter_work.x.push_back(lifter / acc.time_s / scene.slice_thickness());
      lead_share.x.push_back(lifter > 0 ? lead / lifter : 0);
      if (unit_profile.size() < per_unit_edge.size()) unit_profile.resize(per_unit_edge.size());
      for (std::size_t e = 0; e < per_unit_edge.size(); ++e)
        unit_profile[e].x.push_back(lifter > 0 ? per_unit_edge[e] / lifter : 0);
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto pr = [](const char* name, const Stat& s, const char* unit) {
      std::printf("  %-28s %10.4g +- %-9.3g %s\n", name, s.mean(), s.sem(), unit);
    };
    std::printf("%s (%zu disks, %.1f s wall, %lld escaped)\n", b == Backend::Box2D ? "box2d" : "soft",
                engine->state().size(), wall, escaped);
    pr("power", power, "kW/m");
    pr("torque arm omega M g x_cm", arm, "kW/m");
    pr("toe", toe, "deg from 6 o'clock");
    pr("shoulder", shoulder, "deg from 6 o'clock");
    pr("particle-particle dissipation", pp, "kW/m");
    pr("particle-liner dissipation", pl, "kW/m");
    pr("solver share", solver, "kW/m");
    pr("lifter shear work", lifter_work, "W/m");
    pr("leading-face share", lead_share, "of lifter work");
    std::printf("  lifter shear-work share by unit edge (with SE):");
    for (std::size_t e = 0; e < unit_profile.size(); ++e) {
      if (unit_profile[e].mean() == 0.0) continue;
      std::printf(" %zu:%.3f+-%.3f", e, unit_profile[e].mean(), unit_profile[e].sem());
    }
    std::printf("\n");
    std::fflush(stdout);
  }
  return 0;
}

// A snapshot's scene: the probe at one of its sizes, or (eq*) the 1k probe's disks in a mill
// widened by mill_scale (equal_size_scene). Both numbers are stored in the snapshot.
struct SnapshotScene {
  double radius_m = 0.0287, mill_scale = 1.0;
};
SnapshotScene snapshot_scene(const std::string& size) {
  if (size == "1k") return {0.0287, 1.0};
  if (size == "3k") return {0.0166, 1.0};
  if (size == "10k") return {0.0091, 1.0};
  if (size == "eq1k") return {0.0287, 1.0};
  if (size == "eq3k") return {0.0287, std::sqrt(3.0)};
  if (size == "eq10k") return {0.0287, std::sqrt(10.0)};
  if (size == "eq30k") return {0.0287, std::sqrt(30.0)};
  if (size == "eq100k") return {0.0287, 10.0};
  std::fprintf(stderr, "size must be 1k, 3k, 10k, eq1k, eq3k, eq10k, eq30k or eq100k\n");
  std::exit(2);
}
Scene scene_of(const SnapshotScene& at) {
  Scene scene = at.mill_scale == 1.0 ? probe_scene(at.radius_m) : equal_size_scene(at.mill_scale);
  scene.solver.backend = Backend::Soft;
  scene.solver.threads = g_threads;
  return scene;
}

template <class T>
void put(std::FILE* f, const std::vector<T>& v) {
  const std::uint64_t n = v.size();
  std::fwrite(&n, sizeof n, 1, f);
  std::fwrite(v.data(), sizeof(T), v.size(), f);
}
template <class T>
bool get(std::FILE* f, std::vector<T>& v) {
  std::uint64_t n = 0;
  if (std::fread(&n, sizeof n, 1, f) != 1) return false;
  v.resize(n);
  return std::fread(v.data(), sizeof(T), n, f) == n;
}

int snapshot(const std::string& size, const std::string& path) {
  // "rest-" before a size: the mill stands still (the settled bed; --run keeps it still).
  const bool rest = size.rfind("rest-", 0) == 0;
  const SnapshotScene at = snapshot_scene(rest ? size.substr(5) : size);
  Scene scene = scene_of(at);
  if (rest) scene.mill.speed_fraction_critical = 0.0, scene.solver.settle_time_s = 4.0;
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
  settle_unchecked(*engine, scene);
  const ChargeState& s = engine->state();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) { std::perror(path.c_str()); return 1; }
  std::fwrite(&at.radius_m, sizeof(double), 1, f);
  std::fwrite(&at.mill_scale, sizeof(double), 1, f);
  std::fwrite(&s.mill_angle_rad, sizeof(double), 1, f);
  std::fwrite(&s.mill_speed_rad_s, sizeof(double), 1, f);
  std::fwrite(&s.time_s, sizeof(double), 1, f);
  put(f, s.position_m); put(f, s.velocity_m_s); put(f, s.angle_rad); put(f, s.spin_rad_s);
  put(f, s.radius_m); put(f, s.mass_kg); put(f, s.species); put(f, s.active);
  std::fclose(f);
  std::printf("%s: %zu disks at t = %.3f s\n", path.c_str(), s.size(), s.time_s);
  return 0;
}

// FNV-1a over raw bytes: equal fingerprints mean bit-identical results.
struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
  template <class T>
  void add(const std::vector<T>& v) { add(v.data(), v.size() * sizeof(T)); }
  void add(double d) { add(&d, sizeof d); }
};

// Steps run untimed by --run before the timed ones. The first step grows every contact array
// (and faults in its pages) with no warm start, the second is the first with live rows in
// lanes. On one thread at eq30k and eq100k the first step took 3-4 times a later one, the
// second and third 1.5-1.8 times and the fourth up to 1.2 times; from the fifth on, a step
// costs what the run's later ones do.
constexpr int kWarmupSteps = 4;

Engine::Timing timing_since(const Engine::Timing& a, const Engine::Timing& b) {
  Engine::Timing d;
  d.collide_s = b.collide_s - a.collide_s;
  d.solve_s = b.solve_s - a.solve_s;
  d.account_s = b.account_s - a.account_s;
  d.broad_s = b.broad_s - a.broad_s;
  d.disk_steps = b.disk_steps - a.disk_steps;
  d.pair_rows = b.pair_rows - a.pair_rows;
  d.live_pair_rows = b.live_pair_rows - a.live_pair_rows;
  d.liner_rows = b.liner_rows - a.liner_rows;
  return d;
}

int run_snapshot(const std::string& path, int steps, const char* backend) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) { std::perror(path.c_str()); return 1; }
  SnapshotScene at;
  ChargeState s;
  bool ok = std::fread(&at.radius_m, sizeof(double), 1, f) == 1 &&
            std::fread(&at.mill_scale, sizeof(double), 1, f) == 1 && std::fread(&s.mill_angle_rad, sizeof(double), 1, f) == 1 &&
            std::fread(&s.mill_speed_rad_s, sizeof(double), 1, f) == 1 &&
            std::fread(&s.time_s, sizeof(double), 1, f) == 1;
  ok = ok && get(f, s.position_m) && get(f, s.velocity_m_s) && get(f, s.angle_rad) && get(f, s.spin_rad_s) &&
       get(f, s.radius_m) && get(f, s.mass_kg) && get(f, s.species) && get(f, s.active);
  std::fclose(f);
  if (!ok) { std::fprintf(stderr, "%s: not a snapshot\n", path.c_str()); return 1; }
  Scene scene = scene_of(at);
  scene.solver.backend = backend && std::strcmp(backend, "box2d") == 0 ? Backend::Box2D : Backend::Soft;
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, s, accounting_options_for(scene));
  engine->set_mill_speed(s.mill_speed_rad_s);
  engine->reset_window();
  engine->step(kWarmupSteps);
  const Engine::Timing before = engine->timing();
  const auto t0 = std::chrono::steady_clock::now();
  const double c0 = cpu_seconds();
  engine->step(steps);
  const double cpu = cpu_seconds() - c0;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ChargeState& e = engine->state();
  const Accounting& acc = engine->accounting();
  Fnv h;
  h.add(e.position_m); h.add(e.velocity_m_s); h.add(e.angle_rad); h.add(e.spin_rad_s); h.add(e.active);
  Fnv ha;
  for (double d : {acc.drive_work_J, acc.torque_impulse_Nms, acc.pp_normal_J, acc.pp_tangent_J, acc.pl_normal_J,
                   acc.pl_tangent_J, acc.solver_position_J})
    ha.add(d);
  ha.add(acc.shear_work_J); ha.add(acc.impact_energy_J); ha.add(acc.contacts);
  ha.add(acc.spectrum_count.data(), sizeof acc.spectrum_count);
  ha.add(acc.spectrum_energy_J.data(), sizeof acc.spectrum_energy_J);
  const Engine::Timing tm = timing_since(before, engine->timing());
  std::printf("%s %zu disks %d steps: state %016llx accounting %016llx  %.3g disk-steps/cpu-s "
              "%.3g disk-steps/wall-s (broad %.0f%% narrow %.0f%% solve %.0f%% account %.0f%%)\n",
              engine->backend_name(), e.size(), steps, static_cast<unsigned long long>(h.h),
              static_cast<unsigned long long>(ha.h), tm.disk_steps / cpu, tm.disk_steps / wall,
              100 * tm.broad_s / wall,
              100 * tm.collide_s / wall, 100 * tm.solve_s / wall, 100 * tm.account_s / wall);
  const RowsPerDisk rows = rows_per_disk(tm);
  std::printf("  rows per disk-step: %.2f candidate pairs, %.2f live pairs, %.2f liner (timed steps, after %d "
              "untimed)\n",
              rows.pairs, rows.live, rows.liner, kWarmupSteps);
  return 0;
}

}  // namespace

// Hands out stages of `ranges` ranges, each `work` rounds of arithmetic on its own slot,
// for about a second; returns microseconds per stage.
double pool_stage_us(soft::Workers& workers, int ranges, int work) {
  struct alignas(64) Slot {
    double x = 1.0;
  };
  std::vector<Slot> slots(static_cast<std::size_t>(ranges));
  const auto body = [&](int r) {
    double x = slots[static_cast<std::size_t>(r)].x;
    for (int k = 0; k < work; ++k) x = x * 0.999999 + 1e-9;
    slots[static_cast<std::size_t>(r)].x = x;
  };
  long long stages = 0;
  const auto t0 = std::chrono::steady_clock::now();
  double elapsed = 0.0;
  while (elapsed < 1.0) {
    for (int k = 0; k < 1000; ++k) workers.run(ranges, body);
    stages += 1000;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return elapsed / static_cast<double>(stages) * 1e6;
}

int pool_table() {
  soft::Workers alone(1), pool(g_threads);
  std::printf("worker pool, %d thread(s): microseconds per stage (wall)\n", g_threads);
  std::printf(" ranges   work/range    caller alone    pool   pool - alone/%d\n", g_threads);
  for (int work : {0, 500}) {
    for (int ranges : {1, 2, 4, 16, 64}) {
      const double a = pool_stage_us(alone, ranges, work);
      const double p = pool_stage_us(pool, ranges, work);
      std::printf("%7d %12d %15.3f %7.3f %17.3f\n", ranges, work, a, p, p - a / g_threads);
    }
  }
  return 0;
}

int main(int argc, char** argv) {
  // --threads N anywhere: the threads of one soft engine's step (default 1).
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--threads") != 0) continue;
    g_threads = std::atoi(argv[i + 1]);
    if (g_threads < 1) { std::fprintf(stderr, "--threads must be at least 1\n"); return 2; }
    for (int j = i; j + 2 < argc; ++j) argv[j] = argv[j + 2];
    argc -= 2;
    break;
  }
  if (argc > 3 && std::strcmp(argv[1], "--snapshot") == 0) return snapshot(argv[2], argv[3]);
  if (argc > 3 && std::strcmp(argv[1], "--run") == 0)
    return run_snapshot(argv[2], std::atoi(argv[3]), argc > 4 ? argv[4] : nullptr);
  if (argc > 2 && std::strcmp(argv[1], "--compare") == 0) {
    try {
      return compare(argv[2], argc > 3 ? std::atof(argv[3]) : 6.0, argc > 4 ? std::atoi(argv[4]) : 6,
                     argc > 5 ? argv[5] : nullptr);
    } catch (const InputError& e) {
      std::fprintf(stderr, "bench_backends: error: %s\n", e.what());
      return 2;
    }
  }
  if (argc > 1 && std::strcmp(argv[1], "--pool") == 0) return pool_table();
  if (argc > 1 && std::strcmp(argv[1], "--equal-size") == 0) return equal_size_table(argc > 2 ? std::atof(argv[2]) : 1.0);
  const char* usage =
      "usage: bench_backends [SECONDS] | --equal-size [SECONDS] | --compare SCENE [REVOLUTIONS] [BATCHES] "
      "[box2d|soft]\n       | --snapshot NAME FILE | --run FILE STEPS [box2d|soft] | --pool, each with "
      "[--threads N]\n(what each prints: the comment at the top of bench/bench_backends.cpp)\n";
  if (argc > 1 && (std::strcmp(argv[1], "-h") == 0 || std::strcmp(argv[1], "--help") == 0)) {
    std::fputs(usage, stdout);
    return 0;
  }
  double seconds = 1.0;
  if (argc > 1) {
    char* end = nullptr;
    seconds = std::strtod(argv[1], &end);
    if (argc > 2 || *end != '\0' || !(seconds > 0.0 && seconds <= 1e4)) {
      std::fputs(usage, stderr);
      return 2;
    }
  }
  return speed_table(seconds);
}
