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
// Calibration of C. In the staged loop the lifter geometry depends on C and the operating
// time t almost only through the product C t (depth = C x work / area, and the loop steps by
// depth), so the history run with C_run predicts the profile for C = s C_run at hours h as
// its own profile at s h. A 1D search on s (a log-spaced scan, then golden section) over
// one history gives the least-squares s; a new history at C = s C_run removes what the
// time-scaling misses (reversal times, stage restarts), and the loop stops when s is 1
// within a tolerance. Uncertainty: the larger of (a) the Gauss-Newton standard error from
// the curvature of the misfit, sigma_s^2 = (RSS / (n - 1)) / sum (d r_i / d s)^2, and (b)
// the standard error of the mean of the per-survey estimates (with two or more worn
// surveys), which catches correlated residuals that (a) treats as independent; combined in
// quadrature with (c) the statistical error of the simulation itself: the wear up to the
// last survey is a sum over N measuring windows whose rates carry the batch-means relative
// error of rule 2 (StageRecord::area_loss_rate_rel_sem, about 7-10% per lab-mill window), so
// one history's cumulative wear, and hence C, is uncertain by sqrt(sum n_k sem_k^2) / N.
// It is reported as an expanded uncertainty U = 2 sigma (about 95%). A round trip on
// simulated surveys carries (c) twice (the surveys are one realisation, the fit another):
// there the difference may reach about sqrt(2) U.
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "validation/surveys.hpp"
#include "wear/wear.hpp"

namespace millwear::validation {

// Lifter-local profiles of unit 0 at increasing operating hours.
struct ProfileHistory {
  std::vector<double> hours;
  std::vector<Polyline> surfaces;   // whole liner unit surfaces, m
  double last_hours() const { return hours.empty() ? 0.0 : hours.back(); }
  bool covers(double h) const { return !hours.empty() && h >= hours.front() - 1e-6 && h <= last_hours() + 1e-6; }
  // Exact stage geometry within 1e-6 h of a stage, otherwise the normal interpolation
  // above. Precondition: covers(h), or h up to extrapolation_limit() (the calibration
  // only): beyond the last stage the last interval's motion is continued.
  Polyline profile_at(double h) const;
  // The calibration may look this far past the last stage: a fifth of the last interval.
  // It lets a history that ends at the last survey still find a best C slightly above its
  // own, instead of every later run needing one more stage.
  double extrapolation_limit() const {
    return hours.size() < 2 ? last_hours() : last_hours() + 0.2 * (last_hours() - hours[hours.size() - 2]);
  }
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

// Stage hours for a fresh run that puts stage boundaries on the survey hours: the largest
// step h0 with every survey's hours a whole multiple of it (1e-6 relative), if that needs
// at most max_stages stages to the last survey; otherwise 0 (use the scene's stage_hours).
double common_stage_hours(const std::vector<Survey>& surveys, int max_stages = 50);

// The scene set up for a fresh history covering the surveys up to `reach` x the last
// survey's hours: stage_hours from common_stage_hours (or the scene's), enough stages,
// wear rate C given.
Scene scene_for_surveys(const Scene& scene, const std::vector<Survey>& surveys, double c_m3_per_J,
                        double reach = 1.0);

// ---- calibration ----

// Least-squares time scale s of one history against the surveys (worn surveys only:
// hours > 0). C = s * C_run.
struct ScaleFit {
  double scale = 1.0;
  double sigma_curvature = 0.0;       // Gauss-Newton standard error of s
  double sigma_spread = 0.0;          // standard error of the mean of per-survey estimates
  double rms_m = 0.0;                 // residual rms at s
  int points = 0;
  bool at_bound = false;              // the best s is at the largest the history reaches
  std::vector<double> survey_hours;   // worn surveys
  std::vector<double> survey_scale;   // per-survey least-squares s
};
// Throws InputError(surveys file, ...) if no survey has hours > 0 (nothing to fit).
ScaleFit fit_time_scale(const ProfileHistory& history, const std::vector<Survey>& surveys);

struct CalibrationOptions {
  int max_runs = 5;
  double rel_tol = 0.01;        // stop when the run's own C fits within this
  double first_reach = 1.6;     // first history runs to this x the last survey's hours
  double reach = 1.0;           // later histories (plus extrapolation_limit)
};

struct CalibrationRun {
  int run = 0;
  double c_m3_per_J = 0.0;      // C of the history run
  double reached_hours = 0.0;
  ScaleFit fit;                 // s against this history
  double c_estimate = 0.0;      // s * C
  double wall_s = 0.0;
  std::vector<std::string> events;
};

struct CalibrationResult {
  double c_m3_per_J = 0.0;
  double sigma_m3_per_J = 0.0;    // standard uncertainty (fit and simulation combined)
  double sigma_fit_m3_per_J = 0.0;    // (a) or (b) above
  double sigma_model_m3_per_J = 0.0;  // (c) above
  double expanded_m3_per_J = 0.0; // U = 2 sigma (about 95%)
  bool converged = false;
  std::vector<CalibrationRun> runs;
  std::vector<double> survey_hours, survey_c;  // per-survey estimates (last run)
  WearHistory last_history;                    // of the last run
};

// (c) above: relative statistical error of the cumulative wear of a history up to `hours`.
double history_relative_error(const Scene& scene, const std::vector<StageRecord>& stages, double hours);

// Runs wear histories of `scene` (its C as the first guess) until the fitted C agrees with
// the run's own C. on_run is called after every history (progress; may be empty).
// `run_history` runs one history (default: run_wear_history); tests and the app may wrap it.
CalibrationResult calibrate_wear_rate(
    const Scene& scene, const std::vector<Survey>& surveys, const CalibrationOptions& options = {},
    const std::function<void(const CalibrationRun&)>& on_run = {},
    const std::function<WearHistory(const Scene&)>& run_history = {});

}  // namespace millwear::validation
