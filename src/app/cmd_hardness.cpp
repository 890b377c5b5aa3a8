// `millwear hardness FILE -o OUT`: the ore-hardness correction of operating time
// CT = a * H^b fitted to measured wear per operating period (the paper's Figs. 1 to 3;
// file format and method in study/hardness.hpp).
//
// Outputs in OUT:
//   hardness_periods.csv   period,start,end,length,hardness,wear,rate,ct,corrected_time,
//                          corrected_rate (time in the file's unit, days or hours)
//   hardness_fit.csv       a,a_se,b,b_se,reference_hardness,cv_before,cv_after,mean_rate,
//                          mean_corrected_rate,r_squared,periods,time_unit,wear_column
//   hardness.png/.svg      rate per period before correction, ore hardness, rate after
// Exit codes: 0 done; 1 the figure failed; 2 bad input.
#include <CLI/CLI.hpp>

#include <cstdio>

#include "app/number_checks.hpp"
#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "common/errors.hpp"
#include "io/atomic_write.hpp"
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
  std::printf("coefficient of variation of the wear rate: %.1f%% before, %.1f%% after the correction "
              "(log-log R^2 %.3f)\n", 100.0 * f.cv_before, 100.0 * f.cv_after, f.r_squared);

  const io::FolderLock lock(a.out, "hardness");  // one writer per folder
  io::ensure_dir(io::join_path(a.out, "plots"));
  io::CsvTable t({"period", "start", "end", "length", "hardness", "wear", "rate", "ct", "corrected_time",
                  "corrected_rate"});
  for (const auto& p : data.periods)
    t.add_row({p.label, p.start, p.start + p.length, p.length, p.hardness, p.wear, p.rate, p.ct, p.ct * p.length,
               p.corrected_rate});
  const std::string periods = io::join_path(a.out, "hardness_periods.csv");
  t.write(periods);
  io::CsvTable ft({"a", "a_se", "b", "b_se", "reference_hardness", "cv_before", "cv_after", "mean_rate",
                   "mean_corrected_rate", "r_squared", "periods", "time_unit", "wear_column"});
  ft.add_row({f.a, f.a_se, f.b, f.b_se, f.reference_hardness, f.cv_before, f.cv_after, f.mean_rate,
              f.mean_corrected_rate, f.r_squared, static_cast<int>(data.periods.size()), data.time_unit,
              data.wear_column});
  ft.write(io::join_path(a.out, "hardness_fit.csv"));

  char fit_text[160];
  std::snprintf(fit_text, sizeof fit_text, "CT = %.4g H^%.3g", f.a, f.b);
  char cv_before[32], cv_after[32];
  std::snprintf(cv_before, sizeof cv_before, "%.1f", 100.0 * f.cv_before);
  std::snprintf(cv_after, sizeof cv_after, "%.1f", 100.0 * f.cv_after);
  try {
    const auto files = plots::render_figure(
        plots::script_path("hardness"),
        {{"periods", periods}, {"outbase", io::join_path(a.out, "hardness")}, {"timeunit", data.time_unit},
         {"wearunit", data.wear_column}, {"fit", fit_text}, {"cv_before", cv_before}, {"cv_after", cv_after}},
        io::join_path(a.out, "plots/gnuplot.log"));
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
