// `millwear tradeoff SCENE -o OUT [--quick] [--only LABELS] [--stages N] [--stage-hours H] [--jobs J]`:
// the wear history of one design, or of every design of a comparison file, over the
// fidelity ladder (study/tradeoff.hpp), each run measured against the reference run; the
// files it writes in study/tradeoff_study.hpp.
// Exit codes: 0 done (without gnuplot: no figure, a warning); 1 the reference run failed or
// gnuplot failed on the figure; 2 bad input.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <mutex>

#include "app/commands.hpp"
#include "app/signals.hpp"
#include "app/default_text.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/plain_progress.hpp"
#include "app/set_option.hpp"
#include "common/text.hpp"
#include "common/units.hpp"
#include "io/csv.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "plots/plots.hpp"
#include "study/tradeoff_study.hpp"

namespace millwear::app {

namespace {

std::string fmt(double v, const char* f = "%.2f") { return io::format_for_table(v, f); }

int run_tradeoff_cmd(const TradeoffStudyRequest& a) {
  refuse_sets_options_give(a.overrides, {{"wear.stages", "--stages", a.options.stages > 0},
                                         {"wear.stage_hours", "--stage-hours", a.options.stage_hours > 0.0}});
  const std::string& out = a.out;
  // One plain line per finished run (the runs go on in worker threads): the time of day, how
  // many of the ladder's runs are done, the elapsed and remaining time.
  std::mutex print_mutex;
  std::size_t total = 0, done = 0;
  const auto t0 = std::chrono::steady_clock::now();
  TradeoffStudyCallbacks cb;
  cb.on_ladder = [&a, &total](const TradeoffLadder& ladder) {
    const Scene& first = ladder.settings.front().scenes.front();
    total = ladder.settings.size() * ladder.settings.front().scenes.size();
    std::printf("tradeoff on %zu design(s): %zu settings, %d stage(s) of %g h, %d job(s)\n",
                ladder.settings.front().scenes.size(), ladder.settings.size(), first.wear.stages,
                first.wear.stage_hours, a.jobs);
    for (const auto& h : ladder.held_knobs) std::printf("  held: %s\n", h.c_str());
    std::fflush(stdout);
  };
  cb.runs.on_design = [&](const TradeoffSetting& s, const TradeoffDesign& d, double wall, double cpu,
                          const std::string& error) {
    std::lock_guard<std::mutex> lock(print_mutex);
    ++done;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double left = elapsed / static_cast<double>(done) * static_cast<double>(total - done);
    const std::string when = clock_text() + "  [" + std::to_string(done) + "/" + std::to_string(total) +
                             ", elapsed " + duration_text(elapsed) + ", left " + duration_text(left) + "]";
    if (error.empty())
      std::printf("  done   %-24s %-12s %8.1f s (CPU %.1f s)  final area %.0f mm^2, height %.1f mm  %s\n",
                  s.label.c_str(), d.name.c_str(), wall, cpu, in_mm2(d.final_area_m2), in_mm(d.final_height_m),
                  when.c_str());
    else
      std::printf("  failed %-24s %8.1f s  %s  %s\n", s.label.c_str(), wall, error.c_str(), when.c_str());
    std::fflush(stdout);
  };
  g_stop_note = "millwear tradeoff: interrupted; nothing of this ladder is kept, " + out +
                " is as it was: run it again (--only LABELS runs fewer settings)\n";
  const SignalScope stop(note_and_die);
  const TradeoffStudy study = run_tradeoff_study(a, cb);
  const TradeoffReport& report = study.report;

  std::printf("\n%-24s %9s %9s %8s %10s %8s %10s %9s %9s %8s %6s %6s\n", "setting", "cpu_s", "wall_s", "speedup",
              "dev_max_mm", "%height", "dev_mean%", "area_err%", "power%", "life%", "order", "front");
  for (const auto& r : report.rows)
    std::printf("%-24s %9s %9s %8s %10s %8s %10s %9s %9s %8s %6s %6s\n", r.label.c_str(), fmt(r.cpu_s, "%.1f").c_str(),
                fmt(r.wall_s, "%.1f").c_str(), fmt(r.speedup, "%.2f").c_str(), fmt(in_mm(r.dev_max_m)).c_str(),
                fmt(r.dev_max_pct).c_str(), fmt(r.dev_mean_pct).c_str(), fmt(r.area_err_pct).c_str(),
                fmt(r.power_err_pct).c_str(), fmt(r.life_err_pct).c_str(),
                r.designs.size() < 2 ? "-" : (r.life_order_same ? "same" : "DIFF"), r.pareto ? "*" : "");
  std::printf("wrote %s/tradeoff.csv, tradeoff_designs.csv, tradeoff_front.csv, tradeoff_profiles.csv, tradeoff.md\n",
              out.c_str());
  if (!a.figure) return 0;
  if (study.figure_skipped) {
    std::printf("no figure: one setting, nothing to trade off\n");
    return 0;
  }
  if (!study.figure_error.empty()) {
    // Without gnuplot the tables stand alone (as for every command); a gnuplot that failed
    // is a failed figure.
    if (!plots::gnuplot_available()) {
      std::fprintf(stderr, "millwear: warning: figures: %s\n", study.figure_error.c_str());
      return 0;
    }
    std::fprintf(stderr, "millwear: figure failed: %s\n", study.figure_error.c_str());
    return 1;
  }
  std::printf("wrote %s/tradeoff.png, tradeoff.svg\n", out.c_str());
  return 0;
}

}  // namespace

void register_tradeoff(CLI::App& app, Action* action) {
  auto args = std::make_shared<TradeoffStudyRequest>();
  TradeoffStudyRequest& r = *args;
  auto no_plot = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "tradeoff", "Speed against accuracy: the wear history over a ladder of fidelity settings, against reference");
  cmd->add_option("scene", r.scene_file, "scene file of one design, or a comparison file (TOML)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", r.out, "output folder")->required()->check(output_folder());
  cmd->add_flag("--quick", r.options.quick, "the three presets only (no one-knob ladder)");
  cmd->add_option("--stages", r.options.stages, "stages to run (default: the scene's)")->check(whole_in(1, 10000));
  cmd->add_option("--stage-hours", r.options.stage_hours, "hours per stage (default: the scene's)")
      ->check(finite_in(1.0, 1e6));
  cmd->add_option("-j,--jobs", r.jobs, "runs (setting x design) at once (" + default_text(r.jobs) + "; wall times then share the cores)")
      ->check(whole_in(1, 1024));
  cmd->add_flag("--no-plot", *no_plot, "skip the figure");
  add_set_option(cmd, &r.overrides);
  cmd->add_option("--only", r.options.only,
                  "run only these settings, by label (comma-separated, e.g. \"standard,standard seed=2\"); "
                  "the reference always runs")
      ->delimiter(',');
  cmd->callback([args, no_plot, action] {
    // "standard, draft": a label's own spaces stay, those around a comma go.
    for (std::string& label : args->options.only) label = trim(label);
    args->figure = !*no_plot;
    args->commit = MILLWEAR_COMMIT;
    *action = [args] { return run_tradeoff_cmd(*args); };
  });
}

}  // namespace millwear::app
