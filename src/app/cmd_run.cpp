// `millwear run SCENE... -o OUT`: the wear history of every design, compared. A SCENE is a
// scene file or a comparison file (study/plan.hpp); every one is validated before anything
// is written (exit 2). The designs run in the library (study/run_designs.hpp); this file
// owns the terminal: live progress on a terminal, a summary at the end.
//
// Exit codes: 0 every design finished; 1 a design failed (the others still finish) or a
// figure failed; 2 bad input; 130 (143 for SIGTERM) interrupted: finished stages are on
// disk and `--resume` continues.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>

#include "app/commands.hpp"
#include "app/default_text.hpp"
#include "app/duration_text.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/plain_progress.hpp"
#include "app/run_command.hpp"
#include "app/run_view.hpp"
#include "app/set_option.hpp"
#include "app/signals.hpp"
#include "app/threads_option.hpp"
#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/run_folder.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "scene/filling.hpp"
#include "scene/limits.hpp"
#include "study/plan.hpp"
#include "study/run_progress.hpp"

namespace millwear::app {

namespace {

// "continued from RUN stage N (H h); changed:" and the settings changed, one a line.
void print_continuation(const char* verb, const std::string& from, const std::vector<std::string>& changes) {
  std::printf("%-*s %s %s; changed: %s\n", 16, "", verb, from.c_str(), changes.empty() ? "nothing" : "");
  for (const auto& c : changes) std::printf("%-*s   %s\n", 16, "", c.c_str());
}

// "mean +- se": the error to two significant digits and the mean to the same decimal place;
// the mean alone (in `format`) where the error is not known; "-" where nothing was measured.
std::string pm(double mean, double se, const char* format = "%.4g") {
  char m[48], e[48];
  if (std::isnan(mean)) return "-";
  if (!std::isfinite(se) || !std::isfinite(mean)) {
    std::snprintf(m, sizeof m, format, mean);
    return m;
  }
  const int decimals = se > 0.0 ? std::max(0, 1 - static_cast<int>(std::floor(std::log10(se)))) : 1;
  std::snprintf(m, sizeof m, "%.*f", std::min(decimals, 12), mean);
  std::snprintf(e, sizeof e, "%.*f", std::min(decimals, 12), se);
  return std::string(m) + " +- " + e;
}

// A life read off the height trend beyond the last stage (marked *); none is marked where
// the trend gives no life.
bool extrapolated(const DesignEstimate& d) { return d.life_extrapolated && std::isfinite(d.life_h.mean); }

void print_final_summary(const study::RunState& state, double wall) {
  const study::RunEstimates est = study::run_estimates(state);
  std::printf("%-*s %5s %7s %18s %13s %15s %18s %16s %17s\n", 16, "design", "stage", "hours", "area_mm2", "loss_%",
              "height_mm", "power_kW", "util", "life_h");
  for (const DesignEstimate& d : est.designs)
    for (const StageEstimate& s : d.stages)
      std::printf("%-*s %5d %7.0f %18s %13s %15s %18s %16s %17s%s\n", 16, d.name.c_str(), s.stage, s.hours,
                  pm(in_mm2(s.area_m2.mean), in_mm2(s.area_m2.se), "%.1f").c_str(),
                  pm(100.0 * s.area_loss_fraction.mean, 100.0 * s.area_loss_fraction.se, "%.1f").c_str(),
                  pm(in_mm(s.height_m.mean), in_mm(s.height_m.se), "%.1f").c_str(),
                  pm(in_kW(s.power_W.mean), in_kW(s.power_W.se)).c_str(),
                  pm(s.utilization.mean, s.utilization.se, "%.3f").c_str(),
                  pm(d.life_h.mean, d.life_h.se, "%.0f").c_str(), extrapolated(d) ? "*" : " ");
  for (const study::DesignLines& d : study::design_lines(state)) {
    std::printf("%-*s %s%s%s\n", 16, d.name.c_str(), study::status_name(d.status),
                d.error.empty() ? "" : ": ", d.error.c_str());
    for (const auto& e : d.events) std::printf("%-*s event: %s\n", 16, "", e.c_str());
    if (d.status == study::DesignStatus::Done && d.stages.size() >= 2 && !std::isfinite(d.life_h))
      std::printf("%-*s no life: the lifter's height does not fall over the last stages, so none is extrapolated "
                  "(is there shear work on the liner?)\n", 16, "");
    if (!d.continued_from.empty()) print_continuation("continued from", d.continued_from, d.changes);
    if (d.life_from_hours != 0.0 && std::isfinite(d.life_h))
      std::printf("%-*s life %.0f h, %.0f h from %.6g h\n", 16, "", d.life_h, d.life_h - d.life_from_hours,
                  d.life_from_hours);
    // A pattern: each kind of lifter on its own.
    for (std::size_t k = 0; k < d.kind_names.size(); ++k) {
      std::printf("%-*s kind %zu (%s): area_mm2", 16, "", k, d.kind_names[k].c_str());
      for (const study::StageLine& l : d.stages)
        if (k < l.kind_area_m2.size()) std::printf(" %.1f", in_mm2(l.kind_area_m2[k]));
      std::printf("; loss mm2/1000h");
      for (const study::StageLine& l : d.stages)
        if (k < l.kind_area_loss_rate_m2_per_s.size())
          std::printf(" %.1f", in_mm2(l.kind_area_loss_rate_m2_per_s[k]) * kSecondsPerHour * 1000.0);
      const double life = k < d.kind_life_h.size() ? d.kind_life_h[k] : std::nan("");
      std::printf("; life %.0f h%s\n", life, k < d.kind_life_extrapolated.size() && d.kind_life_extrapolated[k] ? "*" : "");
    }
  }
  if (!est.designs.empty())
    std::printf("errors: %s\n", est.designs.front().source == ErrorSource::Replicates
                                    ? ("standard errors of the mean of " + std::to_string(state.plan.replicates) +
                                       " replicates per design").c_str()
                                    : "batch means of each window (one history per design; "
                                      "--replicates N measures the spread between histories)");
  for (const Verdict& v : est.verdicts) std::printf("%s\n", v.text.c_str());
  const bool any_extrapolated =
      std::any_of(est.designs.begin(), est.designs.end(), [](const DesignEstimate& d) { return extrapolated(d); });
  std::printf("(%snormalised to %s new; wall time %s)\n",
              any_extrapolated ? "* life extrapolated from the stage trend; " : "", state.plan.reference.c_str(),
              duration_text(wall).c_str());
}

// `--stop-after-stage K` stops after a stage some design runs and does not end on: stage 0
// to its last but one, or from the stage after the one `--continue` copies. Another K would
// stop nothing, or only after a copied stage; refused before anything runs (exit 2).
void check_stop_stage(const study::Plan& plan, int k) {
  if (k < 0) return;
  int lo = -1, hi = -1;
  for (const auto& d : plan.designs) {
    const int first = d.continue_run.empty() ? 0 : d.continue_stage + 1;
    const int last_but_one = d.scene.wear.stages - 1;
    if (first > last_but_one) continue;
    if (k >= first && k <= last_but_one) return;
    lo = lo < 0 ? first : std::min(lo, first);
    hi = std::max(hi, last_but_one);
  }
  const std::string range = lo < 0 ? "no stage: no design runs a stage before its last"
                                   : "a stage from " + std::to_string(lo) + " to " + std::to_string(hi) +
                                         " that a design runs before its last";
  throw InputError("", "--stop-after-stage", range + ", got " + std::to_string(k));
}

}  // namespace

int run_command(const RunArgs& args) {
  refuse_sets_options_give(args.plan.overrides, {{"fidelity", "--fidelity", !args.plan.fidelity.empty()}});
  // Every scene validated; nothing written yet.
  study::PlanArgs plan_args = args.plan;
  if (args.vtk) plan_args.overrides.push_back("outputs.vtk=true");
  const study::Plan plan = study::make_plan(plan_args);
  check_stop_stage(plan, args.run.stop_after_stage);
  study::check_fills(plan);
  if (args.check) {
    const std::string folder = study::check_run_folder(plan, args.plan.out, args.run.force, args.run.resume);
    for (const auto& d : plan.designs) {
      std::printf("%s: %s (fidelity %s, %d stage%s of %g h, about %.0f disks)%s\n", d.name.c_str(),
                  d.files.front().c_str(), d.scene.fidelity.c_str(), d.scene.wear.stages,
                  d.scene.wear.stages == 1 ? "" : "s", d.scene.wear.stage_hours,
                  expected_charge_disks(d.scene), d.name == plan.reference ? ", reference" : "");
      for (const std::string& note : distribution_notes(d.scene)) std::printf("%-*s %s\n", 16, "", note.c_str());
      for (const std::string& note : limit_notes(d.scene)) std::printf("%-*s %s\n", 16, "", note.c_str());
      if (d.continue_run.empty()) continue;
      char stage[64];
      std::snprintf(stage, sizeof stage, " stage %d (%.6g h)", d.continue_stage, d.continue_hours);
      print_continuation("continues", d.continue_run + stage, d.changes);
    }
    if (!folder.empty()) std::printf("%s\n", folder.c_str());
    std::printf("inputs valid; nothing run\n");
    return 0;
  }
  study::RunState state(plan);
  const bool live = !args.quiet && ::isatty(STDERR_FILENO);
  SignalScope signals;
  study::RunOptions opt = args.run;
  opt.out = args.plan.out;
  opt.stop_signal = &g_signal;
  opt.commit = MILLWEAR_COMMIT;
  bool drawn = false;
  PlainProgress plain(args.progress_every_s);
  const bool logged = !args.quiet && !live;
  if (logged)
    std::fprintf(stderr, "millwear run: %zu design(s), fidelity %s, output %s; progress every %s\n",
                 plan.designs.size(), plan.fidelity.c_str(), args.plan.out.c_str(),
                 duration_text(args.progress_every_s).c_str());
  opt.on_tick = [&] {
    if (logged) plain.tick(state);
    if (!live) return;
    if (!drawn)
      std::fprintf(stderr, "millwear run: %zu design(s), %d job(s), fidelity %s, output %s%s\n", plan.designs.size(),
                   state.jobs, plan.fidelity.c_str(), args.plan.out.c_str(), state.resumed ? " (resumed)" : "");
    draw_progress(state, drawn);
  };
  const study::RunOutcome r = study::run_designs(state, opt);

  if (r.interrupted) {
    print_final_summary(state, r.wall_s);
    std::fprintf(stderr, "millwear: interrupted%s; finished stages are kept in %s. Run the same command "
                 "with --resume to continue.\n",
                 r.signal == 0 ? " (--stop-after-stage)" : r.signal == SIGTERM ? " by SIGTERM" : " by SIGINT",
                 args.plan.out.c_str());
    return r.signal == SIGTERM ? 128 + SIGTERM : 128 + SIGINT;
  }
  if (!r.figure_error.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", r.figure_error.c_str());
  print_final_summary(state, r.wall_s);
  std::printf("results in %s (summary.csv, manifest.json, profiles/)", args.plan.out.c_str());
  if (r.figures_written > 0) std::printf("; figures in %s", io::plots_out_dir(args.plan.out).c_str());
  std::printf("\n");
  for (std::size_t i = 0; i < plan.designs.size(); ++i)
    if (state.designs[i]->status == study::DesignStatus::Failed)
      std::fprintf(stderr, "millwear: run failed: %s: %s (finished stages are kept; --resume retries)\n",
                   plan.designs[i].name.c_str(), state.designs[i]->error.c_str());
  return r.failed || r.figures_failed ? 1 : 0;
}

void register_run(CLI::App& app, Action* action) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Run the wear history of one or more designs and compare them: summary.csv, lifter "
      "profiles per stage, figures (paper Figs 6-10), resumable");
  cmd->footer(
      "A SCENE is a scene file (one design, named by its `name`) or a comparison file:\n"
      "  [comparison]\n"
      "  designs = [\"sag-2x30.toml\", \"sag-1x30.toml\"]   # relative to the comparison file\n"
      "  reference = \"sag-1x30\"   # its new stage normalises the *_norm columns (default: first)\n"
      "Units: hours, mm, mm^2, kW per mill (per-metre figure x mill length).\n"
      "Exit codes: 0 done, 1 a design or figure failed (the others finish), 2 bad input,\n"
      "130/143 interrupted (Ctrl-C/SIGTERM): finished stages are kept, --resume continues.");
  cmd->add_option("scene", args->plan.scenes, "scene or comparison files (TOML)")->required();
  cmd->add_option("-o,--out", args->plan.out, "output folder")->required()->check(output_folder());
  cmd->add_option("--fidelity", args->plan.fidelity, "draft | standard | reference (default: each scene's)")->check(fidelity_name());
  cmd->add_option("--reference", args->plan.reference, "design whose new stage normalises (default: the comparison's, else the first)")
      ->check(non_empty("a design name"));
  CLI::Option* resume = cmd->add_flag("--resume", args->run.resume, "continue an interrupted run in OUT from its last finished stages");
  // --force starts over, which --resume does not: the two together are refused, not one
  // of them obeyed.
  cmd->add_flag("--force", args->run.force,
               "OUT holds another run's results: delete the files its manifest lists, then run")
      ->excludes(resume);
  cmd->add_flag("-q,--quiet", args->quiet, "no live progress, only the final summary");
  cmd->add_option("--progress-every", args->progress_every_s,
                  "without a terminal: a plain progress line every SECONDS and at each stage (" +
                      default_text(args->progress_every_s) + ")")
      ->check(finite_in(1.0, 86400.0));
  cmd->add_flag("--check", args->check, "validate the scenes and comparison files, list the designs, run nothing");
  cmd->add_option("-j,--jobs", args->run.jobs, "designs run at once (default: hardware cores)")
      ->check(whole_in(1, 1024));
  cmd->add_option("--continue", args->plan.continue_from,
                  "go on from a finished run's stage (its exact liner and charge) under these scenes' "
                  "conditions (a new speed, filling); stages up to it are copied into OUT");
  auto* stage_opt = cmd->add_option("--stage", args->plan.continue_stage,
                                    "with --continue: the stage to go on from (default: each design's last)")
                        ->check(whole_in(0, 10000));
  stage_opt->needs("--continue");
  add_threads_option(cmd, args->run.threads, "each design's engine step", "the cores the designs at once leave");
  cmd->add_option("--stop-after-stage", args->run.stop_after_stage,
                  "for testing: stop cleanly after stage K as if interrupted (then --resume)")
      ->check(whole_in(0, 10000));
  cmd->add_option("--replicates", args->plan.replicates,
                  "histories per design, seeds s .. s+N-1, run in parallel: every figure is their mean with its "
                  "standard error (" + default_text(args->plan.replicates) + ": errors from one history's batch means)")
      ->check(whole_in(1, study::kMaxReplicates));
  add_set_option(cmd, &args->plan.overrides);
  cmd->add_flag("--vtk", args->vtk, "ParaView files of every stage's measuring window in OUT/vtk/ (as --set outputs.vtk=true)");
  cmd->callback([args, action] { *action = [args] { return run_command(*args); }; });
}

}  // namespace millwear::app
