// `millwear rule1 SCENE`: checks rule 1 (C_model x n with time / n gives the same profile).
#include <CLI/CLI.hpp>

#include <cstdio>

#include "app/commands.hpp"
#include "app/set_option.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "study/rule1.hpp"
#include "wear/wear.hpp"

namespace millwear::app {

namespace {

struct Rule1Args {
  std::string scene;
  std::string fidelity;
  std::vector<double> factors;
  double tolerance_pct = 5.0;
  int stages = 1;
  std::vector<std::string> overrides;
};

int run_rule1(const Rule1Args& a) {
  Scene scene = load_scene(a.scene, a.overrides);
  if (!a.fidelity.empty()) apply_fidelity(scene, a.fidelity);
  scene.wear.stages = a.stages;
  check_run_limits(scene, a.scene);  // before anything is filled or written
  std::vector<double> factors = a.factors;
  if (factors.empty()) {
    const double f = scene.wear.factor;
    factors = {0.5 * f, f, 2.0 * f, 10.0 * f};
  }
  const Rule1Report r = rule1_check(scene, factors, a.tolerance_pct);
  std::printf("rule 1 on %s: %d stage(s) of %.0f h, continuous mode\n", scene.name.c_str(), a.stages,
              scene.wear.stage_hours);
  std::printf("%12s %12s %10s %16s %12s\n", "factor", "sim_s", "wall_s", "deviation_mm", "% height");
  for (const auto& row : r.rows) {
    std::printf("%12.3g %12.2f %10.1f %16.3f %12.2f%s\n", row.factor, row.simulated_s, row.wall_s,
                row.deviation_m * 1e3, row.deviation_pct_height, row.events.empty() ? "" : "  (events)");
    for (const auto& e : row.events) std::printf("    %s\n", e.c_str());
  }
  if (r.recommended_factor > 0.0)
    std::printf("recommended factor: %.3g (largest whose profile stays within %.1f%% of the lifter height "
                "of every smaller factor)\n", r.recommended_factor, r.tolerance_pct_height);
  else
    std::printf("no factor passed: even the smallest run reported events\n");
  return r.recommended_factor > 0.0 ? 0 : 1;
}

}  // namespace

void register_rule1(CLI::App& app, Action* action) {
  auto args = std::make_shared<Rule1Args>();
  CLI::App* cmd = app.add_subcommand("rule1", "Check rule 1: scaling C_model by n and time by 1/n gives the same profile");
  cmd->add_option("scene", args->scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--factors", args->factors, "factors C_model/C to compare (default: f/2, f, 2f, 10f)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--tolerance", args->tolerance_pct, "allowed deviation, % of lifter height (default 5)")
      ->check(CLI::Range(1e-6, 100.0));
  cmd->add_option("--stages", args->stages, "stages to run (default 1)")->check(CLI::Range(1, 10000));
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference");
  add_set_option(cmd, &args->overrides);
  cmd->callback([args, action] { *action = [args] { return run_rule1(*args); }; });
}

}  // namespace millwear::app
