// `millwear validate SCENE --measured FILE -o OUT [--from RUN]`: measured lifter profiles
// (the paper's Fig. 4), or measured lifter areas alone, against the simulated wear history.
//
// The history is either run here (stage boundaries on the survey hours when they share a
// common step, see study/calibration.hpp) or read from a finished `millwear run`
// folder (--from RUN: its exact stage geometry, OUT/stages/DESIGN_stageK.units.csv, for the
// design named by the scene). The measured file holds profiles (hours,x_mm,y_mm) or areas
// only (hours,area_mm2 or hours,area_loss_mm2; study/area_surveys.hpp). Outputs in OUT:
// profiles:
//   validation.csv               one row per survey: distances (mm, % of the new lifter's
//                                height), bias, areas and area error
//   simulated_surveys.csv        the simulated profiles at the survey hours, in the survey
//                                format (hours,x_mm,y_mm), lifter region only
//   plots/validate_measured.dat, plots/validate_simulated.dat   gnuplot blocks
//   validate_profiles.png/.svg   measured (dashed) against simulated (solid)
// areas only:
//   validation.csv               one row per survey row: measured and simulated area and
//                                area loss, their errors (mm^2, % of the new lifter's area,
//                                % of the measured loss)
//   simulated_areas.csv          the simulated areas at the survey hours (hours,area_mm2)
//   plots/validate_area_measured.csv, plots/validate_area_simulated.csv (every stage)
//   validate_areas.png/.svg      measured points on the simulated area history
// Exit codes: 0 done; 1 the run or a figure failed; 2 bad input.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <map>

#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "io/stage_files.hpp"
#include "app/validation_common.hpp"
#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "study/area_fit.hpp"
#include "study/area_surveys.hpp"
#include "study/profile_fit.hpp"

namespace millwear::app {

namespace {

struct ValidateArgs {
  std::string scene, measured, out, from, fidelity;
};

// The stages of the history to compare with: a finished run (--from) or a fresh one.
std::vector<StageRecord> history_stages(const Scene& scene, const ValidateArgs& a,
                                        const validation::Measurements& measured) {
  const std::vector<double> hours = measured.hours();
  std::vector<StageRecord> stages;
  if (!a.from.empty()) {
    const int k = io::last_finished_stage(a.from, scene.name);
    if (k < 0)
      throw InputError(a.from, "stages/" + scene.name + "_stage0.done",
                       "a finished `millwear run` folder with design '" + scene.name + "' (the scene's name)");
    for (int s = 0; s <= k; ++s) stages.push_back(io::read_stage_state(a.from, scene.name, s));
    const double reached = stages.back().hours;
    const std::vector<std::size_t> lines = measured.lines();
    for (std::size_t i = 0; i < hours.size(); ++i)
      if (hours[i] > reached + 1e-6)
        throw InputError(a.measured, "line " + std::to_string(lines[i]),
                         "a survey within the " + io::format_number(reached) + " h the run in " + a.from +
                             " reached, found " + io::format_number(hours[i]) + " h");
    std::printf("validate %s: %zu %s survey(s) against the run in %s (%d stage(s), %.0f h)\n", scene.name.c_str(),
                measured.count(), measured.areas_only ? "area" : "profile", a.from.c_str(), k, reached);
    return stages;
  }
  const double c = scene.wear.rate_source == WearRateSource::Given ? scene.wear.wear_rate_m3_per_J : 0.0;
  const Scene s = validation::scene_for_survey_hours(scene, hours, c, 1.0);
  std::printf("validate %s: %zu %s survey(s); running %d stage(s) of %g h (fidelity %s)\n", scene.name.c_str(),
              measured.count(), measured.areas_only ? "area" : "profile", s.wear.stages, s.wear.stage_hours,
              s.fidelity.c_str());
  std::fflush(stdout);
  const WearHistory h = run_wear_history(s, progress_callbacks());
  for (const auto& e : h.events) std::printf("  event: %s\n", e.c_str());
  throw_if_failed(h);  // a lost disk or rule 1's stop: no comparison with the surveys
  return h.stages;
}

void check_covers(bool covers, double last_hours, double survey_hours) {
  if (!covers)
    throw RunError("the wear history ends at " + io::format_number(last_hours) +
                   " h (the lifter wore out?), before the survey at " + io::format_number(survey_hours) + " h");
}

// Renders one figure; a missing gnuplot is a warning, a failing one exit code 1.
int render(const std::string& script, const std::map<std::string, std::string>& vars,
           const std::string& out, const std::string& files_note) {
  try {
    const auto files = plots::render_figure(plots::script_path(script), vars, io::join_path(out, "plots/gnuplot.log"));
    std::printf("results in %s (%s); figure %s\n", out.c_str(), files_note.c_str(),
                files.empty() ? "-" : files.front().c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "millwear: warning: figure: %s\n", e.what());
    std::printf("results in %s (%s)\n", out.c_str(), files_note.c_str());
    return plots::gnuplot_available() ? 1 : 0;
  }
}

int validate_profiles(const Scene& scene, const ValidateArgs& a, const std::vector<validation::Survey>& surveys,
                      const std::vector<StageRecord>& stages) {
  const validation::ProfileHistory history = validation::profile_history(stages);
  for (const auto& v : surveys) check_covers(history.covers(v.hours), history.last_hours(), v.hours);
  const double new_height = stages.front().lifter.height_m;
  const Polyline& new_surface = stages.front().units.front().surface;
  const double half_base = stages.front().units.front().lifter_half_base_m;

  io::ensure_dir(a.out);
  io::ensure_dir(io::join_path(a.out, "plots"));
  io::CsvTable table({"survey", "hours", "points", "mean_mm", "max_mm", "bias_mm", "mean_pct_height",
                      "max_pct_height", "measured_area_mm2", "simulated_area_mm2", "area_error_mm2",
                      "area_error_pct"});
  std::vector<validation::Survey> simulated;
  std::string measured_dat, simulated_dat;
  std::printf("%7s %8s %9s %9s %9s %8s %8s %12s %12s %9s\n", "survey", "hours", "mean_mm", "max_mm", "bias_mm",
              "mean_%h", "max_%h", "meas_mm2", "sim_mm2", "err_%");
  for (std::size_t i = 0; i < surveys.size(); ++i) {
    const auto& v = surveys[i];
    const Polyline sim = history.profile_at(v.hours);
    const auto c = validation::compare_profile(v, sim, scene.radius_m(), new_height, new_surface);
    table.add_row({static_cast<int>(i + 1), v.hours, c.points, c.mean_distance_m * 1e3, c.max_distance_m * 1e3,
                   c.bias_m * 1e3, c.mean_pct_height, c.max_pct_height, c.measured_area_m2 * 1e6,
                   c.simulated_area_m2 * 1e6, c.area_error_m2 * 1e6, c.area_error_pct});
    std::printf("%7zu %8.0f %9.3f %9.3f %9.3f %8.2f %8.2f %12.1f %12.1f %9.2f\n", i + 1, v.hours,
                c.mean_distance_m * 1e3, c.max_distance_m * 1e3, c.bias_m * 1e3, c.mean_pct_height,
                c.max_pct_height, c.measured_area_m2 * 1e6, c.simulated_area_m2 * 1e6, c.area_error_pct);
    // The simulated lifter region: the measured span, or the lifter and its feet.
    const double xa = std::min(v.profile_m.front().x, -io::kProfileMargin * half_base);
    const double xb = std::max(v.profile_m.back().x, io::kProfileMargin * half_base);
    validation::Survey s;
    s.hours = v.hours;
    for (const Vec2& p : sim)
      if (p.x >= xa && p.x <= xb) s.profile_m.push_back(p);
    simulated.push_back(s);
    const std::string title = io::format_number(v.hours) + " h";
    measured_dat += profile_block(title, v.profile_m, i == 0);
    simulated_dat += profile_block(title, s.profile_m, i == 0);
  }
  table.write(io::join_path(a.out, "validation.csv"));
  io::write_file_atomic(io::join_path(a.out, "simulated_surveys.csv"),
                        validation::format_surveys(simulated, "simulated by millwear validate: scene " + scene.name +
                                                                  ", at the hours of " + a.measured));
  const std::string mfile = io::join_path(a.out, "plots/validate_measured.dat");
  const std::string sfile = io::join_path(a.out, "plots/validate_simulated.dat");
  io::write_file_atomic(mfile, measured_dat);
  io::write_file_atomic(sfile, simulated_dat);
  std::printf("(distances: measured point to simulated profile; %% of the new lifter height %.1f mm; "
              "bias > 0: simulation wore deeper; area error %% of the new lifter area over the measured span)\n",
              new_height * 1e3);
  return render("validate_profiles",
                {{"measured", mfile}, {"simulated", sfile}, {"outbase", io::join_path(a.out, "validate_profiles")},
                 {"title", "Measured (dashed) and simulated (solid) profiles: " + scene.name}},
                a.out, "validation.csv, simulated_surveys.csv");
}

int validate_areas(const Scene& scene, const ValidateArgs& a, const validation::AreaSurveys& surveys,
                   const std::vector<StageRecord>& stages) {
  const validation::AreaHistory history = validation::area_history(stages);
  for (const auto& v : surveys.surveys) check_covers(history.covers(v.hours), history.last_hours(), v.hours);
  const auto rows = validation::compare_areas(surveys, history);
  const auto ref = validation::measured_areas(surveys, history.new_area_m2());

  io::ensure_dir(a.out);
  io::ensure_dir(io::join_path(a.out, "plots"));
  io::CsvTable table({"survey", "line", "hours", "measured_area_mm2", "simulated_area_mm2", "area_error_mm2",
                      "area_error_pct", "measured_loss_mm2", "simulated_loss_mm2", "loss_error_mm2",
                      "loss_error_pct"});
  io::CsvTable measured_plot({"hours", "area_mm2"}), simulated_plot({"hours", "area_mm2"});
  validation::AreaSurveys simulated;
  std::printf("%7s %6s %8s %12s %12s %10s %8s %11s %11s %8s\n", "survey", "line", "hours", "meas_mm2", "sim_mm2",
              "err_mm2", "err_%", "meas_loss", "sim_loss", "loss_%");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& c = rows[i];
    table.add_row({static_cast<int>(i + 1), c.line, c.hours, c.measured_area_m2 * 1e6, c.simulated_area_m2 * 1e6,
                   c.area_error_m2 * 1e6, c.area_error_pct, c.measured_loss_m2 * 1e6, c.simulated_loss_m2 * 1e6,
                   c.loss_error_m2 * 1e6, c.loss_error_pct});
    std::printf("%7zu %6zu %8.0f %12.1f %12.1f %10.2f %8.2f %11.1f %11.1f %8.2f\n", i + 1, c.line, c.hours,
                c.measured_area_m2 * 1e6, c.simulated_area_m2 * 1e6, c.area_error_m2 * 1e6, c.area_error_pct,
                c.measured_loss_m2 * 1e6, c.simulated_loss_m2 * 1e6, c.loss_error_pct);
    measured_plot.add_row({c.hours, c.measured_area_m2 * 1e6});
    simulated.surveys.push_back({c.hours, c.simulated_area_m2, 0});
  }
  for (std::size_t k = 0; k < history.hours.size(); ++k)
    simulated_plot.add_row({history.hours[k], history.area_m2[k] * 1e6});
  table.write(io::join_path(a.out, "validation.csv"));
  io::write_file_atomic(io::join_path(a.out, "simulated_areas.csv"),
                        validation::format_area_surveys(simulated, "simulated by millwear validate: scene " +
                                                                       scene.name + ", at the hours of " + a.measured));
  const std::string mfile = io::join_path(a.out, "plots/validate_area_measured.csv");
  const std::string sfile = io::join_path(a.out, "plots/validate_area_simulated.csv");
  measured_plot.write(mfile);
  simulated_plot.write(sfile);
  std::printf("(errors: simulated - measured; area %% of the new lifter area %.1f mm^2; loss %% of the measured loss; "
              "losses from %s %.1f mm^2)\n",
              history.new_area_m2() * 1e6,
              ref.reference_measured ? "the file's 0 h area" : "the scene's new lifter area", ref.reference_m2 * 1e6);
  return render("validate_areas",
                {{"measured", mfile}, {"simulated", sfile}, {"outbase", io::join_path(a.out, "validate_areas")},
                 {"title", "Measured (points) and simulated (line) lifter area: " + scene.name}},
                a.out, "validation.csv, simulated_areas.csv");
}

int run_validate(const ValidateArgs& a) {
  Scene scene = load_scene(a.scene);
  if (!a.fidelity.empty()) apply_fidelity(scene, a.fidelity);
  check_run_limits(scene, a.scene);  // before anything is filled or written
  const validation::Measurements measured = validation::read_measurements(a.measured);
  const io::FolderLock lock(a.out);  // one writer per folder, for the whole run
  const std::vector<StageRecord> stages = history_stages(scene, a, measured);
  return measured.areas_only ? validate_areas(scene, a, measured.areas, stages)
                             : validate_profiles(scene, a, measured.profiles, stages);
}

}  // namespace

void register_validate(CLI::App& app, Action* action) {
  auto args = std::make_shared<ValidateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "validate", "Compare measured lifter profiles or areas with the simulated wear history (paper Fig. 4)");
  cmd->add_option("scene", args->scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--measured", args->measured,
                  "measured surveys (CSV): profiles hours,x_mm,y_mm or areas only hours,area_mm2 (see below)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--from", args->from, "reuse a finished `millwear run` folder instead of running")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference");
  cmd->footer(std::string(kMeasuredFileHelp) +
              "\nProfiles: normal distances (mm, % of the lifter height) and area error per survey.\n"
              "Areas only: area and area-loss error per row (simulated - measured).");
  cmd->callback([args, action] { *action = [args] { return run_validate(*args); }; });
}

}  // namespace millwear::app
