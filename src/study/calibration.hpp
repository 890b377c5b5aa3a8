#pragma once
// The calibration of the real wear rate C by time scaling, shared by the fit on measured
// profiles (profile_fit.hpp: residuals are signed normal distances, m) and the fit on
// measured areas alone (area_fit.hpp: residuals are area losses, m^2).
//
// In the staged loop the lifter geometry depends on C and the operating time t almost only
// through the product C t (depth = C x work / area, and the loop steps by depth), so the
// history run with C_run predicts the lifter for C = s C_run at hours h as its own lifter at
// s h. A 1D search on s (a log-spaced scan, then golden section) over one history gives the
// least-squares s; a new history at C = s C_run removes what the time-scaling misses
// (reversal times, stage restarts), and the loop stops when s is 1 within a tolerance (or
// within the history's own statistical error). Every history after the first ran near the
// answer and is an independent estimate: C is their mean.
//
// Uncertainty: the larger of (a) the Gauss-Newton standard error from the curvature of the
// misfit, sigma_s^2 = (RSS / (n - 1)) / sum (d r_i / d s)^2, and (b) the standard error of the
// mean of the per-survey estimates (with two or more worn surveys), which catches correlated
// residuals that (a) treats as independent; combined in quadrature with (c) the statistical
// error of the simulation itself: the wear up to the last survey is a sum over N measuring
// windows whose rates carry the batch-means relative error of rule 2
// (StageRecord::area_loss_rate_rel_sem, about 7-10% per lab-mill window), so one history's
// cumulative wear, and hence C, is uncertain by sqrt(sum n_k sem_k^2) / N; with two or more
// histories averaged, by the larger of that and their estimates' standard deviation (the
// batch means understate it when batches are correlated), over sqrt(histories). With a single
// residual (one worn area survey) neither (a) nor (b) exists: the fit is exact, its error is
// not known, and only (c) is counted (CalibrationResult::fit_error_known = false). It is
// reported as an expanded uncertainty U = 2 sigma (about 95%). A round trip on simulated
// surveys carries (c) twice (the surveys are one realisation, the fit another): there the
// difference may reach about sqrt(2) U.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "wear/wear.hpp"

namespace millwear::validation {

// How far past its last stage a history (stage hours, increasing) may be read by the
// calibration: a fifth of the last interval beyond it. It lets a history that ends at the
// last survey still find a best C slightly above its own, instead of every later run
// needing one more stage.
double extrapolation_limit(const std::vector<double>& stage_hours);

// A survey's hours and a stage's this close (h) are the same time: a stage's hours are sums
// of stage lengths, a survey's the decimals of a file.
constexpr double kSameHoursTolerance = 1e-6;

// Stage hours for a fresh run that puts stage boundaries on the survey hours (hours since
// the history's start): the largest step h0 with every survey's hours a whole multiple of it
// (1e-6 relative), if that needs at most max_stages stages to the last survey and is at least
// kMinStageHours (scene/limits.hpp), the shortest stage a scene takes; otherwise 0 (use the
// scene's stage_hours).
constexpr int kMaxCommonStages = 50;
double common_stage_hours(const std::vector<double>& survey_hours, int max_stages = kMaxCommonStages);

// The scene set up for a fresh history covering the surveys up to `reach` x the last
// survey's hours, both counted from the history's start (lifters.start_hours; 0 for a new
// liner): stage_hours from common_stage_hours (or the scene's), enough stages, wear rate C
// given (when c_m3_per_J > 0).
Scene scene_for_survey_hours(const Scene& scene, const std::vector<double>& survey_hours, double c_m3_per_J,
                             double reach = 1.0);

// Least-squares time scale s of one history against the worn surveys (after the history's
// start). C = s * C_run.
struct ScaleFit {
  double scale = 1.0;
  double sigma_curvature = 0.0;       // (a) Gauss-Newton standard error of s
  double sigma_spread = 0.0;          // (b) standard error of the mean of per-survey estimates
  double rms = 0.0;                   // residual rms at s (m for profiles, m^2 for areas)
  int points = 0;                     // residuals
  // The best s is at an end of the search: the largest the history reaches, or a thousandth
  // of it (surveys that show next to no wear). Such a fit does not count as converged.
  bool at_bound = false;
  bool beyond_reach = false;          // at the largest end: C is at least s * C_run
  std::vector<double> survey_hours;   // worn surveys
  std::vector<double> survey_scale;   // per-survey least-squares s
  // (a) needs two residuals or more (one worn area survey has one).
  bool error_known() const { return points >= 2; }
};

// Residuals of worn survey j (index into worn_hours) when the history is read at time scale
// s, appended to r. Hours count from the history's start t0: the survey t0 + h is read at
// t0 + s h, clamped to what the history can give (its extrapolation_limit).
using ScaledResiduals = std::function<void(std::size_t j, double s, std::vector<double>& r)>;

// The least-squares s of the residuals over every worn survey, its errors (a) and (b), and
// the per-survey s. worn_hours and reach_hours (the furthest the history can be read at)
// count from the history's start. Throws
// InputError("", "surveys", ...) if worn_hours is empty (nothing to fit).
ScaleFit fit_time_scale(const std::vector<double>& worn_hours, double reach_hours, const ScaledResiduals& residuals);

struct CalibrationOptions {
  int max_runs = 5;
  int min_runs = 2;             // histories at least (the first guess, then one per estimate to average)
  double rel_tol = 0.01;        // stop when the run's own C fits within this, or within the
                                // run's own statistical error if that is larger
  double first_reach = 1.6;     // first history runs to this x the last survey's hours
  double reach = 1.0;           // later histories (plus the extrapolation limit); one after a
                                // fit beyond its history's reach runs to first_reach
  // Histories at the calibrated C with seeds s .. s+N-1 (the last iteration's is seed s):
  // their estimates join the mean, and their spread is the charge's own noise measured.
  int replicates = 1;
};

struct CalibrationRun {
  int run = 0;
  int replicate = 1;            // 1: an iteration (the scene's seed); K > 1: seed + K - 1
  std::uint64_t seed = 0;
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
  double sigma_fit_m3_per_J = 0.0;    // (a) or (b) above; 0 when not known
  double sigma_model_m3_per_J = 0.0;  // (c) above
  double expanded_m3_per_J = 0.0; // U = 2 sigma (about 95%)
  bool fit_error_known = true;    // false: one residual only, (a) and (b) do not exist
  bool converged = false;
  int histories_averaged = 1;     // the estimate is the mean over the histories after the first
                                  // whose fits were not at an end of the search
  std::vector<CalibrationRun> runs;
  std::vector<double> survey_hours, survey_c;  // per-survey estimates (last run)
  WearHistory last_history;                    // of the last run
};

// (c) above: relative statistical error of the cumulative wear of a history up to `hours`.
double history_relative_error(const Scene& scene, const std::vector<StageRecord>& stages, double hours);

// Fits one history's stages against the surveys (fit_time_scale with its residuals).
using HistoryFit = std::function<ScaleFit(const std::vector<StageRecord>& stages)>;

// Runs wear histories of `scene` (its C as the first guess), each covering survey_hours
// (scene_for_survey_hours), until the fitted C agrees with the run's own C. on_run is
// called after every history (progress; may be empty). `run_history` runs one history
// (default: run_wear_history); tests and the app may wrap it.
CalibrationResult calibrate_by_time_scale(const Scene& scene, const std::vector<double>& survey_hours,
                                          const HistoryFit& fit_history, const CalibrationOptions& options = {},
                                          const std::function<void(const CalibrationRun&)>& on_run = {},
                                          const std::function<WearHistory(const Scene&)>& run_history = {});

}  // namespace millwear::validation
