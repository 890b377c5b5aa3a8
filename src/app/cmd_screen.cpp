// `millwear screen SCREEN -o OUT`: a family of lifter designs run and ranked by life.
//
//   millwear screen SCREEN -o OUT [--jobs N] [--resume]      local worker pool, then ranking
//   millwear screen SCREEN -o OUT --emit parallel|slurm [--chunk K] [--jobs M]
//                                                             job list / sbatch array script
//   millwear screen --collect OUT                             ranking of whatever finished
//
// The library does the screen (screen/run_screen.hpp); each design is one `millwear
// screen-task` (cmd_screen_task.cpp). This file parses, prints and maps the outcome to an
// exit code: 0 every design finished
// and was ranked; 1 a design failed or is missing (the ranking lists it); 2 bad input
// (screen file, base scene, a --set override, no valid candidate); 130/143 interrupted
// (--resume continues).
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "app/commands.hpp"
#include "app/default_text.hpp"
#include "app/duration_text.hpp"
#include "app/number_checks.hpp"
#include "study/plan.hpp"
#include "app/output_folder.hpp"
#include "app/plain_progress.hpp"
#include "app/set_option.hpp"
#include "app/signals.hpp"
#include "common/errors.hpp"
#include "common/units.hpp"
#include "screen/jobs.hpp"
#include "screen/run_screen.hpp"

namespace millwear::app {

using namespace millwear::screen;

namespace {

struct ScreenArgs {
  ScreenRequest request;  // request.screen_file is OUT with --collect
  bool collect = false;
  bool quiet = false;
  double progress_every_s = kProgressEveryS;
};

// The ranking table on stdout, the failed and missing designs on stderr. Returns 0 if every
// design finished, else 1.
int print_collected(const std::string& out, const CollectOutcome& o) {
  std::printf("%4s %-10s %12s %10s %4s %10s %8s %12s %6s\n", "rank", "design", "life_h", "+-2sigma", "tie",
              "power_kW", "util", "loss/1000h", "front");
  int replicates = 0;
  for (const auto& r : o.ranked)
    if (r.status == "finished") replicates = std::max(replicates, r.replicates);
  for (const auto& r : o.ranked) {
    if (r.status != "finished") continue;
    const std::string rank = r.rank > 0 ? std::to_string(r.rank) : "-";  // finished with no life
    std::printf("%4s %-10s %11.0f%s %10.0f %4s %10.4g %8.4f %12.1f %6s\n", rank.c_str(), r.design.name.c_str(), r.life_h,
                r.life_extrapolated && std::isfinite(r.life_h) ? "*" : " ", 2.0 * r.life_sigma_h, r.tied_with_best ? "=" : "",
                in_kW(r.power_W), r.utilization, r.area_loss_mm2_per_1000h,
                r.pareto_power && r.pareto_utilization ? "P,U" : r.pareto_power ? "P" : r.pareto_utilization ? "U" : "");
  }
  // The tie rule is compare()'s: 2 combined sigma on one history's errors, Student's t for
  // the replicates' degrees of freedom on their spread.
  const std::string tie_rule = replicates > 1 ? "not resolved by Student's t for " + std::to_string(replicates) +
                                                    " replicates, as run's verdicts"
                                              : "within 2 combined sigma";
  std::printf("(* life extrapolated; - no life to rank; = tied with the best: %s; front P: life vs power, U: life vs "
              "utilisation)\n",
              tie_rule.c_str());
  if (replicates > 1)
    std::printf("sigma: standard error of the mean of %d replicates per design\n", replicates);
  else if (replicates == 1)
    std::printf("sigma: one history per design, from its batch means (--replicates N measures the spread "
                "between histories)\n");
  for (const auto& r : o.ranked) {
    if (r.status == "failed" || r.status == "missing")
      std::fprintf(stderr, "millwear: design %s %s: %s\n", r.design.name.c_str(), r.status.c_str(), r.reason.c_str());
    if (!r.figure_error.empty())
      std::fprintf(stderr, "millwear: design %s: %s\n", r.design.name.c_str(), r.figure_error.c_str());
  }
  if (!o.figure_error.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", o.figure_error.c_str());
  std::printf("ranking: %s (%zu designs: %zu finished, %d failed, %d missing)\n", ranking_csv(out).c_str(),
              o.ranked.size(), o.ranked.size() - o.failed - o.missing, o.failed, o.missing);
  if (o.missing + o.failed > 0)
    std::printf("to finish: run the missing/failed tasks again (millwear screen-task %s I), or re-emit them "
                "with --emit, then --collect\n", shell_word(out).c_str());
  if (o.figures_failed)
    std::printf("to draw the figures: run the screen again with --resume (a finished design's task only redraws "
                "them), then --collect\n");
  return o.missing + o.failed > 0 || o.figures_failed ? 1 : 0;
}

void print_emitted(const ScreenArgs& a, const ScreenOutcome& o) {
  const std::string& out = a.request.out;
  // The commands printed are to be pasted into a shell: their paths are quoted where needed.
  if (o.emit.path.empty()) {
    std::printf("every design has finished: nothing to emit; rank them with millwear screen --collect %s\n",
                screen::shell_word(out).c_str());
    return;
  }
  const bool parallel = a.request.emit == "parallel";
  std::printf("%zu %s (%zu design(s), %d already finished) in %s\nrun:  %s%s\nthen: %s screen --collect %s\n",
              o.emit.jobs, parallel ? "job(s)" : "array task(s)", o.setup.todo.size(), o.setup.already_done,
              o.emit.path.c_str(), parallel ? "parallel -j N < " : "sbatch ", screen::shell_word(o.emit.path).c_str(),
              screen::shell_word(o.emit.binary).c_str(), screen::shell_word(out).c_str());
}

int screen_command(const ScreenArgs& args) {
  if (args.collect) {
    if (!args.request.overrides.empty())
      throw InputError("", "--set", "no --set with --collect (the candidates were written with the screen's overrides)");
    const std::string out = !args.request.out.empty() ? args.request.out : args.request.screen_file;
    if (out.empty()) throw InputError("", "--collect", "the screen's output folder: --collect -o OUT (or --collect OUT)");
    // Two folders named: which one was meant is not for the command to guess.
    if (!args.request.out.empty() && !args.request.screen_file.empty() &&
        std::filesystem::weakly_canonical(args.request.out) != std::filesystem::weakly_canonical(args.request.screen_file))
      throw InputError("", "--collect", "one output folder, as --collect OUT or --collect -o OUT; got " +
                                            args.request.screen_file + " and -o " + args.request.out);
    return print_collected(out, collect_screen(out));
  }
  const std::string& out = args.request.out;
  const bool live = !args.quiet && ::isatty(STDERR_FILENO);
  std::size_t total = 0, to_run = 0;
  std::optional<SignalScope> signals;  // during the pool: a signal stops it, finished designs stay
  ScreenCallbacks cb;
  cb.on_setup = [&](const ScreenSetup& s) {
    total = s.designs.size();
    to_run = s.todo.size();
    std::printf("screen %s: %zu candidate(s), %zu valid, %zu rejected (%s)\n", s.name.c_str(), s.candidates,
                s.designs.size(), s.rejected, rejected_csv(out).c_str());
  };
  cb.on_pool_start = [&](int jobs) {
    signals.emplace(record_signal);
    if (live)
      std::fprintf(stderr, "millwear screen: %zu design(s), %zu to run, %d job(s), output %s\n", total, to_run, jobs,
                   out.c_str());
  };
  if (live)
    cb.on_pool_tick = [](const PoolProgress& p) {
      std::fprintf(stderr, "\r\x1b[Kscreen: %d/%d done, %d running, %d failed, elapsed %s, left %s", p.done, p.total,
                   p.running, p.failed, duration_text(p.elapsed_s).c_str(), duration_text(p.left_s).c_str());
      std::fflush(stderr);
    };
  // Without a terminal (a log, cron, Slurm): plain lines when a design finishes and every
  // --progress-every seconds.
  PlainProgress plain(args.progress_every_s);
  if (!live && !args.quiet) cb.on_pool_tick = [&plain](const PoolProgress& p) { plain.tick(p); };
  cb.on_pool_end = [&] {
    if (live) std::fprintf(stderr, "\n");
    signals.reset();
  };
  const ScreenOutcome o = run_screen(args.request, &g_signal, cb);
  if (o.emitted) {
    print_emitted(args, o);
    return 0;
  }
  if (o.signal != 0) {
    std::fprintf(stderr,
                 "millwear: screen interrupted; finished designs and stages are kept in %s. Run the same command "
                 "with --resume to continue.\n",
                 out.c_str());
    return 128 + o.signal;
  }
  return print_collected(out, o.collected);
}

}  // namespace

void register_screen(CLI::App& app, Action* action) {
  auto args = std::make_shared<ScreenArgs>();
  ScreenRequest& r = args->request;
  CLI::App* cmd = app.add_subcommand(
      "screen", "Screen a family of lifter designs: run each (locally, or via GNU parallel / Slurm), rank by life with "
                "uncertainty, Pareto fronts, figures");
  cmd->footer(
      "Screen file: [screen] base = \"scene.toml\", sampling = \"grid\"|\"latin_hypercube\", equal_area, ...;\n"
      "[family] height, top_width, leading_face_angle, trailing_face_angle, rows, direction (see docs/screen.md).\n"
      "--set KEY=VALUE goes over the base scene and into every candidate's scene file.\n"
      "OUT: designs.csv, rejected.csv, candidates/, designs/NAME/ (a `millwear run` folder each), ranking.csv, plots/.\n"
      "Exit codes: 0 all ranked, 1 a design failed or is missing, 2 bad input, 130/143 interrupted (--resume).");
  cmd->add_option("screen", r.screen_file, "screen file (TOML); with --collect: the output folder");
  cmd->add_option("-o,--out", r.out, "output folder")->check(output_folder());
  auto* jobs = cmd->add_option("-j,--jobs", r.jobs, "designs run at once (default: hardware cores); with --emit slurm: %M")
      ->check(whole_in(1, 1024));
  auto* resume = cmd->add_flag("--resume", r.resume, "keep finished designs (and finished stages) in OUT, run the rest");
  auto* force = cmd->add_flag("--force", r.force,
                "OUT holds a screen of other inputs: delete that screen's files (no other file) and start over");
  auto* emit = cmd->add_option("--emit", r.emit, "parallel | slurm: write a job list / sbatch array script instead of running");
  cmd->add_option("--chunk", r.chunk, "designs per job or array task (with --emit)")
      ->check(whole_in(1, 100000))
      ->needs(emit);
  add_set_option(cmd, &r.overrides);
  auto* replicates = cmd->add_option("--replicates", r.replicates,
                  "histories per design, seeds s, s+1, ... (" + default_text(r.replicates) +
                      "): the life's error from their spread; with 1 it is propagated from one history's batch means")
      ->check(whole_in(1, study::kMaxReplicates));
  // --collect ranks what is there: an option of a screen that runs or emits designs would be
  // ignored, as if it had been applied.
  cmd->add_flag("--collect", args->collect, "rank whatever finished in OUT; list missing and failed designs")
      ->excludes(jobs)
      ->excludes(resume)
      ->excludes(force)
      ->excludes(emit)
      ->excludes(replicates);
  cmd->add_flag("-q,--quiet", args->quiet, "no live progress");
  cmd->add_option("--progress-every", args->progress_every_s,
                  "without a terminal: a plain progress line every SECONDS and at each design (" +
                      default_text(args->progress_every_s) + ")")
      ->check(finite_in(1.0, 86400.0));
  cmd->callback([args, action] { *action = [args] { return screen_command(*args); }; });
}

}  // namespace millwear::app
