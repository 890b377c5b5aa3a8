#pragma once
// Measured lifter areas against the simulated history, and the calibration of the real wear
// rate C on area loss alone (when a survey kept the areas, not the profiles).
//
// Simulated area at any operating hours: the lifter area of row 0 (StageRecord::lifter) at
// the stages, exact within 1e-6 h of a stage and linear in hours between two stages (as the
// profiles are interpolated, profile_fit.hpp: within a stage the staged loop wears at a
// nearly constant rate).
//
// Comparison: per area survey, simulated against measured area (error in mm^2 and in % of
// the new lifter's simulated area) and simulated against measured area loss (error in % of
// the measured loss), the measured loss as area_surveys.hpp defines it.
//
// Calibration (calibration.hpp): least squares on the area losses of the worn surveys,
// residual r_j(s) = [A_sim(0) - A_sim(s h_j)] - L_j (m^2; > 0: the simulation wore more),
// the history read at s h_j as for the profiles. Each row is one residual, so the errors
// (a) and (b) need two worn rows or more; with one, only the simulation's statistics (c)
// are counted (CalibrationResult::fit_error_known = false).
#include <functional>
#include <vector>

#include "scene/scene.hpp"
#include "study/area_surveys.hpp"
#include "study/calibration.hpp"
#include "wear/wear.hpp"

namespace millwear::validation {

// Lifter areas of row 0 at increasing operating hours.
struct AreaHistory {
  std::vector<double> hours;
  std::vector<double> area_m2;
  double last_hours() const { return hours.empty() ? 0.0 : hours.back(); }
  bool covers(double h) const { return !hours.empty() && h >= hours.front() - kSameHoursTolerance && h <= last_hours() + kSameHoursTolerance; }
  double new_area_m2() const { return area_m2.empty() ? 0.0 : area_m2.front(); }  // at the start
  double start_hours() const { return hours.empty() ? 0.0 : hours.front(); }
  // Exact at a stage, linear between stages. Precondition: covers(h), or h up to
  // extrapolation_limit() (the calibration only): beyond the last stage the last
  // interval's slope is continued (and clamped at the limit).
  double area_at(double h) const;
  double extrapolation_limit() const { return validation::extrapolation_limit(hours); }
};
AreaHistory area_history(const std::vector<StageRecord>& stages);

struct AreaComparison {
  double hours = 0.0;
  std::size_t line = 0;             // of the survey row in its file
  double measured_area_m2 = 0.0;    // as given, or A_ref - loss for area_loss_mm2 files
  double simulated_area_m2 = 0.0;
  double area_error_m2 = 0.0;       // simulated - measured
  double area_error_pct = 0.0;      // of the new lifter's simulated area
  double measured_loss_m2 = 0.0;    // area_surveys.hpp's reference rule
  double simulated_loss_m2 = 0.0;   // A_sim(0) - A_sim(h)
  double loss_error_m2 = 0.0;       // simulated - measured
  double loss_error_pct = 0.0;      // of the measured loss; NaN where that is 0, and at the start
};
// One comparison per survey row (file order). Precondition: history.covers(every hours).
std::vector<AreaComparison> compare_areas(const AreaSurveys& surveys, const AreaHistory& history);

// Least-squares time scale s of one history against the worn area surveys (after the
// history's start; residuals: area losses, m^2). C = s * C_run. Throws
// InputError("", "surveys", ...) if no survey is after the start.
ScaleFit fit_time_scale(const AreaHistory& history, const AreaSurveys& surveys);

// Runs wear histories of `scene` (its C as the first guess) until the C fitted on the area
// losses agrees with the run's own C (calibrate_by_time_scale).
CalibrationResult calibrate_wear_rate(
    const Scene& scene, const AreaSurveys& surveys, const CalibrationOptions& options = {},
    const std::function<void(const CalibrationRun&)>& on_run = {},
    const std::function<WearHistory(const Scene&)>& run_history = {});

}  // namespace millwear::validation
