// `millwear run SCENE... -o OUT`: the wear history of every design, compared.
//
// A SCENE argument is either a scene file (one design, named by the scene's `name`) or a
// comparison file:
//
//   [comparison]
//   name = "sag-2x30-vs-1x30"                        # optional, for the record
//   description = "..."                              # optional
//   designs = ["sag-2x30.toml", "sag-1x30.toml"]     # scene files, relative to this file
//   reference = "sag-1x30"                           # design whose new stage normalises
//                                                    # (default: the first design)
//
// Every scene is read and validated before anything is written (exit 2 on bad input).
// Designs run in parallel, one thread per design up to --jobs. The wear library never
// prints; this file owns the terminal: live progress on a terminal, a summary at the end.
//
// Exit codes: 0 every design finished; 1 a design failed (the others still finish) or a
// figure failed; 2 bad input; 130 (143 for SIGTERM) interrupted: finished stages are on
// disk and `--resume` continues.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>

#include "app/commands.hpp"
#include "app/duration_text.hpp"
#include "app/output_folder.hpp"
#include "app/run_command.hpp"
#include "app/signals.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "io/run_folder.hpp"
#include "study/plan.hpp"
#include "study/run_designs.hpp"

namespace millwear::app {

namespace {

double stage_total_hours(const Scene& s) { return s.wear.stage_hours * s.wear.stages; }

// One line per design. Caller holds the mutex.
std::string progress_line(const study::RunState& ctx, std::size_t i, std::size_t name_width) {
  const study::DesignInput& d = ctx.plan.designs[i];
  const study::DesignState& st = *ctx.designs[i];
  char buf[320];
  const int w = static_cast<int>(name_width);
  switch (st.status) {
    case study::DesignStatus::Waiting:
      std::snprintf(buf, sizeof buf, "%-*s  waiting for a free job", w, d.name.c_str());
      break;
    case study::DesignStatus::Running: {
      const double total = stage_total_hours(d.scene);
      const double start_h = st.resumed_up_to >= 0 && st.stages.count(st.resumed_up_to)
                                 ? st.stages.at(st.resumed_up_to).hours : 0.0;
      const double done_h = st.progress.hours - start_h, left_h = total - st.progress.hours;
      const double elapsed = std::chrono::duration<double>(study::Clock::now() - st.started).count();
      // Time left: the rate up to the last report, less the time since that report.
      const double at_report = std::chrono::duration<double>(st.progress_at - st.started).count();
      const double since = std::chrono::duration<double>(study::Clock::now() - st.progress_at).count();
      const double eta = done_h > 0 ? std::max(0.0, at_report * left_h / done_h - since) : std::nan("");
      // The wear loop reports after each stage; before the first report only time runs.
      if (st.progress.simulated_s <= 0.0)
        std::snprintf(buf, sizeof buf, "%-*s  stage %d/%d  %7.0f h  measuring the %s liner ...  elapsed %s",
                      w, d.name.c_str(), std::max(0, st.resumed_up_to), d.scene.wear.stages, start_h,
                      st.resumed_up_to > 0 ? "worn" : "new", duration_text(elapsed).c_str());
      else
        std::snprintf(buf, sizeof buf,
                      "%-*s  stage %d/%d  %7.0f h  sim %8.1f s  %6.2f M disk-steps/s  elapsed %s  left %s",
                      w, d.name.c_str(), st.progress.stage, d.scene.wear.stages, st.progress.hours,
                      st.progress.simulated_s, st.progress.disk_steps_per_s / 1e6,
                      duration_text(elapsed).c_str(), duration_text(eta).c_str());
      break;
    }
    case study::DesignStatus::Done:
      std::snprintf(buf, sizeof buf, "%-*s  finished in %s", w, d.name.c_str(), duration_text(st.wall_s).c_str());
      break;
    case study::DesignStatus::Failed:
      std::snprintf(buf, sizeof buf, "%-*s  FAILED: %.200s", w, d.name.c_str(), st.error.c_str());
      break;
    case study::DesignStatus::Interrupted:
      std::snprintf(buf, sizeof buf, "%-*s  interrupted", w, d.name.c_str());
      break;
  }
  return buf;
}

class ProgressView {
 public:
  ProgressView(study::RunState& ctx, bool live) : ctx_(ctx), live_(live) {
    for (const auto& d : ctx.plan.designs) width_ = std::max(width_, d.name.size());
  }
  // Caller holds the mutex.
  void draw() {
    if (!live_) return;
    std::string s;
    if (drawn_) s += "\x1b[" + std::to_string(ctx_.plan.designs.size()) + "A";
    for (std::size_t i = 0; i < ctx_.plan.designs.size(); ++i)
      s += "\r\x1b[K" + progress_line(ctx_, i, width_) + "\n";
    std::fputs(s.c_str(), stderr);
    std::fflush(stderr);
    drawn_ = true;
  }

 private:
  study::RunState& ctx_;
  bool live_;
  bool drawn_ = false;
  std::size_t width_ = 6;
};

void print_final_summary(const study::RunState& ctx, double wall) {
  std::printf("%-*s %6s %8s %10s %8s %10s %10s %8s %10s\n", 16, "design", "stage", "hours",
              "area_mm2", "loss_%", "height_mm", "power_kW", "util", "life_h");
  for (std::size_t i = 0; i < ctx.plan.designs.size(); ++i) {
    const study::DesignInput& d = ctx.plan.designs[i];
    const study::DesignState& st = *ctx.designs[i];
    double life_h;
    bool extrapolated;
    study::life_of(d, st, life_h, extrapolated);
    const auto own0 = st.stages.find(0);
    for (const auto& [k, r] : st.stages) {
      const double area = r.lifter.area_m2 * 1e6;
      const double loss = own0 != st.stages.end() ? 100.0 * (1.0 - r.lifter.area_m2 / own0->second.lifter.area_m2) : std::nan("");
      const double p = r.charge.power_kW_per_m * d.scene.mill.length_m;
      const double u = r.charge.collision_kW_per_m / r.charge.power_kW_per_m;
      std::printf("%-*s %6d %8.0f %10.1f %8.1f %10.1f %10.4g %8.3f %9.0f%s\n", 16, d.name.c_str(), k,
                  r.hours, area, loss, r.lifter.height_m * 1e3, p, u, life_h, extrapolated ? "*" : " ");
    }
    std::printf("%-*s %s%s%s\n", 16, st.stages.empty() ? d.name.c_str() : "", study::status_name(st.status),
                st.error.empty() ? "" : ": ", st.error.c_str());
    for (const auto& e : st.events) std::printf("%-*s event: %s\n", 16, "", e.c_str());
  }
  std::printf("(* life extrapolated from the stage trend; normalised to %s new; wall time %s)\n",
              ctx.plan.reference.c_str(), duration_text(wall).c_str());
}

}  // namespace

int run_command(const RunArgs& args) {
  study::PlanArgs plan_args{args.scenes, args.fidelity, args.reference, args.out};
  const study::Plan plan = study::make_plan(plan_args);  // every scene validated; nothing written yet
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
  ProgressView view(state, live);
  SignalScope signals;
  study::RunOptions opt;
  opt.out = args.out;
  opt.resume = args.resume;
  opt.force = args.force;
  opt.jobs = args.jobs;
  opt.stop_after_stage = args.stop_after_stage;
  opt.stop_signal = &g_signal;
  opt.commit = MILLWEAR_COMMIT;
  bool announced = false;
  opt.on_tick = [&] {
    if (live && !announced) {
      std::fprintf(stderr, "millwear run: %zu design(s), %d job(s), fidelity %s, output %s%s\n",
                   plan.designs.size(), state.jobs, plan.fidelity.c_str(), args.out.c_str(),
                   state.resumed ? " (resumed)" : "");
      announced = true;
    }
    view.draw();
  };
  const study::RunOutcome r = study::run_designs(state, opt);

  if (r.interrupted) {
    print_final_summary(state, r.wall_s);
    std::fprintf(stderr,
                 "millwear: interrupted%s; finished stages are kept in %s. Run the same command "
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
  cmd->add_flag("--check", args->check, "validate the scenes and comparison files, list the designs, run nothing");
  cmd->add_option("-j,--jobs", args->jobs, "designs run at once (default: hardware cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--stop-after-stage", args->stop_after_stage,
                  "for testing: stop cleanly after stage K as if interrupted (then --resume)")
      ->check(CLI::Range(0, 10000));
  cmd->callback([args, action] { *action = [args] { return run_command(*args); }; });
}

}  // namespace millwear::app
