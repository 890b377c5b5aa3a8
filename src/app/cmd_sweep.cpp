// `millwear sweep SCENE -o OUT --vary KEY=FIRST:LAST:STEP`: `millwear charge` over the values
// of one scene key, in parallel, into one table and figures (study/sweep.hpp).
#include <CLI/CLI.hpp>

#include <cstdio>

#include "app/commands.hpp"
#include "app/signals.hpp"
#include "app/default_text.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/set_option.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "study/plan.hpp"
#include "study/sweep.hpp"

namespace millwear::app {

namespace {

int run_sweep_cmd(const study::SweepRequest& q, bool quiet) {
  refuse_sets_options_give(q.overrides, {{"fidelity", "--fidelity", !q.fidelity.empty()},
                                         {"run.revolutions", "--revolutions", q.revolutions > 0.0}});
  study::SweepCallbacks cb;
  cb.on_start = [&](const study::SweepAxis& axis, int jobs) {
    if (!quiet)
      std::fprintf(stderr, "millwear sweep: %s over %zu values, %d job(s), output %s\n", axis.key.c_str(),
                   axis.values.size(), jobs, q.out.c_str());
  };
  cb.on_point = [&](const study::SweepPoint& p, int done, int total) {
    if (!quiet)
      std::fprintf(stderr, "  [%d/%d] %s = %s: %.4g kW in %.1f s wall%s%s\n", done, total, q.vary.substr(0, q.vary.find('=')).c_str(),
                   p.text.c_str(), p.power_kW, p.wall_s, p.error.empty() ? "" : " FAILED: ", p.error.c_str());
  };
  g_stop_note = "millwear sweep: interrupted; nothing of this sweep is kept, " + q.out +
                " is as it was (the points it finished, in its staging folder, go with the next sweep into "
                "it): run the sweep again\n";
  const SignalScope stop(note_and_die);
  const study::SweepResult r = study::run_sweep(q, cb);
  std::printf("%s: %s over %zu values (%d job(s), %.1f s wall); per mill, +- one standard error (%s)\n",
              r.scene_name.c_str(), r.axis.key.c_str(), r.points.size(), r.jobs, r.wall_s,
              q.replicates > 1 ? ("of the mean of " + std::to_string(q.replicates) + " replicates").c_str()
                               : "batch means of one charge, a lower bound");
  std::printf("%10s %6s %20s %18s %20s %20s %13s %13s\n", "value", "crit", "power_kW", "kW/t", "collision_kW",
              "shear_kW", "toe_deg", "shoulder_deg");
  for (const study::SweepPoint& p : r.points) {
    char toe[32], shoulder[32];
    std::snprintf(toe, sizeof toe, "%5.1f +- %-4.1f", p.toe_deg, p.toe_deg_sem);
    std::snprintf(shoulder, sizeof shoulder, "%5.1f +- %-4.1f", p.shoulder_deg, p.shoulder_deg_sem);
    std::printf("%10s %6.3f %9.4g +- %-8.2g %7.4g +- %-7.2g %9.4g +- %-8.2g %9.4g +- %-8.2g %13s %13s%s\n", p.text.c_str(),
                p.speed_fraction_critical, p.power_kW, p.power_kW_sem, p.specific_kW_per_t, p.specific_kW_per_t_sem,
                p.collision_kW, p.collision_kW_sem, p.shear_kW, p.shear_kW_sem, p.centrifuged ? "centrifuged" : toe,
                p.centrifuged ? "centrifuged" : shoulder, p.error.empty() ? "" : "  FAILED");
  }
  std::printf("results in %s (sweep.csv, manifest.json, points/)", q.out.c_str());
  if (!r.figure_files.empty()) std::printf("; figures in %s/plots", q.out.c_str());
  std::printf("\n");
  if (!r.figure_error.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", r.figure_error.c_str());
  for (const study::SweepPoint& p : r.points)
    if (p.error.empty() && !p.unsteady.empty())
      std::fprintf(stderr, "millwear: warning: %s = %s: %s\n", r.axis.key.c_str(), p.text.c_str(), p.unsteady.c_str());
  for (const study::SweepPoint& p : r.points)
    if (p.error.empty() && !p.unsound.empty())
      std::fprintf(stderr, "millwear: warning: %s = %s: %s\n", r.axis.key.c_str(), p.text.c_str(), p.unsound.c_str());
  for (const study::SweepPoint& p : r.points)
    if (!p.error.empty())
      std::fprintf(stderr, "millwear: run failed: %s = %s: %s\n", r.axis.key.c_str(), p.text.c_str(), p.error.c_str());
  return r.failed() || r.figures_failed ? 1 : 0;
}

}  // namespace

void register_sweep(CLI::App& app, Action* action) {
  auto args = std::make_shared<study::SweepRequest>();
  auto quiet = std::make_shared<bool>(false);
  auto no_plot = std::make_shared<bool>(false);
  CLI::App* cmd = app.add_subcommand(
      "sweep", "The charge (as `millwear charge`) over the values of one scene key: power, toe/shoulder, "
               "collision and liner shear power against it, with errors");
  cmd->footer(
      "--vary KEY=FIRST:LAST:STEP (LAST included) or KEY=V1,V2,...: any numeric scene key, e.g.\n"
      "  millwear sweep scenarios/lab-mill.toml -o out/speed --vary mill.speed=0.5:1.6:0.1\n"
      "Every point is checked before anything runs (exit 2 naming the key). Writes OUT/sweep.csv,\n"
      "OUT/points/NN/ (each point's charge files; NN.rK: replicate K), OUT/plots/sweep_*.png|svg,\n"
      "OUT/manifest.json.\n"
      "Exit codes: 0 done, 1 a point lost a disk (the others are kept), 2 bad input.");
  cmd->add_option("scene", args->scene_file, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--vary", args->vary, "KEY=FIRST:LAST:STEP or KEY=V1,V2,...")->required();
  add_set_option(cmd, &args->overrides);
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference (default: the scene's)")->check(fidelity_name());
  cmd->add_option("--revolutions", args->revolutions, "measured revolutions per point (default: the scene's)")
      ->check(finite_in(1e-6, 1e4));
  cmd->add_option("-j,--jobs", args->jobs, "points at once (default: hardware cores)")->check(whole_in(1, 1024));
  cmd->add_option("--replicates", args->replicates,
                  "charges per value, seeds s .. s+N-1: figures are their mean with its standard error (" +
                      default_text(args->replicates) + ": batch means, a lower bound)")
      ->check(whole_in(1, study::kMaxReplicates));
  cmd->add_flag("--no-plot", *no_plot, "skip the figures");
  cmd->add_flag("-q,--quiet", *quiet, "no progress lines, only the final table");
  cmd->callback([args, quiet, no_plot, action] {
    args->figures = !*no_plot;
    args->commit = MILLWEAR_COMMIT;
    *action = [args, quiet] { return run_sweep_cmd(*args, *quiet); };
  });
}

}  // namespace millwear::app
