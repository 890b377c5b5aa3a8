// `millwear hardness FILE -o OUT`: the ore-hardness correction of operating time
// CT = a * H^b fitted to measured wear per operating period (the paper's Figs. 1 to 3;
// file format and method in study/hardness.hpp).
// Outputs in OUT (study/hardness.hpp): hardness_periods.csv, hardness_fit.csv and the figure
// hardness.png/.svg.
// Exit codes: 0 done; 1 the figure failed; 2 bad input.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "app/number_checks.hpp"
#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "study/hardness.hpp"

namespace millwear::app {

namespace {

struct HardnessArgs {
  std::string file, out;
  double reference_hardness = 0.0;
};

int run_hardness(const HardnessArgs& a) {
  validation::HardnessData data = validation::read_hardness(a.file);
  const validation::HardnessFit f = validation::fit_hardness(data, a.reference_hardness);
  const std::string unit = data.time_unit == "days" ? "day" : "h";
  // The folder before any result is printed: a refused folder is exit 2 with nothing shown.
  const io::FolderLock lock(a.out, "hardness");  // one writer per folder
  io::check_output_names(a.out, {"hardness_periods.csv", "hardness_fit.csv", "hardness.png", "hardness.svg",
                                 "plots/gnuplot.log"}, "hardness");

  std::printf("hardness correction CT = a * H^b from %zu periods in %s (wear: %s)\n", data.periods.size(),
              a.file.c_str(), data.wear_column.c_str());
  std::printf("%8s %10s %10s %10s %12s %8s %14s\n", "period", data.time_unit.c_str(), "hardness", "wear",
              ("rate/" + unit).c_str(), "CT", ("corr rate/" + unit).c_str());
  for (const auto& p : data.periods)
    std::printf("%8s %10.4g %10.4g %10.4g %12.4g %8.4f %14.4g\n", p.label.c_str(), p.length, p.hardness, p.wear,
                p.rate, p.ct, p.corrected_rate);
  std::printf("a = %.5g +- %.2g, b = %.4g +- %.2g (standard errors; %s)\n", f.a, f.a_se, f.b, f.b_se,
              f.reference_hardness > 0.0
                  ? ("CT = 1 at hardness " + io::format_number(f.reference_hardness)).c_str()
                  : "a normalised so the corrected total time equals the actual total time");
  char r_squared[64];
  if (std::isfinite(f.r_squared)) std::snprintf(r_squared, sizeof r_squared, "log-log R^2 %.3f", f.r_squared);
  else std::snprintf(r_squared, sizeof r_squared, "no log-log R^2: the rates do not vary");
  std::printf("coefficient of variation of the wear rate: %.1f%% before, %.1f%% after the correction (%s)\n",
              100.0 * f.cv_before, 100.0 * f.cv_after, r_squared);

  validation::write_hardness_outputs(a.out, data, f);
  // An earlier figure is of earlier data: gone before this one is drawn, so that a figure
  // that fails leaves none beside the new tables.
  for (const char* figure : {"hardness.png", "hardness.svg"}) {
    std::error_code ec;
    std::filesystem::remove(io::join_path(a.out, figure), ec);
  }
  try {
    const auto files = validation::render_hardness_figure(a.out, data, f);
    std::printf("results in %s (hardness_periods.csv, hardness_fit.csv); figure %s\n", a.out.c_str(),
                files.empty() ? "-" : files.front().c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "millwear: warning: figure: %s\n", e.what());
    std::printf("results in %s (hardness_periods.csv, hardness_fit.csv)\n", a.out.c_str());
    if (plots::gnuplot_available()) return 1;
  }
  return 0;
}

}  // namespace

void register_hardness(CLI::App& app, Action* action) {
  auto args = std::make_shared<HardnessArgs>();
  CLI::App* cmd = app.add_subcommand(
      "hardness", "Fit the ore-hardness correction CT = a*H^b to measured wear per period (paper Figs. 1-3)");
  cmd->add_option("file", args->file, "CSV: period,days|hours,<wear column>,hardness")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--reference-hardness", args->reference_hardness,
                  "normalise a so that CT = 1 at this hardness (default: corrected total time = actual)")
      ->check(finite_positive());
  cmd->callback([args, action] { *action = [args] { return run_hardness(*args); }; });
}

}  // namespace millwear::app
