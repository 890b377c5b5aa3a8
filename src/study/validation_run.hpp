#pragma once
// `millwear validate` as one call: measured lifter profiles (the paper's Fig. 4), or
// measured lifter areas alone, against the simulated wear history, with the tables, the
// simulated surveys and the figure.
//
// The history is either run here (stage boundaries on the survey hours when they share a
// common step, calibration.hpp) or read from a finished `millwear run` folder (`from`: its
// exact stage geometry, FROM/stages/DESIGN_stageK.units.csv, for the design named by the
// scene). Outputs in OUT:
// profiles:
//   validation.csv               one row per survey: distances (mm, % of the new lifter's
//                                height), bias, areas and area error
//   simulated_surveys.csv        the simulated profiles at the survey hours, in the survey
//                                format (hours,x_mm,y_mm), lifter region only
//   plots/validate_measured.dat, plots/validate_simulated.dat   gnuplot blocks
//   validate_profiles.png/.svg   measured (dashed) against simulated (solid)
// areas only:
//   validation.csv               one row per survey row: measured and simulated area and
//                                area loss, their errors (mm^2, % of the new lifter's area,
//                                % of the measured loss)
//   simulated_areas.csv          the simulated areas at the survey hours (hours,area_mm2)
//   plots/validate_area_measured.csv, plots/validate_area_simulated.csv (every stage)
//   validate_areas.png/.svg      measured points on the simulated area history
// OUT is locked (io/folder_lock.hpp) from the history to the figure. The files are drawn up in
// OUT/.millwear-staging and moved into OUT once all are complete (io/staging.hpp): until then
// an earlier validation's files stay as they were. Nothing here prints: the history's
// progress comes through the callbacks, the comparison in the outcome.
#include <functional>
#include <string>
#include <vector>

#include "study/area_fit.hpp"
#include "study/area_surveys.hpp"
#include "study/profile_fit.hpp"
#include "wear/wear.hpp"

namespace millwear::validation {

struct ValidateRequest {
  std::string scene_file, measured_file, out;
  std::string from;        // a finished `millwear run` folder, or "" to run the history
  std::string fidelity;    // "": the scene's own
  int threads = 1;         // threads of the engine's step (results do not depend on it)
  bool threads_fit_size = false;  // at most: as many as the charge's size uses (SolverDef)
  std::vector<std::string> overrides;  // --set KEY=VALUE (scene/scene.hpp)
  std::string commit;      // the program's, for OUT/manifest.json
};

// Where the history comes from, known before it is read or run.
struct HistorySource {
  bool from_run = false;
  int last_stage = 0;          // from a run: stages 0..last_stage are read
  double reached_hours = 0.0;  // from a run: the hours of its last stage
  // From a run of --replicates N: its N histories (DESIGN, DESIGN.r2, ...), of which the first
  // (the scene's seed) is compared; its summary.csv gives their mean.
  int histories = 1;
  Scene scene;                 // a fresh history: the scene it runs (stages on the survey hours)
};

struct ValidateCallbacks {
  std::function<void(const Scene&, const Measurements&, const HistorySource&)> on_history;
  // A fresh history's stages. Its should_stop is also asked once the files are drawn up: a
  // stop then throws RunError("interrupted") as the history's does, before OUT is touched.
  WearCallbacks wear;
  std::function<void(const std::string&)> on_event;  // a fresh history's events, once it ran
};

struct ValidateOutcome {
  bool areas_only = false;
  std::vector<ProfileComparison> profiles;   // one per survey (profiles)
  std::vector<AreaComparison> areas;         // one per survey row (areas only)
  double new_height_m = 0.0;                 // profiles: the scale of the % columns
  double new_area_m2 = 0.0;                  // areas: the simulated new lifter's area
  MeasuredAreas measured_areas;              // areas: the reference of the losses
  std::string files_note;                    // the tables written, for the caller's message
  std::vector<std::string> files;            // the tables and the figure's data written into OUT
  std::vector<std::string> figure_files;     // the figure drawn (empty when it was not)
  std::string figure_error;                  // why not
  bool figure_failed = false;                // gnuplot is installed and failed
};

// Throws InputError for bad input (scene, or one outside the run limits, measured file, a
// --from folder without the design or with surveys beyond its last stage, a folder in OUT
// where a file goes), RunError when the history fails (a lost disk or rule 1's stop
// included), ends before the last survey, or is stopped (wear.should_stop).
ValidateOutcome validate_scene(const ValidateRequest& request, const ValidateCallbacks& callbacks = {});

// A gnuplot data block: a title line "TITLE,-" then x_mm,y_mm rows; blocks are separated
// by two blank lines (gnuplot `index`).
std::string profile_block(const std::string& title, const Polyline& line_m, bool first);

}  // namespace millwear::validation
