// The wear history of one design, stage by stage. Stage 0 settles a fresh charge on the new
// liner; every later stage starts a fresh engine from the charge as the previous stage's
// wear ended (kept in its record), so a stage depends only on its record: resuming from a
// saved stage gives the same results as an uninterrupted run.
//
// Per stage (run_wear_history, at the end of the file): start_stage (geometry, engine, first
// window) -> stage_record -> last_stage_measured? -> wear_on: wear_through_stage (wear step ->
// reshape -> next window, until the stage's hours) -> finish_stage.
#include "wear/history.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "wear/archard.hpp"
#include "wear/life.hpp"
#include "wear/reshape.hpp"
#include "wear/wear_step.hpp"
#include "wear/window.hpp"

namespace millwear {

namespace {

using Clock = std::chrono::steady_clock;

// What every stage compares against: the liner the history starts from (new, or a measured
// worn one), derived once from the scene.
struct NewLiner {
  MillGeometry mill;        // every row as it starts
  LifterMetrics lifter;     // the first kind's
  std::vector<LifterMetrics> kinds;
  double smoothing_m = 0.0;
  std::vector<std::string> notes;  // what re-smoothing a measured profile changed
};

NewLiner new_liner(const Scene& scene) {
  NewLiner n;
  n.smoothing_m = smoothing_radius(scene);
  const double R = scene.radius_m();
  const int kinds = scene.mill.kind_count(), rows = scene.mill.rows;
  std::vector<LinerUnit> units;
  for (int k = 0; k < kinds; ++k) {
    units.push_back(starting_unit(scene, k, n.smoothing_m));
    const LifterProfile& p = scene.mill.kind(k);
    if (p.measured.empty()) continue;
    // The file's own lifter area (its points as read, on the unit's centring) against the
    // resampled, re-smoothed unit the history starts from.
    const LinerUnit built = new_liner_unit(scene, k);
    LinerUnit as_read;
    as_read.lifter_half_base_m = built.lifter_half_base_m;
    const double shift = measured_unit_shift_m(p.points, p.unit_pitch_m > 0.0);
    for (const Vec2& q : p.measured) as_read.surface.push_back({q.x + shift, q.y});
    const double a_file = measure_lifter(as_read, R).area_m2, a_start = measure_lifter(units.back(), R).area_m2;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "measured profile '%s': resampled and re-smoothed at %.3g mm, its lifter area went from %.6g mm^2 "
                  "(the file's) to %.6g mm^2 (%+.3g mm^2, %+.2f%%)%s",
                  p.name.c_str(), in_mm(n.smoothing_m), a_file * 1e6, a_start * 1e6, (a_start - a_file) * 1e6,
                  100.0 * (a_start - a_file) / a_file,
                  p.dropped_points > 0 ? (", " + std::to_string(p.dropped_points) + " repeated or looping points dropped").c_str()
                                       : "");
    n.notes.push_back(buf);
  }
  for (const LinerUnit& u : units) n.kinds.push_back(measure_lifter(u, R));
  n.lifter = n.kinds.front();
  if (scene.wear.average_rows) {
    n.mill = build_mill(R, rows, std::move(units), kinds);
  } else {
    std::vector<LinerUnit> per_row;
    for (int r = 0; r < rows; ++r) per_row.push_back(units[static_cast<std::size_t>(r % kinds)]);
    n.mill = build_mill(R, rows, std::move(per_row), kinds);
  }
  return n;
}

// Worn to the shell: the first row of any kind (row 0 for a plain liner).
bool any_worn_out(const std::vector<LinerUnit>& units, int kinds, double radius_m,
                  const std::vector<LifterMetrics>& start) {
  for (std::size_t k = 0; k < start.size() && k < units.size() && k < static_cast<std::size_t>(kinds); ++k)
    if (lifter_worn_out(measure_lifter(units[k], radius_m), start[k])) return true;
  return false;
}

struct WornVariance {
  double area_m4 = 0.0, height_m2 = 0.0;
};

// One stage being worn: the geometry the charge turns in, its engine, the window measured on
// the stage's starting geometry, and the stage's counters.
struct StageRun {
  int stage = 0;
  double hours = 0.0;
  double direction = 1.0;
  MillGeometry mill;
  std::unique_ptr<Engine> engine;
  WindowWork window;
  ChargeState start;        // the charge the stage started from (empty: a fresh fill)
  double simulated_s = 0.0;
  std::int64_t disk_steps = 0;
  Clock::time_point started;
  // The variance of the lifter area and height (and each kind's) the stage's wear updates
  // removed.
  bool worn_through = false;
  WornVariance worn;
  std::vector<WornVariance> kind_worn;
  std::size_t events_noted = 0;  // the engine's events already in the history
};

void check_stop(const WearCallbacks& cb) {
  if (cb.should_stop && cb.should_stop()) throw RunError("interrupted");
}

void report_progress(const WearCallbacks& cb, const StageRun& run) {
  if (!cb.on_progress) return;
  WearProgress p;
  p.stage = run.stage + 1;
  p.hours = run.hours;
  p.simulated_s = run.simulated_s;
  const double wall = std::chrono::duration<double>(Clock::now() - run.started).count();
  p.disk_steps_per_s = wall > 0 ? run.disk_steps / wall : 0.0;
  cb.on_progress(p);
}

std::int64_t disk_steps_of(const Accounting& acc, const Engine& engine) {
  return acc.steps * static_cast<std::int64_t>(engine.state().size());
}

// The engine for stage k on `mill`: a fresh charge settled on the new liner (stage 0), or the
// charge the previous stage ended with; then the first window on this geometry.
StageRun start_stage(const Scene& scene, int k, MillGeometry mill, ChargeState start, const WearCallbacks& cb) {
  StageRun run;
  run.started = Clock::now();
  run.stage = k;
  run.hours = scene.wear.start_hours + k * scene.wear.stage_hours;
  run.mill = std::move(mill);
  const std::function<void()> stop = [&cb] { check_stop(cb); };
  stop();
  run.direction = direction_at(scene, run.hours);
  run.start = std::move(start);
  if (run.start.size() == 0) {
    run.engine = make_engine(scene, run.mill, fill_charge(scene, run.mill), accounting_options_for(scene));
    settle_and_spin_up(*run.engine, scene, run.direction, stop);
  } else {
    run.engine = make_engine(scene, run.mill, run.start, accounting_options_for(scene));
    turn_mill(*run.engine, scene, run.direction, run.start.mill_speed_rad_s * run.direction < 0.0, stop);
  }
  run.window = simulate_window(*run.engine, scene, run.mill, stop);
  run.simulated_s = run.window.simulated_s;
  run.disk_steps = disk_steps_of(run.window.accounting, *run.engine);
  return run;
}

// The stage's record: the liner it started on and what the charge did with it.
StageRecord stage_record(const Scene& scene, const NewLiner& liner, const StageRun& run, double c_real) {
  const WindowWork& w = run.window;
  const MillGeometry& mill = run.mill;
  StageRecord rec;
  rec.stage = run.stage;
  rec.hours = run.hours;
  rec.units = mill.units;
  rec.lifter = measure_lifter(mill.units[0], mill.radius_m);
  rec.kinds = kind_metrics(mill.units, mill.kinds, mill.radius_m);
  rec.charge = charge_figures(w.accounting, scene, run.direction * scene.angular_speed_rad_s());
  const double t = scene.slice_thickness();
  rec.area_loss_rate_m2_per_s = c_real * w.lifter_power_mean_W / t;
  for (double p : kind_lifter_power_W(mill, w.unit_power_W)) rec.kind_area_loss_rate_m2_per_s.push_back(c_real * p / t);
  if (mill.kinds > 1) rec.kind_area_loss_rate_rel_sem = w.kind_lifter_power_rel_sem;
  rec.area_loss_rate_rel_sem = w.lifter_power_rel_sem;
  rec.charge_errors = w.charge_errors;
  rec.spectrum_count_per_s.resize(kSpectrumBins);
  rec.spectrum_energy_W.resize(kSpectrumBins);
  for (int b = 0; b < kSpectrumBins; ++b) {
    rec.spectrum_count_per_s[b] = w.accounting.spectrum_count[b] / w.accounting.time_s;
    rec.spectrum_energy_W[b] = w.accounting.spectrum_energy_J[b] / w.accounting.time_s;
  }
  rec.edge_wear_rate_m_per_s.resize(mill.boundary.size());
  for (std::size_t e = 0; e < mill.boundary.size(); ++e) {
    rec.edge_wear_rate_m_per_s[e] = boundary_edge_wear_rate_m_per_s(scene, mill, e, w.edge_power_W[e], t, c_real);
    rec.liner_loss_rate_m2_per_s += rec.edge_wear_rate_m_per_s[e] * mill.edge_length_m[e];
  }
  if (scene.outputs.vtk) {
    rec.frames = w.frames;
    rec.edge_shear_W_per_m2.resize(mill.boundary.size());
    rec.edge_impact_W_per_m2.resize(mill.boundary.size());
    for (std::size_t e = 0; e < mill.boundary.size(); ++e) {
      const double area = mill.edge_length_m[e] * t;
      rec.edge_shear_W_per_m2[e] = w.edge_power_W[e] / area;
      rec.edge_impact_W_per_m2[e] = w.accounting.impact_energy_J[e] / w.accounting.time_s / area;
    }
  }
  rec.snapshot = run.engine->state();
  rec.mill_angle_rad = run.engine->state().mill_angle_rad;
  rec.start_charge = run.start;
  rec.worn_out = any_worn_out(mill.units, mill.kinds, mill.radius_m, liner.kinds);
  return rec;
}

// The errors of the area and height the stage's wear removed on its way to the next stage.
void record_worn_errors(StageRecord& rec, const StageRun& run) {
  rec.worn_se = {std::sqrt(run.worn.area_m4), std::sqrt(run.worn.height_m2)};
  rec.kind_worn_se.clear();
  for (const WornVariance& v : run.kind_worn) rec.kind_worn_se.push_back({std::sqrt(v.area_m4), std::sqrt(v.height_m2)});
}

// The stage's timings, then the caller hears of it (and persists it).
void finish_stage(WearHistory& history, const StageRun& run, const WearCallbacks& cb) {
  StageRecord& rec = history.stages.back();
  rec.wall_s = std::chrono::duration<double>(Clock::now() - run.started).count();
  rec.simulated_s = run.simulated_s;
  if (run.worn_through) record_worn_errors(rec, run);
  rec.disk_steps = run.disk_steps;
  if (cb.on_stage) cb.on_stage(rec);
}

enum class StageEnd { Finished, WornOut, StoppedByRule };

// The relative error of a wear update's rates: its window's batch means (staged), or, for a
// continuous update, the stage's first window's scaled to the update's simulated time (batch
// means: the error falls as one over the square root of the time averaged).
double update_rel_error(double window_rel, double window_s, const WearStep& step, bool staged) {
  if (staged || !(step.simulated_s > 0.0)) return window_rel;
  return window_rel * std::sqrt(window_s / step.simulated_s);
}

// The lifter's area and height (row 0, the first kind of a pattern) and, for a pattern, each
// kind's.
struct LifterSize {
  LifterMetrics lifter;
  std::vector<LifterMetrics> kinds;
};
LifterSize lifter_size(const MillGeometry& mill) {
  LifterSize a;
  a.lifter = measure_lifter(mill.units[0], mill.radius_m);
  if (mill.kinds > 1) a.kinds = kind_metrics(mill.units, mill.kinds, mill.radius_m);
  return a;
}

// The variance one wear update adds to what the stage removes: the area lost times the
// relative error of the lifters' shear power that wore it, and the height lost times that of
// the power on the lifters' tops.
void add_update_variance(WornVariance& v, const LifterMetrics& before, const LifterMetrics& after, double area_rel,
                         double top_rel) {
  const double a = (before.area_m2 - after.area_m2) * area_rel, h = (before.height_m - after.height_m) * top_rel;
  v.area_m4 += a * a;
  v.height_m2 += h * h;
}

void add_update_variance(StageRun& run, const LifterSize& before, const LifterSize& after, const WearStep& step,
                         bool staged) {
  const WindowWork& w = run.window;
  const auto rel = [&](const std::vector<double>& per_kind, std::size_t k, double all) {
    return update_rel_error(k < per_kind.size() ? per_kind[k] : all, w.simulated_s, step, staged);
  };
  // A pattern's lifter is its first kind's.
  const bool pattern = !before.kinds.empty();
  add_update_variance(run.worn, before.lifter, after.lifter,
                      pattern ? rel(w.kind_lifter_power_rel_sem, 0, w.lifter_power_rel_sem)
                              : update_rel_error(w.lifter_power_rel_sem, w.simulated_s, step, staged),
                      pattern ? rel(w.kind_lifter_top_rel_sem, 0, w.lifter_top_rel_sem)
                              : update_rel_error(w.lifter_top_rel_sem, w.simulated_s, step, staged));
  run.kind_worn.resize(before.kinds.size());
  for (std::size_t k = 0; k < before.kinds.size() && k < after.kinds.size(); ++k)
    add_update_variance(run.kind_worn[k], before.kinds[k], after.kinds[k],
                        rel(w.kind_lifter_power_rel_sem, k, w.lifter_power_rel_sem),
                        rel(w.kind_lifter_top_rel_sem, k, w.lifter_top_rel_sem));
  run.worn_through = true;
}

// Wear the liner from the stage's start to its end: wear step -> reshape -> (the mill turns
// on) -> the next window, until the stage's hours or the shell.
StageEnd wear_through_stage(const Scene& scene, const NewLiner& liner, StageRun& run, double c_real,
                            WearHistory& history, const WearCallbacks& cb) {
  const bool staged = scene.wear.mode == WearMode::Staged;
  const std::function<void()> stop = [&cb] { check_stop(cb); };
  const double target_h = scene.wear.start_hours + (run.stage + 1) * scene.wear.stage_hours;
  while (run.hours < target_h - 1e-9) {
    stop();
    const double max_hours = std::min(target_h, next_reversal(scene, run.hours)) - run.hours;
    const WearStep step =
        staged ? staged_step(scene, run.mill, run.window, c_real, max_hours)
               : continuous_step(scene, run.mill, *run.engine, c_real, max_hours, liner.lifter.height_m, run.stage + 1,
                                 stop);
    run.simulated_s += step.simulated_s;
    run.disk_steps += step.disk_steps;
    if (!step.stop_event.empty()) {
      history.events.push_back(step.stop_event);
      if (history.failure.empty()) history.failure = step.stop_event;
      return StageEnd::StoppedByRule;
    }
    const LifterSize before = lifter_size(run.mill);
    run.mill = build_mill(run.mill.radius_m, run.mill.rows,
                          reshape(run.mill.units, step.depths, run.mill.radius_m, liner.smoothing_m,
                                  scene.mill.mesh, liner.lifter.area_m2, run.stage + 1),
                          run.mill.kinds);
    add_update_variance(run, before, lifter_size(run.mill), step, staged);
    run.hours += step.hours;
    if (cb.on_update) cb.on_update({run.stage, run.hours, &run.mill, &run.engine->state()});
    if (any_worn_out(run.mill.units, run.mill.kinds, run.mill.radius_m, liner.kinds))
      return StageEnd::WornOut;
    if (run.hours >= target_h - 1e-9) return StageEnd::Finished;
    run.engine->set_liner(run.mill);
    const double direction = direction_at(scene, run.hours);
    if (direction != run.direction) {
      run.direction = direction;
      turn_mill(*run.engine, scene, run.direction, true, stop);
    }
    if (staged) {
      run.window = simulate_window(*run.engine, scene, run.mill, stop);
      run.simulated_s += run.window.simulated_s;
      run.disk_steps += disk_steps_of(run.window.accounting, *run.engine);
    }
    report_progress(cb, run);
  }
  return StageEnd::Finished;
}

// The worn-out geometry as the history's last stage.
void record_worn_out(WearHistory& history, const StageRun& run, const WearCallbacks& cb) {
  StageRecord rec;
  rec.stage = run.stage + 1;
  rec.hours = run.hours;
  rec.units = run.mill.units;
  rec.lifter = measure_lifter(run.mill.units[0], run.mill.radius_m);
  rec.kinds = kind_metrics(run.mill.units, run.mill.kinds, run.mill.radius_m);
  rec.worn_out = true;
  // No charge ran on this liner: the last stage's figures keep the record complete (and its
  // file finite); the figures reported leave them out (study/design_estimates.cpp, and the
  // tradeoff's power series).
  rec.charge = history.stages.empty() ? ChargeFigures{} : history.stages.back().charge;
  history.stages.push_back(rec);
  history.events.push_back("stage " + std::to_string(rec.stage) + ": the lifter is worn to the shell at " +
                           std::to_string(run.hours) + " h");
  if (cb.on_stage) cb.on_stage(history.stages.back());
}

// The real wear rate: given, or calibrated on the new liner's first window.
double wear_rate_for(const Scene& scene, const NewLiner& liner, const StageRun& run, bool resumed) {
  if (scene.wear.rate_source == WearRateSource::Given) return scene.wear.wear_rate_m3_per_J;
  if (run.stage != 0 && !resumed) throw RunError("wear-rate calibration needs stage 0");
  if (run.stage == 0) return real_wear_rate(scene, run.mill, run.window.edge_power_W);
  const std::vector<LinerUnit> kinds(liner.mill.units.begin(), liner.mill.units.begin() + liner.mill.kinds);
  return real_wear_rate(scene, build_mill(liner.mill.radius_m, liner.mill.rows, kinds, liner.mill.kinds),
                        run.window.edge_power_W);
}

// The engine's events since the last look into the history. True once a disk is lost: the
// figures from there on are suspect, so the stage it happened in is kept with the event
// named, and the history stops.
bool note_lost_disks(WearHistory& history, StageRun& run) {
  const auto& events = run.engine->events();
  for (; run.events_noted < events.size(); ++run.events_noted) {
    history.events.push_back("stage " + std::to_string(run.stage) + ": " + events[run.events_noted].what);
    if (history.failure.empty()) history.failure = history.events.back() + " (a disk was lost)";
  }
  return !history.failure.empty();
}

// Whether the stage just measured is the history's last (the scene's last stage, the lifter
// at the shell, or a disk lost in its window); if so it is finished here.
bool last_stage_measured(const Scene& scene, WearHistory& history, StageRun& run, const WearCallbacks& cb) {
  const bool lost = note_lost_disks(history, run);
  const bool worn_out = history.stages.back().worn_out;
  if (run.stage < scene.wear.stages && !worn_out && !lost) return false;
  finish_stage(history, run, cb);
  if (worn_out) history.events.push_back("stage " + std::to_string(run.stage) + ": the lifter is worn to the shell");
  return true;
}

// Wear the measured stage through to the next one's hours, then hand it to the caller: its
// record complete (finish_stage), or, for a resumed stage simulated again only to wear on,
// the errors of that wear. False when the history ends here: stopped by a rule, a disk lost,
// or the lifter worn to the shell (then recorded as the last stage).
bool wear_on(const Scene& scene, const NewLiner& liner, StageRun& run, double c_real, bool on_record,
             WearHistory& history, const WearCallbacks& cb) {
  StageEnd end = StageEnd::Finished;
  try {
    end = wear_through_stage(scene, liner, run, c_real, history, cb);
  } catch (const NumericalError& failure) {
    // The stage was measured on a valid liner: keep it. Whatever the caller's on_stage
    // throws then (a stop request, a full disk), the failure is what the run reports.
    if (on_record) {
      try {
        finish_stage(history, run, cb);
      } catch (...) {
        throw failure;
      }
    }
    throw;
  }
  const bool lost = note_lost_disks(history, run);
  if (end == StageEnd::StoppedByRule && on_record) {
    // Not finished (never handed to on_stage), but the time it simulated up to the stop is
    // the history's to report.
    history.stages.back().simulated_s = run.simulated_s;
    history.stages.back().disk_steps = run.disk_steps;
  }
  if (end == StageEnd::StoppedByRule || (lost && !on_record)) return false;
  if (on_record) {
    finish_stage(history, run, cb);
  } else if (run.worn_through) {
    // The same bits on a resume; under the new conditions of a continued run, the new wear's.
    record_worn_errors(history.stages.back(), run);
    if (cb.on_stage) cb.on_stage(history.stages.back());
  }
  if (lost) return false;
  report_progress(cb, run);
  if (end == StageEnd::WornOut) {
    record_worn_out(history, run, cb);
    return false;
  }
  return true;
}

}  // namespace

MillGeometry starting_mill(const Scene& scene) { return new_liner(scene).mill; }

WearHistory run_wear_history(const Scene& scene, const WearCallbacks& cb,
                             const std::vector<StageRecord>& resume_from) {
  check_smoothing_radius(scene, scene.source_file);
  const NewLiner liner = new_liner(scene);
  const bool resumed = !resume_from.empty();
  WearHistory history;
  history.stages = resume_from;
  MillGeometry mill = resumed ? build_mill(liner.mill.radius_m, liner.mill.rows, resume_from.back().units, liner.mill.kinds)
                              : liner.mill;
  history.start_hours = resumed ? resume_from.front().hours : scene.wear.start_hours;
  history.events = liner.notes;
  // The charge as the last stage's wear ended (a resumed run: the one its stage started from).
  ChargeState carry = resumed ? resume_from.back().start_charge : ChargeState{};
  const int first_stage = resumed ? resume_from.back().stage : 0;
  double c_real = scene.wear.rate_source == WearRateSource::Given ? scene.wear.wear_rate_m3_per_J : 0.0;
  history.wear_rate_m3_per_J = c_real;
  const bool all_done = resumed && (first_stage >= scene.wear.stages || resume_from.back().worn_out);
  for (int k = first_stage; k <= scene.wear.stages && !all_done; ++k) {
    StageRun run = start_stage(scene, k, std::move(mill), std::move(carry), cb);
    if (c_real <= 0.0) c_real = wear_rate_for(scene, liner, run, resumed);
    history.wear_rate_m3_per_J = c_real;
    // A resumed run's first stage is on disk already: it is simulated again only to wear on.
    const bool on_record = !(k == first_stage && resumed);
    if (on_record) history.stages.push_back(stage_record(scene, liner, run, c_real));
    if (on_record && last_stage_measured(scene, history, run, cb)) break;
    if (!wear_on(scene, liner, run, c_real, on_record, history, cb)) break;
    carry = run.engine->state();
    mill = std::move(run.mill);
  }
  // Every measured stage's window, resumed ones too, so that a resumed history says the same.
  for (const StageRecord& rec : history.stages) {
    if (const std::string unsteady = unsteady_window(rec.charge.summary); !unsteady.empty())
      history.events.push_back("stage " + std::to_string(rec.stage) + ": " + unsteady);
    if (const std::string unsound = unsound_energy_split(rec.charge); !unsound.empty())
      history.events.push_back("stage " + std::to_string(rec.stage) + ": " + unsound);
  }
  compute_life(history, scene.wear.replacement_height_m);
  return history;
}

int stages_to_reach(double hours, double stage_hours) {
  return std::max(1, static_cast<int>(std::ceil(hours / stage_hours - 1e-9)));
}

std::vector<LifterMetrics> kind_metrics(const std::vector<LinerUnit>& units, int kinds, double radius_m) {
  // One unit per kind, or one per row (row r of kind r % kinds): the mean over its rows.
  const std::size_t n = static_cast<std::size_t>(std::max(kinds, 1));
  std::vector<LifterMetrics> m(std::min(n, units.size()));
  std::vector<double> count(m.size(), 0.0);
  for (std::size_t u = 0; u < units.size(); ++u) {
    const LifterMetrics one = measure_lifter(units[u], radius_m);
    LifterMetrics& sum = m[u % n];
    sum.area_m2 += one.area_m2;
    sum.height_m += one.height_m;
    sum.leading_face_angle_rad += one.leading_face_angle_rad;
    sum.trailing_face_angle_rad += one.trailing_face_angle_rad;
    count[u % n] += 1.0;
  }
  for (std::size_t k = 0; k < m.size(); ++k) {
    if (count[k] == 1.0) continue;  // a shared unit: its own metrics, exactly
    m[k].area_m2 /= count[k];
    m[k].height_m /= count[k];
    m[k].leading_face_angle_rad /= count[k];
    m[k].trailing_face_angle_rad /= count[k];
  }
  return m;
}

void throw_if_failed(const WearHistory& history) {
  if (!history.failure.empty()) throw RunError(history.failure);
}

}  // namespace millwear
