// Speed against accuracy: the fidelity ladder, its runs and their errors (see tradeoff.hpp).
#include "wear/tradeoff.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <thread>

#include <time.h>

#include "common/errors.hpp"
#include "geometry/polyline.hpp"
#include "scene/fidelity.hpp"

namespace millwear {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using Clock = std::chrono::steady_clock;

// CPU seconds of the calling thread (POSIX).
double thread_cpu_s() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

std::string num(double v, const char* fmt = "%g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

// A time step as "1/N" when it is one (every preset's is), else in seconds.
std::string time_step_text(double dt) {
  const double n = 1.0 / dt;
  if (std::fabs(n - std::round(n)) < 1e-6 * n) return "1/" + num(std::round(n), "%.0f");
  return num(dt);
}

// What a history is compared by: light, so the heavy records (snapshots) can go.
struct HistoryDigest {
  std::vector<double> hours, area_m2, power_kW_per_m;
  Polyline final_profile;
  double life_h = 0.0;
  bool life_extrapolated = false;
};

}  // namespace

TradeoffLadder tradeoff_ladder(const Scene& scene, const TradeoffOptions& o) {
  Scene base = scene;
  if (o.stages > 0) base.wear.stages = o.stages;
  if (o.stage_hours > 0.0) base.wear.stage_hours = o.stage_hours;
  const FidelityDef& draft = fidelity_preset("draft");
  const FidelityDef& reference = fidelity_preset("reference");

  TradeoffLadder ladder;
  auto preset = [&](const std::string& name) {
    Scene s = base;
    apply_fidelity(s, name);
    ladder.settings.push_back({name, "preset", name, s});
  };
  preset("reference");
  preset("standard");
  preset("draft");
  if (o.quick) return ladder;

  Scene std_scene = base;
  apply_fidelity(std_scene, "standard");
  // One knob of the standard scene; held (listed, not laddered) when the file sets a key.
  auto knob = [&](const std::string& name, std::vector<std::string> keys,
                  const std::vector<std::pair<std::string, std::function<void(Scene&)>>>& values) {
    for (const auto& k : keys)
      if (scene.file_sets(k)) {
        ladder.held_knobs.push_back(name + " (the scene sets " + k + ")");
        return;
      }
    for (const auto& [text, set] : values) {
      Scene s = std_scene;
      set(s);
      s.fidelity = "standard+" + name;
      ladder.settings.push_back({name + "=" + text, name, text, s});
    }
  };
  auto dt_value = [](double dt) {
    return std::pair{time_step_text(dt), std::function<void(Scene&)>([dt](Scene& s) { s.solver.time_step_s = dt; })};
  };
  knob("time_step", {"solver.time_step", "solver.steps_per_second"},
       {dt_value(1.0 / 200.0), dt_value(draft.time_step_s), dt_value(reference.time_step_s)});
  auto iter_value = [](const FidelityDef& p) {
    return std::pair{std::to_string(p.velocity_iterations) + "/" + std::to_string(p.position_iterations),
                     std::function<void(Scene&)>([v = p.velocity_iterations, q = p.position_iterations](Scene& s) {
                       s.solver.velocity_iterations = v;
                       s.solver.position_iterations = q;
                     })};
  };
  knob("iterations", {"solver.velocity_iterations", "solver.position_iterations"},
       {iter_value(draft), iter_value(reference)});
  auto window_value = [](double w) {
    return std::pair{num(w), std::function<void(Scene&)>([w](Scene& s) { s.wear.window_revolutions = w; })};
  };
  knob("window", {"wear.window_revolutions"}, {window_value(draft.window_revolutions),
                                              window_value(reference.window_revolutions)});
  if (scene.wear.mode == WearMode::Staged) {
    auto depth_value = [](double d) {
      return std::pair{num(d * 1e3) + "mm", std::function<void(Scene&)>([d](Scene& s) { s.wear.max_depth_step_m = d; })};
    };
    knob("depth_step", {"wear.max_depth_step"},
         {depth_value(draft.max_depth_step_m), depth_value(reference.max_depth_step_m)});
  } else {
    auto factor_value = [](double f) {
      return std::pair{num(f), std::function<void(Scene&)>([f](Scene& s) { s.wear.factor = f; })};
    };
    knob("factor", {"wear.factor"}, {factor_value(draft.factor), factor_value(reference.factor)});
  }
  // Size cut-off: relative to the smallest rock, as an absolute size means nothing across
  // scenes. Only values that keep part of every rock species are laddered.
  {
    double smallest_rock = INFINITY, largest_rock_min = INFINITY;
    for (const auto& sp : std_scene.charge.species)
      if (!sp.is_ball && std_scene.species_in_use(sp)) {
        smallest_rock = std::min(smallest_rock, sp.smallest_diameter_m());
        largest_rock_min = std::min(largest_rock_min, sp.largest_diameter_m());
      }
    std::vector<std::pair<std::string, std::function<void(Scene&)>>> values;
    if (std::isfinite(smallest_rock))
      for (double f : {1.25, 1.5}) {
        const double cut = f * smallest_rock;
        if (cut >= largest_rock_min) continue;
        values.push_back({num(cut * 1e3) + "mm", [cut](Scene& s) { s.solver.size_cutoff_m = cut; }});
      }
    if (!values.empty()) knob("size_cutoff", {"solver.size_cutoff"}, values);
  }
  auto mesh_value = [](const FidelityDef& p) {
    return std::pair{num(p.shell_edge_m * 1e3) + "/" + num(p.lifter_edge_m * 1e3) + "mm",
                     std::function<void(Scene&)>([a = p.shell_edge_m, b = p.lifter_edge_m](Scene& s) {
                       s.mill.mesh.shell_edge_m = a;
                       s.mill.mesh.lifter_edge_m = b;
                     })};
  };
  knob("mesh", {"lifters.shell_edge", "lifters.lifter_edge"}, {mesh_value(draft), mesh_value(reference)});
  {
    const double r0 = std_scene.wear.smoothing_radius_m > 0.0 ? std_scene.wear.smoothing_radius_m
                                                              : std_scene.smallest_particle_radius_m();
    std::vector<std::pair<std::string, std::function<void(Scene&)>>> values;
    for (double f : {0.5, 2.0}) {
      const double r = f * r0;
      values.push_back({num(r * 1e3) + "mm", [r](Scene& s) { s.wear.smoothing_radius_m = r; }});
    }
    knob("smoothing", {"wear.smoothing_radius"}, values);
  }
  return ladder;
}

void profile_deviation(const Polyline& a, const Polyline& b, double step_m, double& max_m, double& mean_m) {
  max_m = 0.0;
  double sum = 0.0;
  std::size_t n = 0;
  auto one_way = [&](const Polyline& from, const Polyline& to) {
    const double len = polyline_length(from);
    const int samples = std::max(2, static_cast<int>(std::ceil(len / step_m)) + 1);
    for (int i = 0; i < samples; ++i) {
      const double d = distance_to_polyline(point_at_length(from, len * i / (samples - 1)), to);
      max_m = std::max(max_m, d);
      sum += d;
      ++n;
    }
    // The vertices too: a sharp corner between samples must count.
    for (const Vec2& p : from) max_m = std::max(max_m, distance_to_polyline(p, to));
  };
  one_way(a, b);
  one_way(b, a);
  mean_m = n > 0 ? sum / static_cast<double>(n) : 0.0;
}

namespace {

HistoryDigest digest(const WearHistory& h) {
  HistoryDigest d;
  for (const auto& st : h.stages) {
    d.hours.push_back(st.hours);
    d.area_m2.push_back(st.lifter.area_m2);
    // A worn-out record has no charge window of its own (it repeats the last one).
    d.power_kW_per_m.push_back(st.worn_out ? kNaN : st.charge.power_kW_per_m);
  }
  if (!h.stages.empty()) d.final_profile = h.stages.back().units[0].surface;
  d.life_h = h.life_h;
  d.life_extrapolated = h.life_extrapolated;
  return d;
}

void compare_digests(TradeoffRow& row, const HistoryDigest& d, const HistoryDigest& ref, double height_m,
                     double area_m2) {
  double dmax = 0.0, dmean = 0.0;
  // Sampled every 1% of the lifter height: fine against any deviation worth reporting.
  profile_deviation(d.final_profile, ref.final_profile, 0.01 * height_m, dmax, dmean);
  row.dev_max_mm = dmax * 1e3;
  row.dev_mean_mm = dmean * 1e3;
  row.dev_max_pct = 100.0 * dmax / height_m;
  row.dev_mean_pct = 100.0 * dmean / height_m;
  const std::size_t n = std::min(d.hours.size(), ref.hours.size());
  double area_err = 0.0, power_err = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    area_err = std::max(area_err, std::fabs(d.area_m2[k] - ref.area_m2[k]) / area_m2);
    const double p = d.power_kW_per_m[k], pr = ref.power_kW_per_m[k];
    if (std::isfinite(p) && std::isfinite(pr) && pr != 0.0) power_err = std::max(power_err, std::fabs(p - pr) / pr);
  }
  row.area_err_pct = 100.0 * area_err;
  row.power_err_pct = 100.0 * power_err;
  row.life_err_pct = (std::isfinite(d.life_h) && std::isfinite(ref.life_h) && ref.life_h > 0.0)
                         ? 100.0 * std::fabs(d.life_h - ref.life_h) / ref.life_h
                         : kNaN;
}

}  // namespace

void compare_with_reference(TradeoffRow& row, const WearHistory& h, const WearHistory& ref, double height_m,
                            double area_m2) {
  compare_digests(row, digest(h), digest(ref), height_m, area_m2);
}

void mark_pareto(std::vector<TradeoffRow>& rows) {
  for (auto& r : rows) {
    r.pareto = false;
    if (!r.error.empty() || !std::isfinite(r.dev_max_pct)) continue;
    bool dominated = false;
    for (const auto& o : rows) {
      if (&o == &r || !o.error.empty() || !std::isfinite(o.dev_max_pct)) continue;
      if (o.cpu_s <= r.cpu_s && o.dev_max_pct <= r.dev_max_pct &&
          (o.cpu_s < r.cpu_s || o.dev_max_pct < r.dev_max_pct)) {
        dominated = true;
        break;
      }
    }
    r.pareto = !dominated;
  }
}

TradeoffReport run_tradeoff(const TradeoffLadder& ladder, int jobs, const TradeoffCallbacks& cb) {
  if (ladder.settings.empty()) throw RunError("tradeoff: an empty ladder");
  const Scene& ref_scene = ladder.settings.front().scene;
  TradeoffReport report;
  report.scene_name = ref_scene.name;
  report.held_knobs = ladder.held_knobs;
  report.stages = ref_scene.wear.stages;
  report.stage_hours = ref_scene.wear.stage_hours;
  // The scales: the new lifter (the mesh does not change its area or height beyond
  // rounding; take the reference's).
  const LifterMetrics new_lifter = measure_lifter(
      make_liner_unit(ref_scene.mill.lifter.points, ref_scene.radius_m(), ref_scene.mill.rows, ref_scene.mill.mesh),
      ref_scene.radius_m());
  report.lifter_height_m = new_lifter.height_m;
  report.lifter_area_m2 = new_lifter.area_m2;

  const std::size_t n = ladder.settings.size();
  std::vector<TradeoffRow> rows(n);
  std::vector<HistoryDigest> digests(n);
  std::mutex mutex;
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (;;) {
      const std::size_t i = next.fetch_add(1);
      if (i >= n) return;
      const TradeoffSetting& s = ladder.settings[i];
      if (cb.on_start) {
        std::lock_guard<std::mutex> lock(mutex);
        cb.on_start(s);
      }
      TradeoffRow row;
      row.label = s.label;
      row.knob = s.knob;
      row.value = s.value;
      const auto t0 = Clock::now();
      const double c0 = thread_cpu_s();
      try {
        const WearHistory h = run_wear_history(s.scene);
        row.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
        row.cpu_s = thread_cpu_s() - c0;
        for (const auto& st : h.stages) {
          row.disk_steps += st.disk_steps;
          row.simulated_s += st.simulated_s;
        }
        row.stages = h.stages.size();
        row.final_hours = h.stages.back().hours;
        row.final_area_mm2 = h.stages.back().lifter.area_m2 * 1e6;
        row.final_height_mm = h.stages.back().lifter.height_m * 1e3;
        row.life_h = h.life_h;
        row.life_extrapolated = h.life_extrapolated;
        row.events = h.events;
        digests[i] = digest(h);
        row.final_profile = digests[i].final_profile;
      } catch (const std::runtime_error& e) {  // RunError, or InputError from a limit check
        row.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
        row.cpu_s = thread_cpu_s() - c0;
        row.error = e.what();
      }
      std::lock_guard<std::mutex> lock(mutex);
      rows[i] = std::move(row);
      if (cb.on_row) cb.on_row(rows[i]);
    }
  };
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(n)));
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  const TradeoffRow& ref = rows.front();
  if (!ref.error.empty()) throw RunError("tradeoff: the reference run failed: " + ref.error);
  for (std::size_t i = 0; i < n; ++i) {
    TradeoffRow& r = rows[i];
    if (!r.error.empty()) {
      r.dev_max_mm = r.dev_max_pct = r.dev_mean_mm = r.dev_mean_pct = kNaN;
      r.area_err_pct = r.power_err_pct = r.life_err_pct = kNaN;
      continue;
    }
    compare_digests(r, digests[i], digests[0], report.lifter_height_m, report.lifter_area_m2);
    r.speedup = r.cpu_s > 0.0 ? ref.cpu_s / r.cpu_s : kNaN;
  }
  mark_pareto(rows);
  report.rows = std::move(rows);
  return report;
}

}  // namespace millwear
