#pragma once
// Measured against simulated lifter profiles (the paper's Fig. 4), and the calibration of
// the real wear rate C from measured surveys.
//
// Simulated profile at any operating hours. A wear history has profiles at its stage
// hours only. At a survey's hours that falls on a stage, the stage's exact geometry is
// used; between two stages every vertex of the earlier profile moves along its normal
// into the metal toward the later profile, by the fraction of the interval elapsed
// (linear in time: within a stage the staged loop advances at a nearly constant wear rate,
// so depth is close to linear in hours). Fresh runs made by `validate` and `calibrate`
// put stage boundaries at the survey hours when the survey hours share a common step, so
// interpolation is only needed for a finished run (`--from`) with other stage hours.
//
// Distances. The normal distance of a measured point is its shortest distance to the
// simulated profile, signed: positive when the measured point lies on the charge side of
// the simulated surface (the simulation wore deeper than measured there), negative in the
// metal. Mean (of absolute values) and largest are over the measured points, in mm and in
// % of the new lifter's height.
//
// Calibration of C: by time scaling one history (calibration.hpp, shared with the fit on
// areas alone), on the signed normal distances of every measured point of the worn surveys.
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "study/calibration.hpp"
#include "study/surveys.hpp"
#include "wear/wear.hpp"

namespace millwear::validation {

// Lifter-local profiles of unit 0 at increasing operating hours.
struct ProfileHistory {
  std::vector<double> hours;
  std::vector<Polyline> surfaces;   // whole liner unit surfaces, m
  double last_hours() const { return hours.empty() ? 0.0 : hours.back(); }
  bool covers(double h) const { return !hours.empty() && h >= hours.front() - kSameHoursTolerance && h <= last_hours() + kSameHoursTolerance; }
  // Exact stage geometry within 1e-6 h of a stage, otherwise the normal interpolation
  // above. Precondition: covers(h), or h up to extrapolation_limit() (the calibration
  // only): beyond the last stage the last interval's motion is continued.
  Polyline profile_at(double h) const;
  // The calibration may look this far past the last stage (validation::extrapolation_limit).
  double extrapolation_limit() const { return validation::extrapolation_limit(hours); }
};
ProfileHistory profile_history(const std::vector<StageRecord>& stages);

// The profile between a and b at fraction f in [0, 1]: vertices of a moved along their
// normals toward b (ray to b; the nearest point of b where the ray misses).
Polyline interpolate_profile(const Polyline& a, const Polyline& b, double f);

// Signed shortest distance from p to a lifter-local surface running toward +x (positive on
// the charge side, above it).
double signed_distance(Vec2 p, const Polyline& surface);

// Metal area above the original shell line y = 0 between x_from and x_to, under a
// lifter-local surface, with the polar map's correction (as measure_lifter).
double area_between(const Polyline& surface, double x_from, double x_to, double radius_m);

struct ProfileComparison {
  double hours = 0.0;
  int points = 0;
  double mean_distance_m = 0.0;     // mean |signed distance| over measured points
  double max_distance_m = 0.0;      // largest |signed distance|
  double bias_m = 0.0;              // mean signed distance (+: simulation wore deeper)
  double mean_pct_height = 0.0;     // of the new lifter's height
  double max_pct_height = 0.0;
  double measured_area_m2 = 0.0;    // over the measured x span (area_between)
  double simulated_area_m2 = 0.0;   // same span
  double area_error_m2 = 0.0;       // simulated - measured
  double area_error_pct = 0.0;      // of the new lifter's area over the same span
};
ProfileComparison compare_profile(const Survey& measured, const Polyline& simulated, double radius_m,
                                  double new_height_m, const Polyline& new_surface);

// Every survey spans part of the new lifter (`new_unit`, the scene's): the new lifter has
// metal between the survey's ends, of which a survey's area error is a share. Throws
// InputError(file, "line N", ...) naming the first survey beside the lifter.
void check_surveys_over_lifter(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double radius_m,
                               const std::string& file);

// Wear removes metal: throws InputError(file, "line N", ...) naming a survey after the start
// (start_hours) that has more metal than the lifter at the start, over the span both cover,
// by more than kGainNoiseShare of the new lifter's area (`new_unit`, the scene's lifter at the
// history's start). The lifter at the start is the survey there, else the scene's lifter
// (then kGainNoiseShare + kCastOverDrawingShare: a casting may be bigger than drawn).
// Later surveys are not compared with each other (noise and the spread between lifters may
// beat the wear between two of them). The mirror of check_areas_shrink's check for area files.
// A survey after the start with under kWornOutFraction (wear/life.hpp) of the start's metal over
// that span has lost the lifter, which ends a history: refused too, naming its line.
// one_shape = false (a pattern of lifters of other shapes, Scene::mill.one_lifter_shape): a
// survey may be of any of them, so without a survey at the start there is no reference and
// nothing is checked.
void check_surveys_lose_metal(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double radius_m,
                              double start_hours, const std::string& file, bool one_shape = true);

// A wear rate is fitted to the metal the surveys lost: throws InputError(file, "line N", ...),
// N the last survey's line, if the surveys after the start (start_hours) lost none against the
// lifter at the start (taken as by check_surveys_lose_metal) over the spans they share with it:
// their losses, each times its hours since the start, summed, not above 0 (surveys of a
// lifter that did not wear, or copies of the survey at the start). The mirror of
// check_areas_shrink's check on area losses. Then, as check_area_losses_above_noise does for
// areas, throws at the line of the survey that lost the most unless it lost more than
// kGainNoiseShare of the new lifter's area. Nothing is checked without a reference (a
// pattern's surveys with no survey at the start) or without a later survey over the lifter.
void check_surveys_show_wear(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double radius_m,
                             double start_hours, const std::string& file, bool one_shape);

// The survey version of calibration.hpp's common_stage_hours.
double common_stage_hours(const std::vector<Survey>& surveys, int max_stages = kMaxCommonStages);

// ---- calibration ----

// Least-squares time scale s of one history against the surveys (worn surveys only: after
// the history's start; residuals: signed normal distances, m). C = s * C_run. Throws
// InputError("", "surveys", ...) if no survey is after the start (nothing to fit).
ScaleFit fit_time_scale(const ProfileHistory& history, const std::vector<Survey>& surveys);

// Runs wear histories of `scene` (its C as the first guess) until the C fitted on the
// profiles agrees with the run's own C (calibrate_by_time_scale).
CalibrationResult calibrate_wear_rate(
    const Scene& scene, const std::vector<Survey>& surveys, const CalibrationOptions& options = {},
    const std::function<void(const CalibrationRun&)>& on_run = {},
    const std::function<WearHistory(const Scene&)>& run_history = {});

}  // namespace millwear::validation
