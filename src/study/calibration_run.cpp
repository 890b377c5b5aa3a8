// `millwear calibrate` as one call (see calibration_run.hpp).
#include "study/calibration_run.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "scene/fidelity.hpp"
#include "scene/scene_edit.hpp"
#include "study/area_fit.hpp"
#include "study/plan.hpp"
#include "study/profile_fit.hpp"
#include "wear/reshape.hpp"

namespace millwear::validation {

namespace fs = std::filesystem;

namespace {

// The calibrated copy's text: its wear rate reads back as c, and, where the scene file reads
// as a scene by itself, so does the copy as the file it becomes (its profile paths re-pointed
// for its folder). The --set overrides are not in the copy, and are not applied to it: a
// relative profile path among them resolves from the scene's folder, not the copy's.
void check_calibrated_copy(const std::string& text, const std::string& path, const std::string& scene_file, double c) {
  const auto refuse = [&path](const std::string& why) {
    return InputError(path, "wear.wear_rate",
                      "a copy of the scene that reads back with the rate written into it; " + why +
                          ": give the rate as `wear_rate = ...` on a line of its own in [wear]");
  };
  toml::table t;
  try {
    t = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw refuse(std::string("the edited text is not TOML (") + std::string(e.description()) + ")");
  }
  const std::optional<double> rate = t["wear"]["wear_rate"].value<double>();
  if (!rate || std::fabs(*rate / c - 1.0) > 1e-5) throw refuse("the edit did not set wear.wear_rate");
  bool file_alone = true;
  try {
    load_scene(scene_file);
  } catch (const InputError&) {
    file_alone = false;  // valid only with its overrides: nothing more to compare
  }
  if (!file_alone) return;
  const Scene copy = load_scene_text(text, path);
  if (copy.wear.rate_source != WearRateSource::Given || std::fabs(copy.wear.wear_rate_m3_per_J / c - 1.0) > 1e-5)
    throw refuse("the copy reads another wear rate");
}

}  // namespace

CalibrateOutcome calibrate_scene(const CalibrateRequest& a, const CalibrateCallbacks& cb) {
  // An override of a wear-rate key, however written, or of the [wear] table holding it.
  for (const std::string& o : a.overrides)
    for (const char* key : {"wear.wear_rate=1", "wear.area_loss_rate=1", "wear.height_loss_rate=1"})
      if (override_replaces(o, key) || override_replaces(key, o))
        throw InputError(a.scene_file, "--set " + printable(o.substr(0, o.find('=')), 80),
                         "no wear rate on the command line of calibrate: the scene's is its first guess "
                         "and the calibration finds the rate");
  Scene scene = study::load_checked_scene(a.scene_file, a.overrides, a.fidelity, [&a](Scene& s) {
    s.solver.threads = a.threads;
    s.solver.threads_fit_size = a.threads_fit_size;
  });
  check_derived_seeds(scene, static_cast<std::uint64_t>(std::max(1, a.options.replicates)),
                      "--replicates " + std::to_string(a.options.replicates));
  const Measurements measured = read_measurements(a.measured_file);
  check_surveys_in_mill(measured, scene, a.measured_file);
  const double start_h = scene.wear.start_hours;
  if (!measured.areas_only) {
    check_surveys_over_lifter(measured.profiles, new_liner_unit(scene), scene.radius_m(), a.measured_file);
    check_surveys_lose_metal(measured.profiles, new_liner_unit(scene), scene.radius_m(), start_h, a.measured_file,
                             scene.mill.one_lifter_shape());
  }
  check_surveys_from_start(measured, start_h, "the scene's lifters.start_hours", a.measured_file);
  check_surveys_within_stages(measured, scene, std::max(a.options.first_reach, a.options.reach), a.measured_file);
  bool worn = false;
  for (double h : measured.hours()) worn |= h > start_h + kSameHoursTolerance;
  if (!worn)
    throw InputError(a.measured_file, "hours", "at least one survey after the history's start (" +
                                                   io::format_number(start_h) + " h; a worn " +
                                                   (measured.areas_only ? "lifter area" : "profile") +
                                                   ") to calibrate on");
  CalibrateOutcome o;
  o.areas = measured.areas_only;
  if (!o.areas)
    check_surveys_show_wear(measured.profiles, new_liner_unit(scene), scene.radius_m(), start_h, a.measured_file,
                            scene.mill.one_lifter_shape());
  if (o.areas) {
    const double new_area_m2 = measure_lifter(new_liner_unit(scene), scene.radius_m()).area_m2;
    check_areas_shrink(measured.areas, new_area_m2, start_h, a.measured_file, scene.mill.one_lifter_shape());
    check_area_losses_above_noise(measured.areas, new_area_m2, start_h, a.measured_file);
  }
  const std::string stem = fs::path(a.scene_file).stem().string();
  const std::string out_dir = a.out.empty() ? fs::absolute(fs::path(a.scene_file)).parent_path().string() : a.out;
  // Without -o the copy goes next to the scene: that folder is checked now, as -o is, not
  // once the histories have run.
  if (a.out.empty()) {
    try {
      io::check_output_folder(out_dir);
    } catch (const InputError& e) {
      throw InputError(e.file, "-o", e.expected + " (without -o the calibrated copy goes next to the scene: give -o FOLDER)");
    }
  }
  o.scene_out = io::join_path(out_dir, stem + "-calibrated.toml");
  // A folder where a file goes stops the calibration now, not once its histories have run.
  io::check_output_names(out_dir, {stem + "-calibrated.toml"}, "calibrate");
  if (!a.out.empty())
    io::check_output_names(a.out, {"calibration.csv", "calibration_surveys.csv", "calibration_result.csv"},
                           "calibrate");
  // The calibrated copy replaces only an earlier calibrated copy, never a file of the user's.
  if (io::file_exists(o.scene_out) && io::read_file(o.scene_out).rfind(kCalibratedCopyHeader, 0) != 0)
    throw InputError(o.scene_out, a.out.empty() ? "" : "-o",
                     std::string("no file, or one `millwear calibrate` wrote (its first line \"") +
                         kCalibratedCopyHeader + " ...\"), where the calibrated copy of the scene goes; this file "
                         "is another, which the copy would replace: move it, or give another folder with -o");
  // The copy is the scene file's own text with the rate edited: that it can be edited and
  // reads back with a new rate is checked now, with a rate of its own, not after the histories.
  const auto copy_text = [&a, &out_dir](double c, const std::string& note) {
    return calibrated_scene_text(io::read_file(a.scene_file), a.scene_file, {c, note, out_dir});
  };
  check_calibrated_copy(copy_text(1.23457e-11, "a check of the copy"), o.scene_out, a.scene_file, 1.23457e-11);
  // One writer per output folder, for the whole calibration (not the scene's own folder).
  std::optional<io::FolderLock> lock;
  if (!a.out.empty()) lock.emplace(a.out, "calibrate");
  o.options = a.options;
  o.options.min_runs = std::min(a.options.min_runs, a.options.max_runs);
  if (cb.on_start) cb.on_start(scene, measured, o.options);

  const WearCallbacks wear = cb.wear;
  const auto history = [wear](const Scene& s) {
    WearHistory h = run_wear_history(s, wear);
    throw_if_failed(h);  // a lost disk or rule 1's stop: no rate is fitted to it
    return h;
  };
  o.result = o.areas ? calibrate_wear_rate(scene, measured.areas, o.options, cb.on_run, history)
                     : calibrate_wear_rate(scene, measured.profiles, o.options, cb.on_run, history);
  const CalibrationResult& res = o.result;
  // A stop heard after the last history: nothing is written (a stop within one is the
  // history's RunError("interrupted")). Once writing begins the calibration finishes.
  if (cb.wear.should_stop && cb.wear.should_stop()) throw RunError("interrupted");

  io::ensure_dir(out_dir);
  char note[200];
  std::snprintf(note, sizeof note, "calibrated on %s%s: %.4g +- %.2g (k=2)",
                fs::path(a.measured_file).filename().c_str(), o.areas ? " (areas)" : "", res.c_m3_per_J,
                res.expanded_m3_per_J);
  std::string note_text = note;
  // A calibration stopped at --max-runs says so in the file it leaves, not only on the screen.
  if (!res.converged)
    note_text += ", NOT CONVERGED: the best estimate after " + std::to_string(res.runs.size()) + " runs";
  // The copy is the file's own text: overrides the calibration ran with are named, not written.
  for (const std::string& ov : a.overrides) note_text += " --set " + ov;
  if (!a.overrides.empty()) note_text += " (not written into this file)";
  for (char& c : note_text)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';  // the note is one comment line
  // The copy must read back as a valid scene with exactly this C before it is written.
  const std::string text = copy_text(res.c_m3_per_J, note_text);
  try {
    check_calibrated_copy(text, o.scene_out, a.scene_file, res.c_m3_per_J);
  } catch (const InputError& e) {
    throw RunError(std::string(e.what()));
  }
  io::write_file_atomic(o.scene_out, text);
  if (!a.out.empty()) write_calibration_tables(a.out, res, o.areas);
  return o;
}

void write_calibration_tables(const std::string& out, const CalibrationResult& res, bool areas) {
  // rms of the residuals: normal distances (mm) for profiles, area losses (mm^2) for areas.
  io::CsvTable runs({"run", "replicate", "seed", "c_run_m3_per_J", "reached_hours", "scale", "c_estimate_m3_per_J",
                     areas ? "rms_mm2" : "rms_mm", "points", "sigma_scale_curvature", "sigma_scale_spread",
                     "at_bound", "wall_s"});
  // A sigma one residual leaves unknown (infinite in the fit) is an empty cell; so is the
  // spread of the surveys' estimates with one worn survey (no spread to measure).
  const auto sigma = [](double s) { return std::isfinite(s) ? io::CsvCell(s) : io::CsvCell(""); };
  for (const auto& r : res.runs) {
    const io::CsvCell spread = r.fit.survey_scale.size() >= 2 ? sigma(r.fit.sigma_spread) : io::CsvCell("");
    runs.add_row({r.run, r.replicate, static_cast<unsigned long long>(r.seed), r.c_m3_per_J, r.reached_hours, r.fit.scale, r.c_estimate, r.fit.rms * (areas ? 1e6 : 1e3),
                  r.fit.points, sigma(r.fit.sigma_curvature), spread, r.fit.at_bound, r.wall_s});
  }
  runs.write(io::join_path(out, "calibration.csv"));
  io::CsvTable per({"hours", "c_m3_per_J"});
  for (std::size_t j = 0; j < res.survey_c.size(); ++j) per.add_row({res.survey_hours[j], res.survey_c[j]});
  per.write(io::join_path(out, "calibration_surveys.csv"));
  io::CsvTable sum({"c_m3_per_J", "sigma_m3_per_J", "sigma_fit_m3_per_J", "sigma_simulation_m3_per_J",
                    "expanded_m3_per_J", "converged", "runs", "histories_averaged", "fit_on", "fit_error_known"});
  // The fit's error is empty where one residual leaves it unknown (U then counts the
  // simulation's statistics alone), as calibration.csv leaves its curvature scale.
  sum.add_row({res.c_m3_per_J, res.sigma_m3_per_J,
               res.fit_error_known ? io::CsvCell(res.sigma_fit_m3_per_J) : io::CsvCell(""), res.sigma_model_m3_per_J,
               res.expanded_m3_per_J, res.converged, static_cast<int>(res.runs.size()), res.histories_averaged,
               areas ? "area_loss" : "profiles", res.fit_error_known});
  sum.write(io::join_path(out, "calibration_result.csv"));
}

}  // namespace millwear::validation
