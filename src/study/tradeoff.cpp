// Speed against accuracy: the fidelity ladder, its runs and their errors (see tradeoff.hpp).
#include "study/tradeoff.hpp"

#include <algorithm>
#include <optional>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>

#include <time.h>

#include "common/errors.hpp"
#include "common/parallel.hpp"
#include "common/units.hpp"
#include "geometry/polyline.hpp"
#include "io/csv.hpp"
#include "metrics/pareto.hpp"
#include "scene/fidelity.hpp"
#include "scene/filling.hpp"
#include "scene/limits.hpp"

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
};

// Every setting's scenes within the run limits, before any of them runs. The smoothing radius
// is not checked here: a rung whose radius the history refuses is reported as failed, which is
// what that rung measures.
void check_ladder(const TradeoffLadder& ladder) {
  for (const auto& setting : ladder.settings)
    for (const Scene& s : setting.scenes) check_run_limits(s, s.source_file);
}

}  // namespace

namespace {

using Setter = std::function<void(Scene&)>;
using KnobValues = std::vector<std::pair<std::string, Setter>>;

// The designs with the command line's history length; a limit it breaks is named as its.
std::vector<Scene> ladder_base(const std::vector<Scene>& designs, const TradeoffOptions& o) {
  std::vector<Scene> base = designs;
  for (Scene& s : base) {
    if (o.stages > 0) s.wear.stages = o.stages;
    if (o.stage_hours > 0.0) s.wear.stage_hours = o.stage_hours;
    if (o.stages > 0 || o.stage_hours > 0.0) try {
        check_run_limits(s, s.source_file);
      } catch (const InputError& e) {
        throw InputError("", "--stages, --stage-hours",
                         "a history within the run's limits; " + std::to_string(s.wear.stages) + " stages of " +
                             io::format_number(s.wear.stage_hours) + " h give " + e.file + ": " + e.where + ": " +
                             e.expected);
      }
  }
  return base;
}

// The three presets, then another seed at reference and at standard: the same numerics with
// the charge's noise drawn again. The first is the ladder's noise floor (no setting can be
// shown closer to the reference than the reference is to itself); the second is standard's
// own scatter.
void add_presets(const std::vector<Scene>& base, bool reseed, TradeoffLadder& ladder) {
  for (const char* name : {"reference", "standard", "draft"}) {
    std::vector<Scene> scenes = base;
    for (Scene& s : scenes) apply_fidelity(s, name);
    ladder.settings.push_back({name, "preset", name, std::move(scenes)});
  }
  if (!reseed) return;
  for (const char* name : {"reference", "standard"}) {
    std::vector<Scene> scenes = base;
    for (Scene& s : scenes) {
      apply_fidelity(s, name);
      check_derived_seeds(s, 2, "the ladder's reseeded rows");
      s.solver.seed += 1;
    }
    const std::string seed = std::to_string(scenes.front().solver.seed);
    ladder.settings.push_back({std::string(name) + " seed=" + seed, "seed", seed, std::move(scenes)});
  }
}

// The settings --only names, and the reference, which always runs.
void keep_only(const std::vector<std::string>& only, TradeoffLadder& ladder) {
  if (only.empty()) return;
  for (std::size_t i = 0; i < only.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (only[i] == only[j]) throw InputError("", "--only", "each label once, got \"" + only[i] + "\" twice");
  for (const std::string& want : only) {
    const bool known = std::any_of(ladder.settings.begin(), ladder.settings.end(),
                                   [&want](const TradeoffSetting& t) { return t.label == want; });
    if (!known) {
      std::string labels;
      for (const auto& t : ladder.settings) labels += (labels.empty() ? "" : ", ") + t.label;
      throw InputError("", "--only", "labels of this ladder (\"" + want + "\" is not one): " + labels);
    }
  }
  std::vector<TradeoffSetting> kept{ladder.settings.front()};
  for (std::size_t k = 1; k < ladder.settings.size(); ++k)
    if (std::find(only.begin(), only.end(), ladder.settings[k].label) != only.end())
      kept.push_back(std::move(ladder.settings[k]));
  ladder.settings = std::move(kept);
}

// One knob of the standard scenes, a setting per value; held (listed, not laddered) when a
// design's file sets one of its keys.
void add_knob(const std::vector<Scene>& designs, const std::vector<Scene>& standard_scenes,
              const std::string& name, const std::vector<std::string>& keys, const KnobValues& values,
              TradeoffLadder& ladder) {
  for (const auto& k : keys)
    for (const Scene& d : designs)
      if (d.file_sets(k)) {
        ladder.held_knobs.push_back(name + " (a scene sets " + k + ")");
        return;
      }
  for (const auto& [text, set] : values) {
    std::vector<Scene> scenes = standard_scenes;
    for (Scene& s : scenes) {
      set(s);
      s.fidelity = "standard+" + name;
    }
    ladder.settings.push_back({name + "=" + text, name, text, std::move(scenes)});
  }
}

// The other backend at its own standard step (the library has no substeps), unless a file
// sets the step.
KnobValues backend_values(bool soft, const FidelityDef& standard) {
  return {{soft ? "box2d" : "soft", [soft, &standard](Scene& s) {
             s.solver.backend = soft ? Backend::Box2D : Backend::Soft;
             if (!s.file_sets("solver.time_step") && !s.file_sets("solver.steps_per_second"))
               s.solver.time_step_s = soft ? standard.box2d_time_step_s : standard.time_step_s;
           }}};
}

// Draft's, reference's and half standard's step, leaving out any that is standard's own.
KnobValues time_step_values(const FidelityDef& draft, const FidelityDef& standard,
                            const FidelityDef& reference) {
  KnobValues values;
  for (double dt : {0.5 * standard.time_step_s, draft.time_step_s, reference.time_step_s})
    if (std::fabs(dt - standard.time_step_s) > 1e-9 * standard.time_step_s)
      values.push_back({time_step_text(dt), [dt](Scene& s) { s.solver.time_step_s = dt; }});
  return values;
}

KnobValues substep_values(const FidelityDef& standard) {
  KnobValues values;
  for (int n : {std::max(1, standard.substeps / 2), 2 * standard.substeps})
    values.push_back({std::to_string(n), [n](Scene& s) { s.solver.substeps = n; }});
  return values;
}

KnobValues iteration_values(const FidelityDef& draft, const FidelityDef& reference) {
  KnobValues values;
  for (const FidelityDef* p : {&draft, &reference}) {
    const int v = p->velocity_iterations, q = p->position_iterations;
    values.push_back({std::to_string(v) + "/" + std::to_string(q), [v, q](Scene& s) {
                        s.solver.velocity_iterations = v;
                        s.solver.position_iterations = q;
                      }});
  }
  return values;
}

KnobValues window_values(const FidelityDef& draft, const FidelityDef& reference) {
  KnobValues values;
  for (double w : {draft.window_revolutions, reference.window_revolutions})
    values.push_back({num(w), [w](Scene& s) { s.wear.window_revolutions = w; }});
  return values;
}

KnobValues depth_step_values(const FidelityDef& draft, const FidelityDef& reference) {
  KnobValues values;
  for (double d : {draft.max_depth_step_m, reference.max_depth_step_m})
    values.push_back({num(in_mm(d)) + "mm", [d](Scene& s) { s.wear.max_depth_step_m = d; }});
  return values;
}

KnobValues factor_values(const FidelityDef& draft, const FidelityDef& reference) {
  KnobValues values;
  for (double f : {draft.factor, reference.factor})
    values.push_back({num(f), [f](Scene& s) { s.wear.factor = f; }});
  return values;
}

// Size cut-offs relative to the smallest rock, as an absolute size means nothing across
// scenes; and, for a fine charge (rocks finer than 50 mm, e.g. a size distribution down to
// 25 mm), the cut-offs 25 and 50 mm that SAG scenes use. Only values that cut something and
// keep part of every rock species of every design (and a disk of it), and of values that leave the same charge
// (size classes: 31.25 and 37.5 mm both drop only a 25 mm class) the first.
KnobValues size_cutoff_values(const std::vector<Scene>& standard_scenes) {
  double smallest_rock = INFINITY, largest_rock_min = INFINITY;
  for (const Scene& d : standard_scenes)
    for (const auto& sp : d.charge.species)
      if (!sp.is_ball && d.species_in_use(sp)) {
        smallest_rock = std::min(smallest_rock, sp.smallest_diameter_m());
        largest_rock_min = std::min(largest_rock_min, sp.largest_diameter_m());
      }
  KnobValues values;
  if (!std::isfinite(smallest_rock)) return values;
  std::vector<double> cuts;
  for (double mm : {25.0, 50.0})
    if (mm * 1e-3 > smallest_rock) cuts.push_back(mm * 1e-3);
  for (double f : {1.25, 1.5}) cuts.push_back(f * smallest_rock);
  std::sort(cuts.begin(), cuts.end());
  // The charge a cut-off leaves: every design's rock species' smallest size kept; none where
  // a species' kept classes hold none of its listed mass, or too little of the filling for a
  // disk (the run would be refused).
  auto charge_left = [&standard_scenes](double cut) -> std::optional<std::vector<double>> {
    std::vector<double> smallest;
    for (Scene d : standard_scenes) {
      d.solver.size_cutoff_m = cut;
      const std::vector<SpeciesDef> placed = d.species_as_placed();
      for (std::size_t k = 0; k < placed.size(); ++k) {
        const SpeciesDef& sp = placed[k];
        if (sp.is_ball) continue;
        double kept = 0.0;
        for (double f : sp.mass_fractions) kept += f;
        if (!sp.diameters_m.empty() && !(kept > 0.0)) return std::nullopt;
        if (d.species_in_use(sp) && !species_gets_a_disk(d, k)) return std::nullopt;
        smallest.push_back(sp.smallest_diameter_m());
      }
    }
    return smallest;
  };
  std::vector<std::vector<double>> left;
  for (double cut : cuts) {
    if (cut >= largest_rock_min) continue;
    std::optional<std::vector<double>> charge = charge_left(cut);
    if (!charge || std::find(left.begin(), left.end(), *charge) != left.end()) continue;
    left.push_back(std::move(*charge));
    values.push_back({num(in_mm(cut)) + "mm", [cut](Scene& s) { s.solver.size_cutoff_m = cut; }});
  }
  return values;
}

// Draft's mesh, and half standard's (standard already shares the reference's).
KnobValues mesh_values(const FidelityDef& draft, const FidelityDef& standard) {
  KnobValues values;
  for (auto [shell_m, lifter_m] : {std::pair{draft.shell_edge_m, draft.lifter_edge_m},
                                   std::pair{0.5 * standard.shell_edge_m, 0.5 * standard.lifter_edge_m}})
    values.push_back({num(in_mm(shell_m)) + "/" + num(in_mm(lifter_m)) + "mm", [shell_m, lifter_m](Scene& s) {
                        s.mill.mesh.shell_edge_m = shell_m;
                        s.mill.mesh.lifter_edge_m = lifter_m;
                      }});
  return values;
}

// Half and twice the smoothing radius; the default radius is each design's smallest particle
// radius, so the factor applies per design (the label gives the first design's).
KnobValues smoothing_values(const Scene& standard_scene) {
  auto radius = [](const Scene& s) {
    return s.wear.smoothing_radius_m > 0.0 ? s.wear.smoothing_radius_m : s.smallest_particle_radius_m();
  };
  KnobValues values;
  for (double f : {0.5, 2.0})
    values.push_back({num(in_mm(f * radius(standard_scene))) + "mm",
                      [f, radius](Scene& s) { s.wear.smoothing_radius_m = f * radius(s); }});
  return values;
}

}  // namespace

TradeoffLadder tradeoff_ladder(const std::vector<Scene>& designs, const TradeoffOptions& o) {
  if (designs.empty()) throw InputError("", "SCENE", "at least one design");
  // The errors of a setting are one lifter's profile, area and height against the reference
  // setting's: a pattern's kinds of other shapes wear apart, and the one measured would speak
  // for all of them.
  for (const Scene& d : designs)
    if (!d.mill.one_lifter_shape())
      throw InputError(d.source_file, "lifters.pattern",
                       "one lifter shape: tradeoff measures one lifter's profile, area and height against the "
                       "reference setting, and the kinds of this pattern wear apart; measure a scene of each kind "
                       "(lifters.profile = its file)");
  const std::vector<Scene> base = ladder_base(designs, o);
  TradeoffLadder ladder;
  add_presets(base, !o.quick, ladder);
  if (!o.quick) {
    const FidelityDef& draft = fidelity_preset("draft");
    const FidelityDef& standard = fidelity_preset("standard");
    const FidelityDef& reference = fidelity_preset("reference");
    std::vector<Scene> std_scenes = base;
    for (Scene& s : std_scenes) apply_fidelity(s, "standard");
    const Scene& first = std_scenes.front();
    auto knob = [&](const std::string& name, const std::vector<std::string>& keys, const KnobValues& values) {
      add_knob(designs, std_scenes, name, keys, values, ladder);
    };
    const bool soft = first.solver.backend == Backend::Soft;
    knob("backend", {"solver.backend"}, backend_values(soft, standard));
    knob("time_step", {"solver.time_step", "solver.steps_per_second"},
         time_step_values(draft, standard, reference));
    if (soft)
      knob("substeps", {"solver.substeps"}, substep_values(standard));
    else
      knob("iterations", {"solver.velocity_iterations", "solver.position_iterations"},
           iteration_values(draft, reference));
    knob("window", {"wear.window_revolutions"}, window_values(draft, reference));
    if (first.wear.mode == WearMode::Staged)
      knob("depth_step", {"wear.max_depth_step"}, depth_step_values(draft, reference));
    else
      knob("factor", {"wear.factor"}, factor_values(draft, reference));
    const KnobValues cutoffs = size_cutoff_values(std_scenes);
    if (!cutoffs.empty()) knob("size_cutoff", {"solver.size_cutoff"}, cutoffs);
    knob("mesh", {"lifters.shell_edge", "lifters.lifter_edge"}, mesh_values(draft, standard));
    knob("smoothing", {"wear.smoothing_radius"}, smoothing_values(first));
  }
  keep_only(o.only, ladder);
  check_ladder(ladder);
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
  return d;
}

struct DesignErrors {
  double dev_max_m = 0.0, dev_mean_m = 0.0;
  double area_err = 0.0, power_err = 0.0, life_err = kNaN;  // fractions
};

DesignErrors compare_digests(const HistoryDigest& d, const HistoryDigest& ref, double height_m, double area_m2) {
  DesignErrors e;
  // Sampled every 1% of the lifter height: fine against any deviation worth reporting.
  profile_deviation(d.final_profile, ref.final_profile, 0.01 * height_m, e.dev_max_m, e.dev_mean_m);
  const std::size_t n = std::min(d.hours.size(), ref.hours.size());
  for (std::size_t k = 0; k < n; ++k) {
    e.area_err = std::max(e.area_err, std::fabs(d.area_m2[k] - ref.area_m2[k]) / area_m2);
    const double p = d.power_kW_per_m[k], pr = ref.power_kW_per_m[k];
    if (std::isfinite(p) && std::isfinite(pr) && pr != 0.0) e.power_err = std::max(e.power_err, std::fabs(p - pr) / pr);
  }
  if (std::isfinite(d.life_h) && std::isfinite(ref.life_h) && ref.life_h > 0.0)
    e.life_err = std::fabs(d.life_h - ref.life_h) / ref.life_h;
  return e;
}

// The order of the designs by life, longest first (ties by index).
std::vector<std::size_t> life_order(const std::vector<HistoryDigest>& d) {
  std::vector<std::size_t> idx(d.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::stable_sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return d[a].life_h > d[b].life_h; });
  return idx;
}

// Fill row's errors from its designs' digests against the reference's.
void compare_setting(TradeoffRow& row, const std::vector<HistoryDigest>& d, const std::vector<HistoryDigest>& ref,
                     const std::vector<double>& height_m, const std::vector<double>& area_m2) {
  row.dev_max_m = row.dev_max_pct = row.dev_mean_m = row.dev_mean_pct = 0.0;
  row.area_err_pct = row.power_err_pct = row.life_err_pct = 0.0;
  for (std::size_t i = 0; i < d.size(); ++i) {
    const DesignErrors e = compare_digests(d[i], ref[i], height_m[i], area_m2[i]);
    row.dev_max_m = std::max(row.dev_max_m, e.dev_max_m);
    row.dev_max_pct = std::max(row.dev_max_pct, 100.0 * e.dev_max_m / height_m[i]);
    row.dev_mean_m = std::max(row.dev_mean_m, e.dev_mean_m);
    row.dev_mean_pct = std::max(row.dev_mean_pct, 100.0 * e.dev_mean_m / height_m[i]);
    row.area_err_pct = std::max(row.area_err_pct, 100.0 * e.area_err);
    row.power_err_pct = std::max(row.power_err_pct, 100.0 * e.power_err);
    // NaN (no life) anywhere makes the worst NaN: max() would hide it.
    row.life_err_pct = std::isfinite(e.life_err) && std::isfinite(row.life_err_pct)
                           ? std::max(row.life_err_pct, 100.0 * e.life_err)
                           : kNaN;
    row.designs[i].dev_max_pct = 100.0 * e.dev_max_m / height_m[i];
    row.designs[i].life_err_pct = 100.0 * e.life_err;
  }
  row.life_order_same = life_order(d) == life_order(ref);
  row.life_ratio_err_pct = d.size() < 2 ? kNaN : 0.0;
  for (std::size_t i = 1; i < d.size(); ++i) {
    const double r = d[i].life_h / d[0].life_h, rr = ref[i].life_h / ref[0].life_h;
    row.life_ratio_err_pct = std::isfinite(r) && std::isfinite(rr) && std::isfinite(row.life_ratio_err_pct)
                                 ? std::max(row.life_ratio_err_pct, 100.0 * std::fabs(r - rr) / rr)
                                 : kNaN;
  }
}

}  // namespace

void mark_pareto(std::vector<TradeoffRow>& rows) {
  std::vector<double> cpu, dev;
  for (const TradeoffRow& r : rows) {
    cpu.push_back(r.error.empty() ? r.cpu_s : kNaN);
    dev.push_back(r.dev_max_pct);
  }
  const std::vector<bool> front = pareto_front(cpu, Better::Lower, dev, Better::Lower);
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i].pareto = front[i];
}

TradeoffReport run_tradeoff(const TradeoffLadder& ladder, int jobs, const TradeoffCallbacks& cb) {
  if (ladder.settings.empty()) throw RunError("tradeoff: an empty ladder");
  const std::vector<Scene>& ref_scenes = ladder.settings.front().scenes;
  const std::size_t n_designs = ref_scenes.size();
  TradeoffReport report;
  report.held_knobs = ladder.held_knobs;
  report.stages = ref_scenes.front().wear.stages;
  report.stage_hours = ref_scenes.front().wear.stage_hours;
  for (const Scene& s : ref_scenes) {
    report.scene_name += (report.scene_name.empty() ? "" : " + ") + s.name;
    report.design_names.push_back(s.name);
    // The scales: the new lifter (the mesh does not change its area or height beyond
    // rounding; take the reference's).
    const LifterMetrics m = measure_lifter(new_liner_unit(s), s.radius_m());
    report.lifter_height_m.push_back(m.height_m);
    report.lifter_area_m2.push_back(m.area_m2);
  }

  // One task per (setting, design); the reference's designs come first.
  const std::size_t n = ladder.settings.size();
  std::vector<TradeoffRow> rows(n);
  std::vector<std::vector<HistoryDigest>> digests(n, std::vector<HistoryDigest>(n_designs));
  for (std::size_t i = 0; i < n; ++i) {
    const TradeoffSetting& s = ladder.settings[i];
    if (s.scenes.size() != n_designs) throw RunError("tradeoff: setting " + s.label + " has a different design count");
    rows[i].label = s.label;
    rows[i].knob = s.knob;
    rows[i].value = s.value;
    rows[i].designs.resize(n_designs);
  }
  std::mutex mutex;
  for_each_index_parallel(n * n_designs, jobs, [&](std::size_t task) {
    const std::size_t i = task / n_designs, k = task % n_designs;
    const TradeoffSetting& s = ladder.settings[i];
    const Scene& scene = s.scenes[k];
    if (cb.on_start) {
      std::lock_guard<std::mutex> lock(mutex);
      cb.on_start(s);
    }
    TradeoffDesign out;
    out.name = scene.name;
    HistoryDigest dig;
    std::vector<std::string> events;
    std::int64_t disk_steps = 0;
    double simulated = 0.0;
    std::string error;
    const auto t0 = Clock::now();
    const double c0 = thread_cpu_s();
    try {
      const WearHistory h = run_wear_history(scene);
      throw_if_failed(h);  // a lost disk or rule 1's stop: the setting failed, it has no result
      for (const auto& st : h.stages) {
        disk_steps += st.disk_steps;
        simulated += st.simulated_s;
      }
      out.final_hours = h.stages.back().hours;
      out.final_area_m2 = h.stages.back().lifter.area_m2;
      out.final_height_m = h.stages.back().lifter.height_m;
      out.life_h = h.life_h;
      out.life_extrapolated = h.life_extrapolated;
      for (const auto& e : h.events) events.push_back(scene.name + ": " + e);
      dig = digest(h);
      out.final_profile = dig.final_profile;
    } catch (const std::runtime_error& e) {  // RunError, or InputError from a limit check
      error = scene.name + ": " + e.what();
    }
    const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
    const double cpu = thread_cpu_s() - c0;
    std::lock_guard<std::mutex> lock(mutex);
    TradeoffRow& row = rows[i];
    row.wall_s += wall;
    row.cpu_s += cpu;
    row.disk_steps += disk_steps;
    row.simulated_s += simulated;
    row.events.insert(row.events.end(), events.begin(), events.end());
    if (!error.empty()) row.error += (row.error.empty() ? "" : "; ") + error;
    digests[i][k] = std::move(dig);
    row.designs[k] = out;
    if (cb.on_design) cb.on_design(s, out, wall, cpu, error);
  });

  const TradeoffRow& ref = rows.front();
  if (!ref.error.empty()) throw RunError("tradeoff: the reference run failed: " + ref.error);
  for (std::size_t i = 0; i < n; ++i) {
    TradeoffRow& r = rows[i];
    if (!r.error.empty()) {
      r.dev_max_m = r.dev_max_pct = r.dev_mean_m = r.dev_mean_pct = kNaN;
      r.area_err_pct = r.power_err_pct = r.life_err_pct = r.life_ratio_err_pct = kNaN;
      r.life_order_same = false;
      continue;
    }
    compare_setting(r, digests[i], digests[0], report.lifter_height_m, report.lifter_area_m2);
    r.speedup = r.cpu_s > 0.0 ? ref.cpu_s / r.cpu_s : kNaN;
  }
  mark_pareto(rows);
  report.rows = std::move(rows);
  return report;
}

}  // namespace millwear
