// `millwear calibrate SCENE --measured FILE [-o OUT]`: the real wear rate C that makes the
// simulated wear history fit measured lifter profiles (least squares on the signed normal
// distances; study/profile_fit.hpp) or, when the file holds areas only, measured lifter
// areas (least squares on the area loss; study/area_fit.hpp), with its uncertainty
// (study/calibration.hpp), and a copy of the scene with `wear.wear_rate` filled in.
//
// Outputs: OUT/STEM-calibrated.toml (or, without -o, STEM-calibrated.toml next to the
// scene), OUT/calibration.csv (one row per history run), OUT/calibration_surveys.csv (the
// per-survey estimates), OUT/calibration_result.csv. The copy keeps the scene's text and
// comments; only the wear-rate line changes (and the profile path, rewritten relative to the
// copy's folder).
// Exit codes: 0 converged; 1 a run failed or no convergence within --max-runs (the best
// estimate is still written); 2 bad input.
#include <CLI/CLI.hpp>
#include <toml++/toml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "app/validation_common.hpp"
#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "study/area_fit.hpp"
#include "study/area_surveys.hpp"
#include "study/profile_fit.hpp"

namespace millwear::app {

namespace fs = std::filesystem;

namespace {

struct CalibrateArgs {
  std::string scene, measured, out, fidelity;
  int max_runs = 5;
  int min_runs = 2;
  double tolerance_pct = 1.0;
};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// Replace columns [from, to) (1-based, to exclusive) of line `line` (1-based).
void replace_span(std::vector<std::string>& lines, std::size_t line, std::size_t from, std::size_t to,
                  const std::string& with, const std::string& path) {
  if (line == 0 || line > lines.size() || from == 0 || to < from || to - 1 > lines[line - 1].size())
    throw RunError("cannot edit " + path + " at line " + std::to_string(line) + " (unexpected layout)");
  lines[line - 1] = lines[line - 1].substr(0, from - 1) + with + lines[line - 1].substr(to - 1);
}

std::string toml_path_string(const std::string& p) {
  if (p.find('\'') == std::string::npos) return "'" + p + "'";
  return io::json_quote(p);  // basic string escaping is the same for paths
}

// The scene's text with wear.wear_rate = c (replacing whichever wear-rate key it had) and
// the profile path made relative to `out_dir`. Returns the new text.
std::string calibrated_scene_text(const std::string& scene_path, const std::string& out_dir, double c,
                                  const std::string& note) {
  const std::string text = io::read_file(scene_path);
  toml::table t;
  try {
    t = toml::parse(text, scene_path);
  } catch (const toml::parse_error& e) {
    throw InputError(scene_path, "", std::string("a TOML file: ") + e.what());
  }
  std::vector<std::string> lines = split_lines(text);
  // Edits go bottom-up within a line, so columns stay valid: collect, then apply by line.
  struct Edit { std::size_t line, from, to; std::string with; };
  std::vector<Edit> edits;

  toml::table* wear = t["wear"].as_table();
  if (!wear) throw RunError(scene_path + ": no [wear] table to edit");
  bool done = false;
  for (auto&& [k, v] : *wear) {
    const std::string key(k.str());
    if (key != "wear_rate" && key != "area_loss_rate" && key != "height_loss_rate") continue;
    const auto ks = k.source(), vs = v.source();
    if (ks.begin.line != vs.end.line)
      throw RunError(scene_path + ": the wear-rate key and value are not on one line; set wear_rate by hand");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", c);
    edits.push_back({ks.begin.line, ks.begin.column, lines[vs.end.line - 1].size() + 1,
                     std::string("wear_rate = ") + buf + "   # m^3/J, " + note});
    done = true;
  }
  if (!done) throw RunError(scene_path + ": no wear-rate key in [wear] to replace");

  const fs::path scene_dir = fs::absolute(fs::path(scene_path)).parent_path();
  const fs::path target_dir = fs::absolute(fs::path(out_dir));
  if (toml::table* lifters = t["lifters"].as_table()) {
    if (toml::node* prof = lifters->get("profile"); prof && prof->is_string() &&
                                                    fs::weakly_canonical(scene_dir) != fs::weakly_canonical(target_dir)) {
      const fs::path resolved = (scene_dir / fs::path(prof->as_string()->get())).lexically_normal();
      // Relative when the copy stays near the scene (portable with its folder), else absolute.
      std::string rel = fs::relative(resolved, fs::weakly_canonical(target_dir)).string();
      if (rel.rfind("../../", 0) == 0) rel = resolved.string();
      const auto vs = prof->source();
      if (vs.begin.line != vs.end.line) throw RunError(scene_path + ": lifters.profile spans lines");
      edits.push_back({vs.begin.line, vs.begin.column, vs.end.column, toml_path_string(rel.empty() ? resolved.string() : rel)});
    }
  }
  std::sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) {
    return a.line != b.line ? a.line > b.line : a.from > b.from;
  });
  for (const Edit& e : edits) replace_span(lines, e.line, e.from, e.to, e.with, scene_path);

  std::string out = "# Calibrated copy of " + scene_path + " written by millwear calibrate (" + note + ").\n";
  for (const auto& l : lines) out += l + "\n";
  return out;
}

int run_calibrate(const CalibrateArgs& a) {
  Scene scene = load_scene(a.scene);
  if (!a.fidelity.empty()) apply_fidelity(scene, a.fidelity);
  check_run_limits(scene, a.scene);  // before anything is filled or written
  const validation::Measurements measured = validation::read_measurements(a.measured);
  bool worn = false;
  for (double h : measured.hours()) worn |= h > 0.0;
  if (!worn)
    throw InputError(a.measured, "hours", std::string("at least one survey after 0 h (a worn ") +
                                              (measured.areas_only ? "lifter area" : "profile") + ") to calibrate on");
  const bool areas = measured.areas_only;
  if (areas)
    validation::check_areas_shrink(measured.areas, measure_lifter(new_liner_unit(scene), scene.radius_m()).area_m2,
                                   a.measured);

  const std::string stem = fs::path(a.scene).stem().string();
  const std::string out_dir = a.out.empty() ? fs::absolute(fs::path(a.scene)).parent_path().string() : a.out;
  const std::string scene_out = io::join_path(out_dir, stem + "-calibrated.toml");
  // One writer per output folder, for the whole calibration (not the scene's own folder).
  std::optional<io::FolderLock> lock;
  if (!a.out.empty()) lock.emplace(a.out);

  validation::CalibrationOptions opt;
  opt.max_runs = a.max_runs;
  opt.min_runs = std::min(a.min_runs, a.max_runs);
  opt.rel_tol = a.tolerance_pct / 100.0;
  std::printf("calibrate %s against %zu %s in %s (least squares on %s; fidelity %s, up to %d wear histories)\n",
              scene.name.c_str(), measured.count(), areas ? "lifter area(s)" : "profile survey(s)", a.measured.c_str(),
              areas ? "the area loss" : "the normal distances", scene.fidelity.c_str(), opt.max_runs);
  std::fflush(stdout);
  const auto on_run = [areas](const validation::CalibrationRun& r) {
    std::printf("run %d: C = %.4g m^3/J to %.0f h: best fit C = %.4g (x %.4f), rms %.3f %s over %d %s%s (%.1f s)\n",
                r.run, r.c_m3_per_J, r.reached_hours, r.c_estimate, r.fit.scale, r.fit.rms * (areas ? 1e6 : 1e3),
                areas ? "mm^2" : "mm", r.fit.points, areas ? "worn area(s)" : "points",
                r.fit.at_bound ? ", at the end of the history" : "", r.wall_s);
    for (const auto& e : r.events) std::printf("  event: %s\n", e.c_str());
    std::fflush(stdout);
  };
  const auto history = [](const Scene& s) {
    WearHistory h = run_wear_history(s, progress_callbacks());
    throw_if_failed(h);  // a lost disk or rule 1's stop: no rate is fitted to it
    return h;
  };
  const validation::CalibrationResult res =
      areas ? validation::calibrate_wear_rate(scene, measured.areas, opt, on_run, history)
            : validation::calibrate_wear_rate(scene, measured.profiles, opt, on_run, history);

  char fit_sigma[32] = "unknown";
  if (res.fit_error_known) std::snprintf(fit_sigma, sizeof fit_sigma, "%.2g", res.sigma_fit_m3_per_J);
  std::printf("C = %.4g +- %.2g m^3/J (expanded uncertainty, k = 2, about 95%%; standard %.2g: fit %s, "
              "simulation statistics %.2g)%s\n",
              res.c_m3_per_J, res.expanded_m3_per_J, res.sigma_m3_per_J, fit_sigma, res.sigma_model_m3_per_J,
              res.converged ? "" : "  NOT CONVERGED");
  if (res.histories_averaged > 1)
    std::printf("  the mean of the last %d histories' estimates; their spread sets the simulation statistics "
                "when it is the larger\n", res.histories_averaged);
  if (!res.fit_error_known)
    std::printf("  one worn area survey: the fit's own error is unknown, U counts the simulation statistics only "
                "(two or more areas after 0 h give it)\n");
  for (std::size_t j = 0; j < res.survey_c.size(); ++j)
    std::printf("  survey at %.0f h alone: C = %.4g m^3/J\n", res.survey_hours[j], res.survey_c[j]);

  io::ensure_dir(out_dir);
  char note[200];
  std::snprintf(note, sizeof note, "calibrated on %s%s: %.4g +- %.2g (k=2)", fs::path(a.measured).filename().c_str(),
                areas ? " (areas)" : "", res.c_m3_per_J, res.expanded_m3_per_J);
  io::write_file_atomic(scene_out, calibrated_scene_text(a.scene, out_dir, res.c_m3_per_J, note));
  // The copy must read back as a valid scene with exactly this C.
  const Scene check = load_scene(scene_out);
  if (check.wear.rate_source != WearRateSource::Given ||
      std::fabs(check.wear.wear_rate_m3_per_J / res.c_m3_per_J - 1.0) > 1e-5)
    throw RunError(scene_out + ": the calibrated copy does not read back with the calibrated wear rate");

  if (!a.out.empty()) {
    // rms of the residuals: normal distances (mm) for profiles, area losses (mm^2) for areas.
    io::CsvTable runs({"run", "c_run_m3_per_J", "reached_hours", "scale", "c_estimate_m3_per_J",
                       areas ? "rms_mm2" : "rms_mm", "points", "sigma_scale_curvature", "sigma_scale_spread",
                       "at_bound", "wall_s"});
    for (const auto& r : res.runs)
      runs.add_row({r.run, r.c_m3_per_J, r.reached_hours, r.fit.scale, r.c_estimate, r.fit.rms * (areas ? 1e6 : 1e3),
                    r.fit.points, r.fit.sigma_curvature, r.fit.sigma_spread, r.fit.at_bound, r.wall_s});
    runs.write(io::join_path(a.out, "calibration.csv"));
    io::CsvTable per({"hours", "c_m3_per_J"});
    for (std::size_t j = 0; j < res.survey_c.size(); ++j) per.add_row({res.survey_hours[j], res.survey_c[j]});
    per.write(io::join_path(a.out, "calibration_surveys.csv"));
    io::CsvTable sum({"c_m3_per_J", "sigma_m3_per_J", "sigma_fit_m3_per_J", "sigma_simulation_m3_per_J",
                      "expanded_m3_per_J", "converged", "runs", "histories_averaged", "fit_on", "fit_error_known"});
    sum.add_row({res.c_m3_per_J, res.sigma_m3_per_J, res.sigma_fit_m3_per_J, res.sigma_model_m3_per_J,
                 res.expanded_m3_per_J, res.converged, static_cast<int>(res.runs.size()), res.histories_averaged,
                 areas ? "area_loss" : "profiles", res.fit_error_known});
    sum.write(io::join_path(a.out, "calibration_result.csv"));
  }
  std::printf("calibrated scene: %s\n", scene_out.c_str());
  if (!res.converged) {
    std::fprintf(stderr, "millwear: calibration did not converge within %d runs (last factor %.4f)\n", opt.max_runs,
                 res.runs.back().fit.scale);
    return 1;
  }
  return 0;
}

}  // namespace

void register_calibrate(CLI::App& app, Action* action) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate",
      "Fit the real wear rate C to measured lifter profiles or areas; writes a calibrated scene copy");
  cmd->add_option("scene", args->scene, "scene file (TOML); its wear rate is the first guess")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("--measured", args->measured,
                  "measured surveys (CSV): profiles hours,x_mm,y_mm or areas only hours,area_mm2 (see below)")
      ->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder (default: the calibrated scene goes next to SCENE)")
      ->check(output_folder());
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference");
  cmd->add_option("--max-runs", args->max_runs, "wear histories at most (default 5)")->check(CLI::Range(1, 1000));
  cmd->add_option("--min-runs", args->min_runs,
                  "wear histories at least (default 2); every history after the first is an estimate, and C is "
                  "their mean")
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--tolerance", args->tolerance_pct, "stop when the run's C fits within this % (default 1)")
      ->check(CLI::Range(1e-6, 100.0));
  cmd->footer(std::string(kMeasuredFileHelp) +
              "\nProfiles: least squares on the normal distances of every measured point. Areas only: least\n"
              "squares on the area loss of every row after 0 h (two or more such rows give the fit's own\n"
              "error). C is printed with U = 2 sigma (about 95%).");
  cmd->callback([args, action] { *action = [args] { return run_calibrate(*args); }; });
}

}  // namespace millwear::app
