#pragma once
// `millwear calibrate` as one call: a scene file fitted to a measured file (profiles, by the
// normal distances, profile_fit.hpp; or areas alone, by the area loss, area_fit.hpp), then
// the calibrated copy of the scene (scene/scene_edit.hpp) checked by reading it back, and
// the tables of the fit.
//
// Outputs: OUT/STEM-calibrated.toml (without OUT: STEM-calibrated.toml next to the scene),
// and with OUT only: OUT/calibration.csv (one row per history run), OUT/calibration_surveys.csv
// (the per-survey estimates), OUT/calibration_result.csv. Nothing here prints: progress
// comes through the callbacks. OUT is locked (io/folder_lock.hpp) while the calibration
// runs.
#include <functional>
#include <string>

#include "study/area_surveys.hpp"
#include "study/calibration.hpp"
#include "wear/wear.hpp"

namespace millwear::validation {

struct CalibrateRequest {
  std::string scene_file, measured_file;
  std::string out;               // "": the copy goes next to the scene, no tables
  std::string fidelity;          // "": the scene's own
  int threads = 1;               // threads of the engine's step (results do not depend on it)
  bool threads_fit_size = false; // at most: as many as the charge's size uses (SolverDef)
  // --set KEY=VALUE (scene/scene.hpp); not the wear rate, which the calibration finds. The
  // calibrated copy is the file's text: its header comment lists them, they are not in it.
  std::vector<std::string> overrides;
  CalibrationOptions options;    // min_runs is capped at max_runs
};

struct CalibrateCallbacks {
  // Once the inputs are read and checked, before the first history.
  std::function<void(const Scene&, const Measurements&, const CalibrationOptions&)> on_start;
  std::function<void(const CalibrationRun&)> on_run;  // after every history
  // Every history's stages. Its should_stop is also asked after the last history: a stop
  // then throws RunError("interrupted") as a history's does, before anything is written.
  WearCallbacks wear;
};

struct CalibrateOutcome {
  bool areas = false;            // fitted on areas alone
  CalibrationResult result;
  CalibrationOptions options;    // as used
  std::string scene_out;         // the calibrated copy
};

// Throws InputError for a bad scene (or one outside the run limits) or measured file, a file
// with no survey after 0 h, areas that do not shrink, or a folder where an output file goes;
// RunError when a history fails (a lost disk or rule 1's stop included) or is stopped
// (wear.should_stop), or the copy does not read back with the calibrated C.
CalibrateOutcome calibrate_scene(const CalibrateRequest& request, const CalibrateCallbacks& callbacks = {});

// The three tables above, in `out`; rms in mm for profiles, mm^2 for areas.
void write_calibration_tables(const std::string& out, const CalibrationResult& result, bool areas);

}  // namespace millwear::validation
