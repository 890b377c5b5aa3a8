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

#include <csignal>
#include <cstdio>

#include "app/commands.hpp"
#include "app/duration_text.hpp"
#include "app/output_folder.hpp"
#include "app/run_command.hpp"
#include "app/plain_progress.hpp"
#include "app/run_view.hpp"
#include "app/signals.hpp"
#include "common/units.hpp"
#include "io/run_folder.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "study/run_progress.hpp"

namespace millwear::app {

namespace {

void print_final_summary(const study::RunState& state, double wall) {
  std::printf("%-*s %6s %8s %10s %8s %10s %10s %8s %10s\n", 16, "design", "stage", "hours",
              "area_mm2", "loss_%", "height_mm", "power_kW", "util", "life_h");
  for (const study::DesignLines& d : study::design_lines(state)) {
    for (const study::StageLine& l : d.stages)
      std::printf("%-*s %6d %8.0f %10.1f %8.1f %10.1f %10.4g %8.3f %9.0f%s\n", 16, d.name.c_str(), l.stage, l.hours,
                  in_mm2(l.area_m2), 100.0 * l.area_loss_fraction, in_mm(l.height_m), l.power_kW, l.utilization,
                  d.life_h, d.life_extrapolated ? "*" : " ");
    std::printf("%-*s %s%s%s\n", 16, d.stages.empty() ? d.name.c_str() : "", study::status_name(d.status),
                d.error.empty() ? "" : ": ", d.error.c_str());
    for (const auto& e : d.events) std::printf("%-*s event: %s\n", 16, "", e.c_str());
  }
  std::printf("(* life extrapolated from the stage trend; normalised to %s new; wall time %s)\n",
              state.plan.reference.c_str(), duration_text(wall).c_str());
}

}  // namespace

int run_command(const RunArgs& args) {
  // Every scene validated; nothing written yet.
  const study::Plan plan = study::make_plan({args.scenes, args.fidelity, args.reference, args.out});
  if (args.check) {
    for (const auto& d : plan.designs)
      std::printf("%s: %s (fidelity %s, %d stages of %g h)%s\n", d.name.c_str(), d.files.front().c_str(),
                  d.scene.fidelity.c_str(), d.scene.wear.stages, d.scene.wear.stage_hours,
                  d.name == plan.reference ? ", reference" : "");
    std::printf("inputs valid; nothing run\n");
    return 0;
  }
  study::RunState state(plan);
  const bool live = !args.quiet && ::isatty(STDERR_FILENO);
  SignalScope signals;
  study::RunOptions opt;
  opt.out = args.out;
  opt.resume = args.resume;
  opt.force = args.force;
  opt.jobs = args.jobs;
  opt.stop_after_stage = args.stop_after_stage;
  opt.stop_signal = &g_signal;
  opt.commit = MILLWEAR_COMMIT;
  bool drawn = false;
  PlainProgress plain(args.progress_every_s);
  const bool logged = !args.quiet && !live;
  if (logged)
    std::fprintf(stderr, "millwear run: %zu design(s), fidelity %s, output %s; progress every %s\n",
                 plan.designs.size(), plan.fidelity.c_str(), args.out.c_str(),
                 duration_text(args.progress_every_s).c_str());
  opt.on_tick = [&] {
    if (logged) plain.tick(state);
    if (!live) return;
    if (!drawn)
      std::fprintf(stderr, "millwear run: %zu design(s), %d job(s), fidelity %s, output %s%s\n", plan.designs.size(),
                   state.jobs, plan.fidelity.c_str(), args.out.c_str(), state.resumed ? " (resumed)" : "");
    draw_progress(state, drawn);
  };
  const study::RunOutcome r = study::run_designs(state, opt);

  if (r.interrupted) {
    print_final_summary(state, r.wall_s);
    std::fprintf(stderr, "millwear: interrupted%s; finished stages are kept in %s. Run the same command "
                 "with --resume to continue.\n",
                 r.signal == 0 ? " (--stop-after-stage)" : r.signal == SIGTERM ? " by SIGTERM" : " by SIGINT",
                 args.out.c_str());
    return r.signal == SIGTERM ? 128 + SIGTERM : 128 + SIGINT;
  }
  if (!r.figure_error.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", r.figure_error.c_str());
  print_final_summary(state, r.wall_s);
  std::printf("results in %s (summary.csv, manifest.json, profiles/); figures in %s\n", args.out.c_str(),
              io::plots_out_dir(args.out).c_str());
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
  cmd->add_option("scene", args->scenes, "scene or comparison files (TOML)")->required();
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference (default: each scene's)");
  cmd->add_option("--reference", args->reference, "design whose new stage normalises (default: the comparison's, else the first)");
  cmd->add_flag("--resume", args->resume, "continue an interrupted run in OUT from its last finished stages");
  cmd->add_flag("--force", args->force,
               "OUT holds another run's results: delete the files its manifest lists, then run");
  cmd->add_flag("-q,--quiet", args->quiet, "no live progress, only the final summary");
  cmd->add_option("--progress-every", args->progress_every_s,
                  "without a terminal: a plain progress line every SECONDS and at each stage (default 60)")
      ->check(CLI::Range(1.0, 86400.0));
  cmd->add_flag("--check", args->check, "validate the scenes and comparison files, list the designs, run nothing");
  cmd->add_option("-j,--jobs", args->jobs, "designs run at once (default: hardware cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--stop-after-stage", args->stop_after_stage,
                  "for testing: stop cleanly after stage K as if interrupted (then --resume)")
      ->check(CLI::Range(0, 10000));
  cmd->callback([args, action] { *action = [args] { return run_command(*args); }; });
}

}  // namespace millwear::app
