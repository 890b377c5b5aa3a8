// `millwear calibrate SCENE --measured FILE [-o OUT]`: the real wear rate C that makes the
// simulated wear history fit measured lifter profiles or, when the file holds areas only,
// measured lifter areas, with its uncertainty, and a copy of the scene with
// `wear.wear_rate` filled in (study/calibration_run.hpp: the outputs; study/calibration.hpp:
// the method).
// Exit codes: 0 converged; 1 a run failed or no convergence within --max-runs (the best
// estimate is still written); 2 bad input; 130/143 interrupted (Ctrl-C, SIGTERM: nothing is
// written, an earlier calibration's files stay as they were).
#include <CLI/CLI.hpp>

#include <cstdio>

#include "app/commands.hpp"
#include "app/default_text.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/set_option.hpp"
#include "app/signals.hpp"
#include "app/threads_option.hpp"
#include "app/validation_common.hpp"
#include "study/calibration_run.hpp"
#include "study/plan.hpp"

namespace millwear::app {

namespace {

struct CalibrateArgs {
  validation::CalibrateRequest request;
  double tolerance_pct = 100.0 * validation::CalibrationOptions{}.rel_tol;
  int threads = 0;
  bool min_runs_given = false;
};

int run_calibrate(CalibrateArgs a) {
  refuse_sets_options_give(a.request.overrides, {{"fidelity", "--fidelity", !a.request.fidelity.empty()}});
  // Both given and contradicting: refused. The default minimum yields to --max-runs 1.
  if (a.min_runs_given && a.request.options.min_runs > a.request.options.max_runs)
    throw InputError("", "--min-runs", "at most --max-runs (" + std::to_string(a.request.options.max_runs) +
                                           "), got " + std::to_string(a.request.options.min_runs));
  a.request.options.rel_tol = a.tolerance_pct / 100.0;
  a.request.threads = step_threads(a.threads);
  a.request.threads_fit_size = a.threads == 0;
  validation::CalibrateCallbacks cb;
  bool areas = false;
  cb.on_start = [&](const Scene& scene, const validation::Measurements& m, const validation::CalibrationOptions& o) {
    areas = m.areas_only;
    std::printf("calibrate %s against %zu %s in %s (least squares on %s; fidelity %s, up to %d wear histories)\n",
                scene.name.c_str(), m.count(), areas ? "lifter area(s)" : "profile survey(s)",
                a.request.measured_file.c_str(), areas ? "the area loss" : "the normal distances",
                scene.fidelity.c_str(), o.max_runs);
    std::fflush(stdout);
  };
  cb.on_run = [&areas](const validation::CalibrationRun& r) {
    if (r.replicate > 1) std::printf("replicate %d (seed %llu): ", r.replicate, static_cast<unsigned long long>(r.seed));
    std::printf("run %d: C = %.4g m^3/J to %.0f h: best fit C = %.4g (x %.4f), rms %.3f %s over %d %s%s (%.1f s)\n",
                r.run, r.c_m3_per_J, r.reached_hours, r.c_estimate, r.fit.scale, r.fit.rms * (areas ? 1e6 : 1e3),
                areas ? "mm^2" : "mm", r.fit.points, areas ? "worn area(s)" : "points",
                r.fit.at_bound ? ", at an end of the search (the history's end, or next to no wear)" : "", r.wall_s);
    for (const auto& e : r.events) std::printf("  event: %s\n", e.c_str());
    std::fflush(stdout);
  };
  cb.wear = progress_callbacks();
  // Ctrl-C or SIGTERM stops the history that runs between pieces of its steps; the copy and
  // the tables are written only after the last history, so a stop writes nothing.
  const SignalScope signals;
  cb.wear.should_stop = [] { return g_signal.load() != 0; };
  validation::CalibrateOutcome o;
  try {
    o = validation::calibrate_scene(a.request, cb);
  } catch (const RunError&) {
    const int sig = g_signal.load();
    if (sig == 0) throw;
    const std::string where = a.request.out.empty() ? "the calibrated copy beside the scene is" : a.request.out + " is";
    std::fprintf(stderr, "millwear calibrate: interrupted by %s; nothing of this calibration is written (%s as it "
                 "was): run it again\n", sig == SIGTERM ? "SIGTERM" : "SIGINT", where.c_str());
    return 128 + sig;
  }

  const validation::CalibrationResult& res = o.result;
  char fit_sigma[32] = "unknown";
  if (res.fit_error_known) std::snprintf(fit_sigma, sizeof fit_sigma, "%.2g", res.sigma_fit_m3_per_J);
  std::printf("C = %.4g +- %.2g m^3/J (expanded uncertainty, k = 2, about 95%%; standard %.2g: fit %s, "
              "simulation statistics %.2g)%s\n",
              res.c_m3_per_J, res.expanded_m3_per_J, res.sigma_m3_per_J, fit_sigma, res.sigma_model_m3_per_J,
              res.converged ? "" : "  NOT CONVERGED");
  if (res.histories_averaged > 1)
    std::printf("  the mean of %d histories' estimates (after the first, and none at an end of the search); their "
                "spread sets the simulation statistics when it is the larger\n", res.histories_averaged);
  if (!res.fit_error_known)
    std::printf("  one worn area survey: the fit's own error is unknown, U counts the simulation statistics only "
                "(two or more areas after the history's start give it)\n");
  for (std::size_t j = 0; j < res.survey_c.size(); ++j)
    std::printf("  survey at %.0f h alone: C = %.4g m^3/J\n", res.survey_hours[j], res.survey_c[j]);
  std::printf("calibrated scene: %s\n", o.scene_out.c_str());
  if (!res.converged) {
    std::fprintf(stderr, "millwear: calibration did not converge within %d runs (last factor %.4f)\n",
                 o.options.max_runs, res.runs.back().fit.scale);
    return 1;
  }
  return 0;
}

}  // namespace

void register_calibrate(CLI::App& app, Action* action) {
  auto args = std::make_shared<CalibrateArgs>();
  validation::CalibrateRequest& r = args->request;
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Fit the real wear rate C to measured lifter profiles or areas; writes a calibrated scene copy");
  cmd->add_option("scene", r.scene_file, "scene file (TOML); its wear rate is the first guess")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("--measured", r.measured_file,
                  "measured surveys (CSV): profiles hours,x_mm,y_mm or areas only hours,area_mm2 (see below)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", r.out, "output folder (default: the calibrated scene goes next to SCENE)")
      ->check(output_folder());
  cmd->add_option("--fidelity", r.fidelity, "draft | standard | reference")->check(fidelity_name());
  add_threads_option(cmd, args->threads);
  add_set_option(cmd, &r.overrides);
  cmd->add_option("--max-runs", r.options.max_runs, "wear histories at most (" + default_text(r.options.max_runs) + ")")->check(whole_in(1, 1000));
  CLI::Option* min_runs = cmd->add_option("--min-runs", r.options.min_runs,
                  "wear histories at least (" + default_text(r.options.min_runs) +
                      "); every history after the first is an estimate, and C is their mean")
      ->check(whole_in(1, 1000));
  cmd->add_option("--replicates", r.options.replicates,
                  "histories at the calibrated C with seeds s .. s+N-1 (" + default_text(r.options.replicates) +
                      "): their estimates join the mean and their spread measures the charge's noise")
      ->check(whole_in(1, study::kMaxReplicates));
  cmd->add_option("--tolerance", args->tolerance_pct, "stop when the run's C fits within this % (" + default_text(args->tolerance_pct) + ")")
      ->check(finite_in(1e-6, 100.0));
  cmd->footer(std::string(kMeasuredFileHelp) +
              "\nProfiles: least squares on the normal distances of every measured point. Areas only: least\n"
              "squares on the area loss of every row after the history's start (0 h, or lifters.start_hours;\n"
              "two or more such rows give the fit's own error). C is printed with U = 2 sigma (about 95%).");
  cmd->callback([args, action, min_runs] {
    args->min_runs_given = min_runs->count() > 0;
    *action = [args] { return run_calibrate(*args); };
  });
}

}  // namespace millwear::app
