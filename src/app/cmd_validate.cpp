// `millwear validate SCENE --measured FILE -o OUT [--from RUN]`: measured lifter profiles
// (the paper's Fig. 4), or measured lifter areas alone, against the simulated wear history,
// run here or read from a finished `millwear run` folder (study/validation_run.hpp: the
// outputs in OUT).
// Exit codes: 0 done; 1 the run or a figure failed; 2 bad input; 130/143 interrupted (Ctrl-C,
// SIGTERM: OUT keeps an earlier validation's results as they were).
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>

#include "app/commands.hpp"
#include "app/fidelity_option.hpp"
#include "app/output_folder.hpp"
#include "app/set_option.hpp"
#include "app/signals.hpp"
#include "app/threads_option.hpp"
#include "app/validation_common.hpp"
#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/csv.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "study/validation_run.hpp"

namespace millwear::app {

namespace {

// Hours (a survey's, a run's) to six digits, as a survey file gives them: a survey within
// the first hour keeps its fraction (0.5 h is not 0 h, the start).
std::string hours_text(double hours) { return io::format_number(hours, 6); }

void print_history(const Scene& scene, const validation::Measurements& m, const validation::HistorySource& src,
                   const std::string& from) {
  const char* kind = m.areas_only ? "area" : "profile";
  if (src.from_run) {
    std::printf("validate %s: %zu %s survey(s) against the run in %s (%d stage(s), %s h)\n", scene.name.c_str(),
                m.count(), kind, from.c_str(), src.last_stage, hours_text(src.reached_hours).c_str());
    if (src.histories > 1)
      std::printf("  the run holds %d histories of %s (--replicates); compared: the first, seed %llu, not their "
                  "mean in its summary.csv\n",
                  src.histories, scene.name.c_str(), static_cast<unsigned long long>(scene.solver.seed));
  }
  else
    std::printf("validate %s: %zu %s survey(s); running %d stage(s) of %g h (fidelity %s)\n", scene.name.c_str(),
                m.count(), kind, src.scene.wear.stages, src.scene.wear.stage_hours, src.scene.fidelity.c_str());
  std::fflush(stdout);
}

void print_profiles(const validation::ValidateOutcome& o) {
  std::printf("%7s %8s %9s %9s %9s %8s %8s %12s %12s %9s\n", "survey", "hours", "mean_mm", "max_mm", "bias_mm",
              "mean_%h", "max_%h", "meas_mm2", "sim_mm2", "err_%");
  for (std::size_t i = 0; i < o.profiles.size(); ++i) {
    const auto& c = o.profiles[i];
    std::printf("%7zu %8s %9.3f %9.3f %9.3f %8.2f %8.2f %12.1f %12.1f %9.2f\n", i + 1, hours_text(c.hours).c_str(),
                in_mm(c.mean_distance_m), in_mm(c.max_distance_m), in_mm(c.bias_m), c.mean_pct_height,
                c.max_pct_height, in_mm2(c.measured_area_m2), in_mm2(c.simulated_area_m2), c.area_error_pct);
  }
  std::printf("(distances: measured point to simulated profile; %% of the new lifter height %.1f mm; "
              "bias > 0: simulation wore deeper; area error %% of the new lifter area over the measured span)\n",
              in_mm(o.new_height_m));
}

void print_areas(const validation::ValidateOutcome& o) {
  std::printf("%7s %6s %8s %12s %12s %10s %8s %11s %11s %8s\n", "survey", "line", "hours", "meas_mm2", "sim_mm2",
              "err_mm2", "err_%", "meas_loss", "sim_loss", "loss_%");
  for (std::size_t i = 0; i < o.areas.size(); ++i) {
    const auto& c = o.areas[i];
    char loss_pct[32] = "-";  // no measured loss (the survey at the start): no percentage of it
    if (!std::isnan(c.loss_error_pct)) std::snprintf(loss_pct, sizeof loss_pct, "%.2f", c.loss_error_pct);
    std::printf("%7zu %6zu %8s %12.1f %12.1f %10.2f %8.2f %11.1f %11.1f %8s\n", i + 1, c.line, hours_text(c.hours).c_str(),
                in_mm2(c.measured_area_m2), in_mm2(c.simulated_area_m2), in_mm2(c.area_error_m2), c.area_error_pct,
                in_mm2(c.measured_loss_m2), in_mm2(c.simulated_loss_m2), loss_pct);
  }
  std::printf("(errors: simulated - measured; area %% of the lifter's area at the history's start, %.1f mm^2; "
              "loss %% of the measured loss; losses from %s %.1f mm^2)\n",
              in_mm2(o.new_area_m2),
              o.measured_areas.reference_measured ? "the file's area at the start" : "the scene's lifter area at the start",
              in_mm2(o.measured_areas.reference_m2));
}

int run_validate(const validation::ValidateRequest& a) {
  refuse_sets_options_give(a.overrides, {{"fidelity", "--fidelity", !a.fidelity.empty()}});
  validation::ValidateCallbacks cb;
  cb.on_history = [&a](const Scene& s, const validation::Measurements& m, const validation::HistorySource& src) {
    print_history(s, m, src, a.from);
  };
  cb.wear = progress_callbacks();
  cb.on_event = [](const std::string& e) { std::printf("  event: %s\n", e.c_str()); };
  // Ctrl-C or SIGTERM stops the history between pieces of its steps; the new results are
  // drawn up aside and replace the earlier ones only once complete, so a stop leaves OUT as
  // it was.
  const SignalScope signals;
  cb.wear.should_stop = [] { return g_signal.load() != 0; };
  validation::ValidateOutcome o;
  try {
    o = validation::validate_scene(a, cb);
  } catch (const RunError&) {
    const int sig = g_signal.load();
    if (sig == 0) throw;
    std::fprintf(stderr, "millwear validate: interrupted by %s; nothing of this validation is written: %s is as "
                 "it was before (an earlier validation's results in it stay): run it again\n",
                 sig == SIGTERM ? "SIGTERM" : "SIGINT", a.out.c_str());
    return 128 + sig;
  }
  if (o.areas_only) print_areas(o);
  else print_profiles(o);
  if (o.figure_error.empty()) {
    std::printf("results in %s (%s); figure %s\n", a.out.c_str(), o.files_note.c_str(),
                o.figure_files.empty() ? "-" : o.figure_files.front().c_str());
    return 0;
  }
  std::fprintf(stderr, "millwear: warning: figure: %s\n", o.figure_error.c_str());
  std::printf("results in %s (%s)\n", a.out.c_str(), o.files_note.c_str());
  return o.figure_failed ? 1 : 0;
}

}  // namespace

void register_validate(CLI::App& app, Action* action) {
  auto args = std::make_shared<validation::ValidateRequest>();
  args->threads = 0;  // not given: one per kDisksPerStepThread disks, up to every core
  CLI::App* cmd = app.add_subcommand(
      "validate", "Compare measured lifter profiles or areas with the simulated wear history (paper Fig. 4)");
  cmd->add_option("scene", args->scene_file, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--measured", args->measured_file,
                  "measured surveys (CSV): profiles hours,x_mm,y_mm or areas only hours,area_mm2 (see below)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--from", args->from, "reuse a finished `millwear run` folder instead of running")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference")->check(fidelity_name());
  add_threads_option(cmd, args->threads);
  add_set_option(cmd, &args->overrides);
  cmd->footer(std::string(kMeasuredFileHelp) +
              "\nProfiles: normal distances (mm, % of the lifter height) and area error per survey.\n"
              "Areas only: area and area-loss error per row (simulated - measured).");
  cmd->callback([args, action] {
    *action = [args] {
      validation::ValidateRequest request = *args;
      request.threads_fit_size = request.threads == 0;
      request.threads = step_threads(request.threads);
      request.commit = MILLWEAR_COMMIT;
      return run_validate(request);
    };
  });
}

}  // namespace millwear::app
