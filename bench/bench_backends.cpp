// Backend benchmark and comparison (issue 11).
//
//   build/bench_backends [seconds_measured]
//     Both backends on the probe scene of shared/notes/box2d-mill-probe.md (5 m mill, 24
//     lifters, 75% critical) at about 1k, 3k and 10k disks, at equal time step (1/600 s) and
//     substeps (4; Box2D 2.4 has none: 8 velocity / 3 position iterations), one thread:
//     disk-steps per second and the time share of broad phase, narrow phase, solve and
//     accounting, escapes beside every figure.
//   build/bench_backends --compare scene.toml [revolutions] [batches] [box2d|soft]
//     Runs a scene on both backends and prints power, torque arm, toe and shoulder, energy
//     shares and the lifter shear work, each with its batch-means standard error.
// Prints tables; asserts nothing (speed is measured here, never in tests).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "engine/charge_run.hpp"
#include "engine/engine.hpp"
#include "scene/scene.hpp"

using namespace millwear;

namespace {

Scene probe_scene(double r_min_m) {
  Scene s;
  s.name = "probe";
  s.source_file = "(bench)";
  s.mill.diameter_m = 5.0;
  s.mill.length_m = 1.0;
  s.mill.speed_fraction_critical = 0.75;
  s.mill.rows = 24;
  TrapezoidDef t;
  t.height_m = 0.15;
  t.top_width_m = 0.10;
  t.leading_face_angle_rad = t.trailing_face_angle_rad = 30.0 * 3.14159265358979 / 180.0;
  s.mill.lifter.points = trapezoid_points(t);
  s.mill.lifter.name = "probe";
  s.mill.mesh.shell_edge_m = 0.05;
  s.mill.mesh.lifter_edge_m = 0.02;
  SpeciesDef sp;
  sp.name = "ball";
  sp.is_ball = true;
  sp.density_kg_m3 = 2700.0;
  sp.d_min_m = 2.0 * r_min_m;
  sp.d_max_m = 2.0 * 1.67 * r_min_m;
  sp.friction = sp.friction_liner = 0.5;
  sp.restitution = sp.restitution_liner = 0.4;
  sp.rolling_resistance = 0.05;
  s.charge.species = {sp};
  s.charge.filling = 0.30;
  s.charge.ball_filling = 0.30;
  s.charge.bulk_packing = 0.8;
  s.solver.time_step_s = 1.0 / 600.0;
  s.solver.substeps = 4;
  s.solver.settle_time_s = 1.0;
  s.solver.spinup_revolutions = 0.25;
  return s;
}

struct Row {
  std::size_t disks;
  double rate, broad, narrow, solve, account;
  long long escaped;
};

Row measure(const Scene& scene, double seconds) {
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
  settle_and_spin_up(*engine, scene, 1.0);
  const long long escaped_before = engine->accounting().escaped;
  const auto t0 = std::chrono::steady_clock::now();
  engine->step(steps_for(seconds, engine->time_step_s()));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto& tm = engine->timing();
  // Escapes over the whole run (settling included): reset_window zeroes the counter, so
  // count the disks that are no longer active.
  long long lost = 0;
  for (auto a : engine->state().active) lost += a ? 0 : 1;
  (void)escaped_before;
  return {engine->state().size(), tm.disk_steps / wall, tm.broad_s / wall, tm.collide_s / wall,
          tm.solve_s / wall, tm.account_s / wall, lost};
}

int speed_table(double seconds) {
  std::printf("Probe scene: 5 m mill, 24 lifters, 75%% critical, dt 1/600 s, one thread, %.2f s measured\n"
              "soft: 4 substeps + relax; box2d: 8 velocity / 3 position iterations\n", seconds);
  std::printf("%8s %8s %14s %8s %8s %8s %8s %8s\n", "backend", "disks", "disk-steps/s", "broad",
              "narrow", "solve", "account", "lost");
  for (double r : {0.0287, 0.0166, 0.0091}) {
    Scene scene = probe_scene(r);
    double box2d_rate = 0.0;
    for (Backend b : {Backend::Box2D, Backend::Soft}) {
      scene.solver.backend = b;
      const Row row = measure(scene, seconds);
      std::printf("%8s %8zu %14.3g %7.0f%% %7.0f%% %7.0f%% %7.0f%% %8lld", b == Backend::Box2D ? "box2d" : "soft",
                  row.disks, row.rate, 100 * row.broad, 100 * row.narrow, 100 * row.solve,
                  100 * row.account, row.escaped);
      if (b == Backend::Box2D) box2d_rate = row.rate;
      else std::printf("   soft/box2d %.2fx", row.rate / box2d_rate);
      std::printf("\n");
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
  Scene base = load_scene(path);
  base.mill.direction = Direction::Forward;
  std::printf("%s: %d batches of %.2f revolutions after settle and spin-up (mean +- batch-means SE)\n",
              path.c_str(), batches, revolutions / batches);
  for (Backend b : {Backend::Box2D, Backend::Soft}) {
    if (only && std::strcmp(only, b == Backend::Box2D ? "box2d" : "soft") != 0) continue;
    Scene scene = base;
    scene.solver.backend = b;
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

}  // namespace

int main(int argc, char** argv) {
  if (argc > 2 && std::strcmp(argv[1], "--compare") == 0)
    return compare(argv[2], argc > 3 ? std::atof(argv[3]) : 6.0, argc > 4 ? std::atoi(argv[4]) : 6,
                   argc > 5 ? argv[5] : nullptr);
  return speed_table(argc > 1 ? std::atof(argv[1]) : 1.0);
}
