// `millwear tradeoff SCENE -o OUT [--quick] [--only LABELS] [--stages N] [--stage-hours H] [--jobs J]`:
// the wear history of one design, or of every design of a comparison file, over the
// fidelity ladder (study/tradeoff.hpp), each run measured against the reference run.
//
// Writes, atomically:
//   OUT/tradeoff.csv          one row per setting: costs (summed over the designs), errors
//                             (the worst design), comparison order, Pareto flag
//   OUT/tradeoff_designs.csv  one row per setting and design: final area, height, life,
//                             its own profile and life errors
//   OUT/tradeoff_front.csv    the Pareto-front rows by CPU time (the figure's front line)
//   OUT/tradeoff_profiles.csv final unit surface of every setting (label, design, x_mm, y_mm)
//   OUT/tradeoff.md           the table as Markdown, with the run's settings
//   OUT/tradeoff.png, .svg    error against wall time (plots/tradeoff.gp), front marked
// Exit codes: 0 done; 1 the reference run failed or the figure failed; 2 bad input.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "study/plan.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "study/tradeoff.hpp"

namespace millwear::app {

namespace {

struct TradeoffArgs {
  std::string scene;
  std::string out;
  bool quick = false;
  int stages = 0;
  double stage_hours = 0.0;
  int jobs = 1;
  bool no_plot = false;
  std::vector<std::string> only;
};

std::string fmt(double v, const char* f = "%.2f") {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

void write_outputs(const TradeoffReport& r, const std::string& out) {
  io::CsvTable t({"label", "knob", "value", "wall_s", "cpu_s", "speedup", "disk_steps", "simulated_s", "dev_max_mm",
                  "dev_max_pct", "dev_mean_mm", "dev_mean_pct", "area_err_pct", "power_err_pct", "life_err_pct",
                  "life_order_same", "life_ratio_err_pct", "events", "error", "pareto"});
  io::CsvTable per({"label", "design", "final_hours", "final_area_mm2", "final_height_mm", "life_h",
                    "life_extrapolated", "dev_max_pct", "life_err_pct"});
  io::CsvTable front({"label", "cpu_s", "wall_s", "dev_max_pct", "dev_mean_pct"});
  io::CsvTable prof({"label", "design", "x_mm", "y_mm"});
  std::vector<const TradeoffRow*> on_front;
  for (const auto& row : r.rows) {
    t.add_row({row.label, row.knob, row.value, row.wall_s, row.cpu_s, row.speedup, static_cast<long long>(row.disk_steps),
               row.simulated_s, row.dev_max_mm, row.dev_max_pct, row.dev_mean_mm, row.dev_mean_pct,
               row.area_err_pct, row.power_err_pct, row.life_err_pct, row.life_order_same, row.life_ratio_err_pct,
               static_cast<long long>(row.events.size()), row.error, row.pareto});
    if (row.pareto) on_front.push_back(&row);
    for (const auto& d : row.designs) {
      per.add_row({row.label, d.name, d.final_hours, d.final_area_mm2, d.final_height_mm, d.life_h,
                   d.life_extrapolated, d.dev_max_pct, d.life_err_pct});
      for (const Vec2& p : d.final_profile) prof.add_row({row.label, d.name, p.x * 1e3, p.y * 1e3});
    }
  }
  std::sort(on_front.begin(), on_front.end(), [](auto* a, auto* b) { return a->cpu_s < b->cpu_s; });
  for (const auto* row : on_front)
    front.add_row({row->label, row->cpu_s, row->wall_s, row->dev_max_pct, row->dev_mean_pct});
  t.write(out + "/tradeoff.csv");
  per.write(out + "/tradeoff_designs.csv");
  front.write(out + "/tradeoff_front.csv");
  prof.write(out + "/tradeoff_profiles.csv");

  const bool several = r.design_names.size() > 1;
  std::ostringstream md;
  md << "Scene `" << r.scene_name << "`, " << r.stages << " stage(s) of " << r.stage_hours << " h; new lifter";
  for (std::size_t k = 0; k < r.design_names.size(); ++k)
    md << (k ? "," : "") << " " << (several ? r.design_names[k] + " " : "") << fmt(r.lifter_height_m[k] * 1e3, "%.1f")
       << " mm high, " << fmt(r.lifter_area_m2[k] * 1e6, "%.0f") << " mm^2";
  md << ". Errors against `reference`" << (several ? ", the worst design; CPU and wall time summed over the designs" : "")
     << ".\n\n";
  md << "| setting | CPU (s) | wall (s) | speed-up | profile dev. max (mm / % h) | mean (mm / % h) | area err (% A0) "
        "| power err (%) | life (h) | life err (%) | "
     << (several ? "order same | life ratio err (%) | " : "") << "events | front |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|" << (several ? "---|---|" : "") << "---|---|\n";
  for (const auto& row : r.rows) {
    std::string lives;
    for (const auto& d : row.designs)
      lives += (lives.empty() ? "" : " / ") + fmt(d.life_h, "%.0f") + (d.life_extrapolated ? "*" : "");
    md << "| " << row.label << " | " << fmt(row.cpu_s, "%.0f") << " | " << fmt(row.wall_s, "%.0f") << " | "
       << fmt(row.speedup, "%.1f") << "x | " << fmt(row.dev_max_mm, "%.1f") << " / " << fmt(row.dev_max_pct, "%.1f")
       << " | " << fmt(row.dev_mean_mm, "%.1f") << " / " << fmt(row.dev_mean_pct, "%.1f") << " | "
       << fmt(row.area_err_pct) << " | " << fmt(row.power_err_pct, "%.1f") << " | " << lives << " | "
       << fmt(row.life_err_pct, "%.1f") << " | ";
    if (several)
      md << (row.error.empty() ? (row.life_order_same ? "yes" : "NO") : "-") << " | "
         << fmt(row.life_ratio_err_pct, "%.1f") << " | ";
    md << (row.error.empty() ? std::to_string(row.events.size()) : "failed") << " | " << (row.pareto ? "yes" : "")
       << " |\n";
  }
  md << "\nSpeed-up: reference CPU time / CPU time. * life extrapolated beyond the simulated stages.";
  if (several)
    md << " Life is listed per design (" << r.scene_name << "); order same: the designs come out in the "
       << "reference's order of life; life ratio err: error of each design's life relative to the first's.";
  md << "\n";
  for (const auto& row : r.rows)
    if (row.knob == "seed" && row.label.rfind("reference", 0) == 0 && row.error.empty())
      md << "\nNoise floor: `" << row.label << "` (the reference's numerics, the charge's noise drawn again) "
         << "deviates " << fmt(row.dev_max_pct, "%.1f") << "% of the lifter height at the worst point and "
         << fmt(row.dev_mean_pct, "%.1f") << "% on average, area " << fmt(row.area_err_pct)
         << "%, life " << fmt(row.life_err_pct, "%.1f")
         << "%: a setting closer to the reference than that cannot be told from it.\n";
  for (const auto& h : r.held_knobs) md << "\nHeld: " << h;
  if (!r.held_knobs.empty()) md << "\n";
  io::write_file_atomic(out + "/tradeoff.md", md.str());
}

int run_tradeoff_cmd(const TradeoffArgs& a) {
  // A scene or a comparison file; InputError -> exit 2 before anything is written.
  const std::vector<Scene> designs = study::load_designs(a.scene);
  TradeoffOptions o;
  o.quick = a.quick;
  o.stages = a.stages;
  o.stage_hours = a.stage_hours;
  o.only = a.only;
  const TradeoffLadder ladder = tradeoff_ladder(designs, o);
  const io::FolderLock lock(a.out);  // one writer per folder, for the whole run
  const Scene& first = ladder.settings.front().scenes.front();
  std::printf("tradeoff on %zu design(s): %zu settings, %d stage(s) of %g h, %d job(s)\n", designs.size(),
              ladder.settings.size(), first.wear.stages, first.wear.stage_hours, a.jobs);
  for (const auto& h : ladder.held_knobs) std::printf("  held: %s\n", h.c_str());
  std::fflush(stdout);
  TradeoffCallbacks cb;
  cb.on_design = [](const TradeoffSetting& s, const TradeoffDesign& d, double wall, double cpu,
                    const std::string& error) {
    if (error.empty())
      std::printf("  done   %-24s %-12s %8.1f s (CPU %.1f s)  final area %.0f mm^2, height %.1f mm\n",
                  s.label.c_str(), d.name.c_str(), wall, cpu, d.final_area_mm2, d.final_height_mm);
    else
      std::printf("  failed %-24s %8.1f s  %s\n", s.label.c_str(), wall, error.c_str());
    std::fflush(stdout);
  };
  const TradeoffReport report = run_tradeoff(ladder, a.jobs, cb);
  write_outputs(report, a.out);

  std::printf("\n%-24s %9s %9s %8s %10s %8s %10s %9s %9s %8s %6s %6s\n", "setting", "cpu_s", "wall_s", "speedup",
              "dev_max_mm", "%height", "dev_mean%", "area_err%", "power%", "life%", "order", "front");
  for (const auto& r : report.rows)
    std::printf("%-24s %9s %9s %8s %10s %8s %10s %9s %9s %8s %6s %6s\n", r.label.c_str(), fmt(r.cpu_s, "%.1f").c_str(),
                fmt(r.wall_s, "%.1f").c_str(), fmt(r.speedup, "%.2f").c_str(), fmt(r.dev_max_mm).c_str(),
                fmt(r.dev_max_pct).c_str(), fmt(r.dev_mean_pct).c_str(), fmt(r.area_err_pct).c_str(),
                fmt(r.power_err_pct).c_str(), fmt(r.life_err_pct).c_str(),
                r.designs.size() < 2 ? "-" : (r.life_order_same ? "same" : "DIFF"), r.pareto ? "*" : "");
  std::printf("wrote %s/tradeoff.csv, tradeoff_designs.csv, tradeoff_front.csv, tradeoff_profiles.csv, tradeoff.md\n",
              a.out.c_str());
  if (a.no_plot) return 0;
  try {
    plots::render_figure(plots::script_path("tradeoff"),
                         {{"datadir", a.out}, {"outbase", a.out + "/tradeoff"}}, a.out + "/gnuplot.log");
    std::printf("wrote %s/tradeoff.png, tradeoff.svg\n", a.out.c_str());
  } catch (const RunError& e) {
    std::fprintf(stderr, "millwear: figure failed: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace

void register_tradeoff(CLI::App& app, Action* action) {
  auto args = std::make_shared<TradeoffArgs>();
  CLI::App* cmd = app.add_subcommand(
      "tradeoff", "Speed against accuracy: the wear history over a ladder of fidelity settings, against reference");
  cmd->add_option("scene", args->scene, "scene file of one design, or a comparison file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_flag("--quick", args->quick, "the three presets only (no one-knob ladder)");
  cmd->add_option("--stages", args->stages, "stages to run (default: the scene's)")->check(CLI::Range(1, 10000));
  cmd->add_option("--stage-hours", args->stage_hours, "hours per stage (default: the scene's)")
      ->check(CLI::Range(1.0, 1e6));
  cmd->add_option("-j,--jobs", args->jobs, "runs (setting x design) at once (default 1; wall times then share the cores)")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--no-plot", args->no_plot, "skip the figure");
  cmd->add_option("--only", args->only,
                  "run only these settings, by label (comma-separated, e.g. \"standard,standard seed=2\"); "
                  "the reference always runs")
      ->delimiter(',');
  cmd->callback([args, action] { *action = [args] { return run_tradeoff_cmd(*args); }; });
}

}  // namespace millwear::app
