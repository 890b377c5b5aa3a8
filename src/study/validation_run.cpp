// `millwear validate` as one call (see validation_run.hpp).
#include "study/validation_run.hpp"

#include <cmath>

#include <algorithm>
#include <map>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "study/calibration.hpp"
#include "study/command_manifest.hpp"
#include "study/plan.hpp"
#include "study/run_outputs.hpp"
#include "study/stage_files.hpp"
#include "wear/reshape.hpp"

namespace millwear::validation {

namespace {

// Checks a --from folder against the surveys; plans a fresh history otherwise.
HistorySource history_source(const Scene& scene, const ValidateRequest& a, const Measurements& measured) {
  HistorySource src;
  const std::vector<double> hours = measured.hours();
  if (!a.from.empty()) {
    src.from_run = true;
    src.last_stage = io::last_finished_stage(a.from, scene.name);
    if (src.last_stage < 0)
      throw InputError(a.from, "stages/" + scene.name + "_stage0.done",
                       "a finished `millwear run` folder with design '" + scene.name + "' (the scene's name)");
    // The run's figures stand for the scene only if the run was of the scene as given now
    // (its --set and --fidelity included).
    study::check_run_of_scene(a.from, scene, "--from");
    // A run of --replicates N holds N histories of the design; the first, on the scene's own
    // seed, is the one compared, and the outcome says so.
    while (io::last_finished_stage(a.from, scene.name + ".r" + std::to_string(src.histories + 1)) >= 0)
      ++src.histories;
    return src;
  }
  check_surveys_from_start(measured, scene.wear.start_hours, "the scene's lifters.start_hours", a.measured_file);
  check_surveys_within_stages(measured, scene, 1.0, a.measured_file);
  const double c = scene.wear.rate_source == WearRateSource::Given ? scene.wear.wear_rate_m3_per_J : 0.0;
  src.scene = scene_for_survey_hours(scene, hours, c, 1.0);
  return src;
}

// The stages of a finished run (--from), read and checked against the scene and the surveys
// before anything is written.
std::vector<StageRecord> stages_from_run(const Scene& scene, const ValidateRequest& a, const Measurements& measured,
                                         HistorySource& src) {
  std::vector<StageRecord> stages;
  for (int s = 0; s <= src.last_stage; ++s) {
    stages.push_back(study::read_stage_state(a.from, scene.name, s));
    study::check_stage_of_scene(stages.back(), scene, a.from, "--from");
  }
  src.reached_hours = stages.back().hours;
  check_surveys_from_start(measured, stages.front().hours, "the run's first stage in " + a.from, a.measured_file);
  const std::vector<double> hours = measured.hours();
  const std::vector<std::size_t> lines = measured.lines();
  for (std::size_t i = 0; i < hours.size(); ++i)
    if (hours[i] > src.reached_hours + kSameHoursTolerance)
      throw InputError(a.measured_file, "line " + std::to_string(lines[i]),
                       "a survey within the " + io::format_number(src.reached_hours) + " h the run in " + a.from +
                           " reached, found " + io::format_number(hours[i]) + " h");
  return stages;
}

// A fresh history of the scene to the surveys' hours.
std::vector<StageRecord> fresh_history(const HistorySource& src, const ValidateCallbacks& cb) {
  const WearHistory h = run_wear_history(src.scene, cb.wear);
  if (cb.on_event)
    for (const auto& e : h.events) cb.on_event(e);
  throw_if_failed(h);  // a lost disk or rule 1's stop: no comparison with the surveys
  return h.stages;
}

// The files a validation writes into OUT, relative to it.
std::vector<std::string> output_names(bool areas_only) {
  const std::string figure = areas_only ? "validate_areas" : "validate_profiles";
  std::vector<std::string> names = {"manifest.json", "validation.csv", "plots/gnuplot.log", figure + ".png",
                                    figure + ".svg"};
  if (areas_only)
    names.insert(names.end(), {"simulated_areas.csv", "plots/validate_area_measured.csv",
                               "plots/validate_area_simulated.csv"});
  else
    names.insert(names.end(), {"simulated_surveys.csv", "plots/validate_measured.dat", "plots/validate_simulated.dat"});
  return names;
}

bool stop_requested(const ValidateCallbacks& cb) { return cb.wear.should_stop && cb.wear.should_stop(); }

void check_covers(bool covers, double last_hours, double survey_hours) {
  if (!covers)
    throw RunError("the wear history ends at " + io::format_number(last_hours) +
                   " h (the lifter wore out?), before the survey at " + io::format_number(survey_hours) + " h");
}

// Renders one figure; a missing gnuplot is only noted, a failing one marks the outcome.
void render(const std::string& script, const std::map<std::string, std::string>& vars, const std::string& out,
            ValidateOutcome& o) {
  try {
    o.figure_files = plots::render_figure(plots::script_path(script), vars, io::join_path(out, "plots/gnuplot.log"));
  } catch (const std::exception& e) {
    o.figure_error = e.what();
    o.figure_failed = plots::gnuplot_available();
  }
}

// The tables, the figure's data and the figure into `dir` (the staging folder of OUT).
void validate_profiles(const Scene& scene, const ValidateRequest& a, const std::vector<Survey>& surveys,
                       const std::vector<StageRecord>& stages, const std::string& dir, ValidateOutcome& o) {
  const ProfileHistory history = profile_history(stages);
  for (const auto& v : surveys) check_covers(history.covers(v.hours), history.last_hours(), v.hours);
  o.new_height_m = stages.front().lifter.height_m;
  const Polyline& new_surface = stages.front().units.front().surface;
  const double half_base = stages.front().units.front().lifter_half_base_m;

  io::ensure_dir(io::join_path(dir, "plots"));
  io::CsvTable table({"survey", "hours", "points", "mean_mm", "max_mm", "bias_mm", "mean_pct_height",
                      "max_pct_height", "measured_area_mm2", "simulated_area_mm2", "area_error_mm2",
                      "area_error_pct"});
  std::vector<Survey> simulated;
  std::string measured_dat, simulated_dat;
  for (std::size_t i = 0; i < surveys.size(); ++i) {
    const auto& v = surveys[i];
    const Polyline sim = history.profile_at(v.hours);
    const auto c = compare_profile(v, sim, scene.radius_m(), o.new_height_m, new_surface);
    table.add_row({static_cast<int>(i + 1), v.hours, c.points, in_mm(c.mean_distance_m), in_mm(c.max_distance_m),
                   in_mm(c.bias_m), c.mean_pct_height, c.max_pct_height, in_mm2(c.measured_area_m2),
                   in_mm2(c.simulated_area_m2), in_mm2(c.area_error_m2), c.area_error_pct});
    o.profiles.push_back(c);
    // The simulated lifter region: the measured span, or the lifter and its feet.
    const double xa = std::min(v.profile_m.front().x, -study::kProfileMargin * half_base);
    const double xb = std::max(v.profile_m.back().x, study::kProfileMargin * half_base);
    Survey s;
    s.hours = v.hours;
    for (const Vec2& p : sim)
      if (p.x >= xa && p.x <= xb) s.profile_m.push_back(p);
    simulated.push_back(s);
    const std::string title = io::format_number(v.hours) + " h";
    measured_dat += profile_block(title, v.profile_m, i == 0);
    simulated_dat += profile_block(title, s.profile_m, i == 0);
  }
  table.write(io::join_path(dir, "validation.csv"));
  io::write_file_atomic(io::join_path(dir, "simulated_surveys.csv"),
                        format_surveys(simulated, "simulated by millwear validate: scene " + scene.name +
                                                      ", at the hours of " + a.measured_file));
  const std::string mfile = io::join_path(dir, "plots/validate_measured.dat");
  const std::string sfile = io::join_path(dir, "plots/validate_simulated.dat");
  io::write_file_atomic(mfile, measured_dat);
  io::write_file_atomic(sfile, simulated_dat);
  o.files = {"validation.csv", "simulated_surveys.csv", mfile, sfile};
  o.files_note = "manifest.json, validation.csv, simulated_surveys.csv";
  render("validate_profiles",
         {{"measured", mfile}, {"simulated", sfile}, {"outbase", io::join_path(dir, "validate_profiles")},
          {"title", "Measured (dashed) and simulated (solid) profiles: " + scene.name}},
         dir, o);
}

void validate_areas(const Scene& scene, const ValidateRequest& a, const AreaSurveys& surveys,
                    const std::vector<StageRecord>& stages, const std::string& dir, ValidateOutcome& o) {
  const AreaHistory history = area_history(stages);
  for (const auto& v : surveys.surveys) check_covers(history.covers(v.hours), history.last_hours(), v.hours);
  o.areas = compare_areas(surveys, history);
  o.new_area_m2 = history.new_area_m2();
  o.measured_areas = measured_areas(surveys, history.new_area_m2(), history.start_hours());

  io::ensure_dir(io::join_path(dir, "plots"));
  io::CsvTable table({"survey", "line", "hours", "measured_area_mm2", "simulated_area_mm2", "area_error_mm2",
                      "area_error_pct", "measured_loss_mm2", "simulated_loss_mm2", "loss_error_mm2",
                      "loss_error_pct"});
  io::CsvTable measured_plot({"hours", "area_mm2"}), simulated_plot({"hours", "area_mm2"});
  AreaSurveys simulated;
  for (std::size_t i = 0; i < o.areas.size(); ++i) {
    const auto& c = o.areas[i];
    // No measured loss (the survey at the start): no percentage of it, an empty cell rather than NaN.
    const io::CsvCell loss_pct = std::isnan(c.loss_error_pct) ? io::CsvCell("") : io::CsvCell(c.loss_error_pct);
    table.add_row({static_cast<int>(i + 1), c.line, c.hours, in_mm2(c.measured_area_m2), in_mm2(c.simulated_area_m2),
                   in_mm2(c.area_error_m2), c.area_error_pct, in_mm2(c.measured_loss_m2), in_mm2(c.simulated_loss_m2),
                   in_mm2(c.loss_error_m2), loss_pct});
    measured_plot.add_row({c.hours, in_mm2(c.measured_area_m2)});
    simulated.surveys.push_back({c.hours, c.simulated_area_m2, 0});
  }
  for (std::size_t k = 0; k < history.hours.size(); ++k)
    simulated_plot.add_row({history.hours[k], history.area_m2[k] * 1e6});
  table.write(io::join_path(dir, "validation.csv"));
  io::write_file_atomic(io::join_path(dir, "simulated_areas.csv"),
                        format_area_surveys(simulated, "simulated by millwear validate: scene " + scene.name +
                                                           ", at the hours of " + a.measured_file));
  const std::string mfile = io::join_path(dir, "plots/validate_area_measured.csv");
  const std::string sfile = io::join_path(dir, "plots/validate_area_simulated.csv");
  measured_plot.write(mfile);
  simulated_plot.write(sfile);
  o.files = {"validation.csv", "simulated_areas.csv", mfile, sfile};
  o.files_note = "manifest.json, validation.csv, simulated_areas.csv";
  render("validate_areas",
         {{"measured", mfile}, {"simulated", sfile}, {"outbase", io::join_path(dir, "validate_areas")},
          {"title", "Measured (points) and simulated (line) lifter area: " + scene.name}},
         dir, o);
}

}  // namespace

std::string profile_block(const std::string& title, const Polyline& line_m, bool first) {
  std::string s = first ? "" : "\n\n";
  s += title + ",-\n";
  for (const Vec2& p : line_m) s += io::format_number(p.x * 1e3) + "," + io::format_number(p.y * 1e3) + "\n";
  return s;
}

ValidateOutcome validate_scene(const ValidateRequest& a, const ValidateCallbacks& cb) {
  Scene scene = study::load_checked_scene(a.scene_file, a.overrides, a.fidelity, [&a](Scene& s) {
    s.solver.threads = a.threads;
    s.solver.threads_fit_size = a.threads_fit_size;
  });
  const Measurements measured = read_measurements(a.measured_file);
  check_surveys_in_mill(measured, scene, a.measured_file);
  // Every check before the folder is touched: the history to compare with (a --from run read
  // and checked against the scene and the surveys' hours, or the surveys from the start of a
  // fresh one), then the surveys against the lifter.
  HistorySource src = history_source(scene, a, measured);
  std::vector<StageRecord> stages;
  if (src.from_run) stages = stages_from_run(scene, a, measured, src);
  // As calibrate: the surveys lose metal with the hours (profiles: none after the start has more
  // than the lifter at the start; areas: none more than at the start, none lost more than the
  // whole lifter, and the losses grow with time).
  if (!measured.areas_only) {
    check_surveys_over_lifter(measured.profiles, new_liner_unit(scene), scene.radius_m(), a.measured_file);
    check_surveys_lose_metal(measured.profiles, new_liner_unit(scene), scene.radius_m(), scene.wear.start_hours,
                             a.measured_file, scene.mill.one_lifter_shape());
  } else
    check_areas_shrink(measured.areas, measure_lifter(new_liner_unit(scene), scene.radius_m()).area_m2,
                       scene.wear.start_hours, a.measured_file, scene.mill.one_lifter_shape());
  const io::FolderLock lock(a.out, "validate");  // one writer per folder, for the whole run
  io::check_output_names(a.out, output_names(measured.areas_only), "validate");
  // The new results are drawn up beside an earlier validation's, which stay in OUT as they
  // were until every new file is complete (a history that fails or is stopped leaves them).
  io::StagedOutputs staged(a.out);
  if (cb.on_history) cb.on_history(scene, measured, src);
  if (!src.from_run) stages = fresh_history(src, cb);
  ValidateOutcome o;
  o.areas_only = measured.areas_only;
  if (o.areas_only) validate_areas(scene, a, measured.areas, stages, staged.dir(), o);
  else validate_profiles(scene, a, measured.profiles, stages, staged.dir(), o);
  study::CommandRecord record{"validate", a.commit, a.scene_file, a.overrides, scene.fidelity, scene.solver.seed,
                              {{"measured", a.measured_file}, {"from", a.from}}, o.files};
  if (src.histories > 1)
    record.settings.push_back({"from_history", "1 of " + std::to_string(src.histories) + " (seed " +
                                                   std::to_string(scene.solver.seed) + ")"});
  record.files.insert(record.files.end(), o.figure_files.begin(), o.figure_files.end());
  record.files.push_back(io::join_path(staged.dir(), "plots/gnuplot.log"));
  study::write_command_manifest(staged.dir(), record);
  // A stop heard while the figure was drawn (Ctrl-C reaches gnuplot too) leaves the earlier
  // results; once the move into OUT begins, the validation finishes.
  if (stop_requested(cb)) throw RunError("interrupted");
  staged.commit({a.measured_file, a.scene_file});
  for (std::string& f : o.files) f = staged.in_out(f);
  for (std::string& f : o.figure_files) f = staged.in_out(f);
  o.figure_error = staged.in_out_text(o.figure_error);
  return o;
}

}  // namespace millwear::validation
