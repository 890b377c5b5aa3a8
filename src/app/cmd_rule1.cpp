// `millwear rule1 SCENE`: checks rule 1 (C_model x n with time / n gives the same profile),
// each factor replicated over seeds so that a deviation is told from seed-to-seed noise.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "app/commands.hpp"
#include "app/signals.hpp"
#include "app/default_text.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/set_option.hpp"
#include "app/threads_option.hpp"
#include "common/units.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "study/command_manifest.hpp"
#include "study/plan.hpp"
#include "study/rule1.hpp"
#include "wear/reshape.hpp"

namespace millwear::app {

namespace {

struct Rule1Args {
  std::string scene;
  std::string out;
  std::string fidelity;
  Rule1Options options;  // no factors: default_rule1_factors of the scene's
  int stages = 1;
  std::vector<std::string> overrides;
  int threads = 0;
};

int run_rule1(const Rule1Args& a) {
  refuse_sets_options_give(a.overrides, {{"fidelity", "--fidelity", !a.fidelity.empty()},
                                         {"wear.stages", "--stages", true},
                                         {"wear.factor", "--factors", !a.options.factors.empty()}});
  Rule1Options opt = a.options;
  const Scene scene = study::load_checked_scene(a.scene, a.overrides, a.fidelity, [&](Scene& s) {
    s.wear.stages = a.stages;
    if (opt.factors.empty()) opt.factors = default_rule1_factors(s.wear.factor);
    // The histories run side by side on the cores; each step gets the cores they leave.
    const int at_once = jobs_for(opt.jobs, opt.factors.size() * static_cast<std::size_t>(opt.replicates));
    s.solver.threads = step_threads_beside(a.threads, at_once);
    s.solver.threads_fit_size = a.threads == 0;
  });
  std::unique_ptr<io::FolderLock> lock;
  // The new files are drawn up beside an earlier check's, which stay in OUT as they were until
  // every new file is complete (a check that fails or is stopped leaves them).
  std::unique_ptr<io::StagedOutputs> staged;
  if (!a.out.empty()) {
    lock = std::make_unique<io::FolderLock>(a.out, "rule1");
    io::check_output_names(a.out, {"manifest.json", "rule1.csv", "rule1_replicates.csv", "rule1_profiles.dat",
                                   "plots/fig5_rule1.png", "plots/fig5_rule1.svg", "plots/gnuplot.log"}, "rule1");
    staged = std::make_unique<io::StagedOutputs>(a.out);
  }
  g_stop_note = a.out.empty() ? "millwear rule1: interrupted; nothing of this check is kept: run it again\n"
                              : "millwear rule1: interrupted; nothing of this check is kept, " + a.out +
                                    " is as it was: run it again\n";
  const SignalScope stop(note_and_die);
  const Rule1Report r = rule1_check(scene, opt);

  std::printf("rule 1 on %s: %d stage(s) of %.0f h, continuous mode, %d seed(s) per factor\n", scene.name.c_str(),
              a.stages, scene.wear.stage_hours, r.replicates);
  std::printf("deviation from the smallest factor's mean profile, %% of the %.1f mm lifter height\n",
              in_mm(r.lifter_height_m));
  std::printf("%12s %10s %20s %12s %14s  %s\n", "factor", "sim_s", "deviation", "noise", "within tol.", "verdict");
  for (const auto& row : r.rows) {
    const double sim = mean_simulated_s(row);
    const double h = 100.0 / r.lifter_height_m;
    if (row.verdict == Rule1Verdict::Failed || row.verdict == Rule1Verdict::Reference) {
      std::printf("%12.3g %10.2f %20s %12s %14s  %s\n", row.factor, sim, "-", "-", "-", verdict_name(row.verdict));
    } else {
      char dev[48];
      if (row.deviation_se_m > 0.0)
        std::snprintf(dev, sizeof dev, "%.2f +- %.2f", row.deviation_m * h, row.deviation_se_m * h);
      else
        std::snprintf(dev, sizeof dev, "%.2f", row.deviation_m * h);
      char noise[24] = "-", within[24] = "-";  // unknown with one seed
      if (std::isfinite(row.noise_floor_m)) std::snprintf(noise, sizeof noise, "%.2f", row.noise_floor_m * h);
      if (std::isfinite(row.chance_within)) std::snprintf(within, sizeof within, "%.0f%%", 100.0 * row.chance_within);
      std::printf("%12.3g %10.2f %20s %12s %14s  %s", row.factor, sim, dev, noise, within, verdict_name(row.verdict));
      if (row.verdict == Rule1Verdict::Scatters)
        std::printf(" (seeds spread %.1fx the smallest factor's, p = %.3f)", std::sqrt(row.scatter_ratio),
                    row.scatter_p);
      std::printf("\n");
    }
    for (const auto& rep : row.replicates)
      for (const auto& e : rep.events) std::printf("    seed %llu: %s\n", static_cast<unsigned long long>(rep.seed), e.c_str());
  }
  if (r.recommended_factor > 0.0) {
    if (r.replicates > 1 && std::isfinite(r.recommended_chance))
      std::printf("recommended factor: %.3g (largest whose profile is not significantly further than %.1f%% of the "
                  "lifter height from the smallest factor's; %.0f%% chance it is within)\n",
                  r.recommended_factor, r.tolerance_pct_height, 100.0 * r.recommended_chance);
    else if (r.replicates > 1)
      std::printf("recommended factor: %.3g (the seeds agree exactly: no noise to judge a deviation by)\n",
                  r.recommended_factor);
    else
      std::printf("recommended factor: %.3g (one seed per factor: the noise is unknown; --replicates 4 tells a "
                  "deviation from noise)\n", r.recommended_factor);
  } else {
    std::printf("no factor passed: even the smallest factor's runs reported events\n");
  }
  if (!a.out.empty()) {
    study::CommandRecord record{"rule1", MILLWEAR_COMMIT, a.scene, a.overrides, scene.fidelity, scene.solver.seed, {}, {}};
    std::string factors;
    for (double f : opt.factors) factors += (factors.empty() ? "" : " ") + io::format_number(f);
    record.settings = {{"factors", factors},
                       {"replicates", std::to_string(opt.replicates)},
                       {"tolerance_pct_height", io::format_number(opt.tolerance_pct_height)},
                       {"stages", std::to_string(a.stages)}};
    const std::string& dir = staged->dir();
    record.files = write_rule1_outputs(dir, scene, r);
    bool figure_failed = false;
    try {
      const std::vector<std::string> figures = render_rule1_figure(dir, scene, r);
      record.files.insert(record.files.end(), figures.begin(), figures.end());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "millwear: warning: figure: %s\n", staged->in_out_text(e.what()).c_str());
      figure_failed = true;
    }
    record.files.push_back(io::join_path(dir, "plots/gnuplot.log"));
    study::write_command_manifest(dir, record);
    staged->commit({a.scene});
    std::printf("results in %s (manifest.json, rule1.csv, rule1_replicates.csv, rule1_profiles.dat%s)\n",
                a.out.c_str(), figure_failed ? "" : ", plots/fig5_rule1");
    if (figure_failed && plots::gnuplot_available()) return 1;
  }
  return r.recommended_factor > 0.0 ? 0 : 1;
}

}  // namespace

void register_rule1(CLI::App& app, Action* action) {
  auto args = std::make_shared<Rule1Args>();
  CLI::App* cmd = app.add_subcommand("rule1", "Check rule 1: scaling C_model by n and time by 1/n gives the same profile");
  cmd->add_option("scene", args->scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder: rule1.csv, the profiles and Fig. 5 (default: print only)")
      ->check(output_folder());
  cmd->add_option("--factors", args->options.factors, "factors C_model/C to compare, at least two (default: f/2, f, 2f, 10f)")
      ->check(finite_positive());
  cmd->add_option("--replicates", args->options.replicates,
                  "histories per factor, seeds s, s+1, ... (" + default_text(args->options.replicates) + ")")
      ->check(whole_in(1, study::kMaxReplicates));
  cmd->add_option("--tolerance", args->options.tolerance_pct_height,
                  "allowed deviation, % of lifter height (" + default_text(args->options.tolerance_pct_height) + ")")
      ->check(finite_in(1e-6, 100.0));
  cmd->add_option("--stages", args->stages, "stages to run (" + default_text(args->stages) + ")")
      ->check(whole_in(1, 10000));
  cmd->add_option("-j,--jobs", args->options.jobs, "histories at once (default: the cores)")->check(whole_in(1, 1024));
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference")->check(fidelity_name());
  add_threads_option(cmd, args->threads, "each history's engine step", "the cores the histories at once leave");
  add_set_option(cmd, &args->overrides);
  cmd->callback([args, action] { *action = [args] { return run_rule1(*args); }; });
}

}  // namespace millwear::app
