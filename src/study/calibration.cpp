// The time-scale fit and the calibration loop shared by the profile and area calibrations
// (method in calibration.hpp).
#include "study/calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "common/errors.hpp"
#include "scene/limits.hpp"
#include "wear/history.hpp"

namespace millwear::validation {

namespace {

// Least-squares 1D minimum of fn over [lo, hi]: a log-spaced scan, then golden section
// between the best scan point's neighbours (the misfit need not be unimodal far away).
double minimize_scale(const std::function<double(double)>& fn, double lo, double hi, bool& at_bound,
                      bool* at_hi = nullptr) {
  constexpr int kScan = 80;
  std::vector<double> s(kScan), v(kScan);
  for (int k = 0; k < kScan; ++k) {
    s[k] = lo * std::pow(hi / lo, static_cast<double>(k) / (kScan - 1));
    v[k] = fn(s[k]);
  }
  const int best = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  double a = s[std::max(0, best - 1)], b = s[std::min(kScan - 1, best + 1)];
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = fn(c), fd = fn(d);
  for (int it = 0; it < 60 && (b - a) > 1e-7 * b; ++it) {
    if (fc < fd) { b = d; d = c; fd = fc; c = b - g * (b - a); fc = fn(c); }
    else { a = c; c = d; fc = fd; d = a + g * (b - a); fd = fn(d); }
  }
  const double m = 0.5 * (a + b);
  const double found = fn(m) <= v[best] ? m : s[best];
  // At a bound only if the refined minimum is (within the search's resolution) hi or lo
  // itself: the last scan point being the best says little, the scan steps by about 9%.
  at_bound = hi - found <= 1e-6 * hi || found - lo <= 1e-6 * lo;
  if (at_hi) *at_hi = hi - found <= 1e-6 * hi;
  return found;
}

}  // namespace

double extrapolation_limit(const std::vector<double>& h) {
  if (h.empty()) return 0.0;
  return h.size() < 2 ? h.back() : h.back() + 0.2 * (h.back() - h[h.size() - 2]);
}

double common_stage_hours(const std::vector<double>& survey_hours, int max_stages) {
  double hmin = INFINITY, hmax = 0.0;
  for (double h : survey_hours)
    if (h > 0.0) { hmin = std::min(hmin, h); hmax = std::max(hmax, h); }
  if (!(hmax > 0.0)) return 0.0;
  for (int k = 1; k <= max_stages; ++k) {
    const double h0 = hmin / k;
    if (hmax / h0 > max_stages + 1e-6) return 0.0;
    // No stage shorter than a scene may have: surveys minutes apart fall between stages.
    if (h0 < kMinStageHours) return 0.0;
    bool ok = true;
    for (double h : survey_hours) {
      const double q = h / h0;
      if (std::fabs(q - std::round(q)) > 1e-6 * std::max(1.0, q)) { ok = false; break; }
    }
    if (ok) return h0;
  }
  return 0.0;
}

Scene scene_for_survey_hours(const Scene& scene, const std::vector<double>& survey_hours, double c, double reach) {
  Scene s = scene;
  // Hours since the history's start: a worn start's stages begin at its start_hours.
  std::vector<double> since;
  for (double h : survey_hours) since.push_back(h - scene.wear.start_hours);
  double hmax = 0.0;
  for (double h : since) hmax = std::max(hmax, h);
  const double h0 = common_stage_hours(since);
  if (h0 > 0.0) s.wear.stage_hours = h0;
  s.wear.stages = stages_to_reach(reach * hmax, s.wear.stage_hours);
  if (c > 0.0) {
    s.wear.rate_source = WearRateSource::Given;
    s.wear.wear_rate_m3_per_J = c;
  }
  return s;
}

ScaleFit fit_time_scale(const std::vector<double>& worn_hours, double reach_hours, const ScaledResiduals& residuals) {
  if (worn_hours.empty())
    throw InputError("", "surveys", "at least one survey after the history's start (a worn lifter) to calibrate on");
  if (!(reach_hours > 0.0)) throw RunError("the wear history has no worn stage to compare with");

  std::vector<std::size_t> all(worn_hours.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  // Residuals of a set of surveys at scale s.
  auto collect = [&residuals](const std::vector<std::size_t>& set, double s, std::vector<double>& r) {
    r.clear();
    for (std::size_t j : set) residuals(j, s, r);
  };
  auto misfit = [&collect](const std::vector<std::size_t>& set) {
    return [&collect, set](double s) {
      std::vector<double> r;
      collect(set, s, r);
      double ss = 0.0;
      for (double x : r) ss += x * x;
      return ss;
    };
  };
  const double hmax = *std::max_element(worn_hours.begin(), worn_hours.end());

  ScaleFit fit;
  const double s_hi = reach_hours / hmax;
  fit.scale = minimize_scale(misfit(all), 1e-3 * s_hi, s_hi, fit.at_bound, &fit.beyond_reach);

  std::vector<double> r, rp, rm;
  collect(all, fit.scale, r);
  fit.points = static_cast<int>(r.size());
  double rss = 0.0;
  for (double x : r) rss += x * x;
  fit.rms = std::sqrt(rss / r.size());
  // Gauss-Newton: J = d r / d s by central differences (one-sided at the history's end);
  // the step spans several geometry updates so the piecewise-linear interpolation is smooth.
  const double ds = 0.02 * fit.scale;
  const double s_up = std::min(fit.scale + ds, s_hi), s_dn = fit.scale - ds;
  collect(all, s_up, rp);
  collect(all, s_dn, rm);
  double jj = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double j = (rp[i] - rm[i]) / (s_up - s_dn);
    jj += j * j;
  }
  fit.sigma_curvature = (jj > 0.0 && r.size() > 1) ? std::sqrt(rss / (r.size() - 1) / jj) : INFINITY;

  for (std::size_t j = 0; j < worn_hours.size(); ++j) {
    bool bound;
    const double hi = reach_hours / worn_hours[j];
    const double sj = minimize_scale(misfit({j}), 1e-3 * hi, hi, bound);
    fit.survey_hours.push_back(worn_hours[j]);
    fit.survey_scale.push_back(sj);
  }
  const std::size_t m = fit.survey_scale.size();
  if (m >= 2) {
    const double mean = std::accumulate(fit.survey_scale.begin(), fit.survey_scale.end(), 0.0) / m;
    double var = 0.0;
    for (double x : fit.survey_scale) var += (x - mean) * (x - mean);
    fit.sigma_spread = std::sqrt(var / (m - 1) / m);
  }
  return fit;
}

double history_relative_error(const Scene& scene, const std::vector<StageRecord>& stages, double hours) {
  // Stage k's wear (up to the next stage) came from about simulated_s / window windows, each
  // with the stage's relative batch-means error (the first window's; later windows of the
  // stage see similar geometry).
  const double window_s = scene.wear.window_revolutions * scene.revolution_time_s();
  double n_total = 0.0, var_sum = 0.0;
  for (std::size_t k = 0; k + 1 < stages.size(); ++k) {
    if (stages[k].hours >= hours - kSameHoursTolerance) break;
    const double n = std::max(1.0, std::round(stages[k].simulated_s / window_s));
    n_total += n;
    var_sum += n * stages[k].area_loss_rate_rel_sem * stages[k].area_loss_rate_rel_sem;
  }
  return n_total > 0.0 ? std::sqrt(var_sum) / n_total : 0.0;
}

CalibrationResult calibrate_by_time_scale(const Scene& scene, const std::vector<double>& survey_hours,
                                          const HistoryFit& fit_history, const CalibrationOptions& opt,
                                          const std::function<void(const CalibrationRun&)>& on_run,
                                          const std::function<WearHistory(const Scene&)>& run_history) {
  CalibrationResult result;
  double c = scene.wear.rate_source == WearRateSource::Given ? scene.wear.wear_rate_m3_per_J : 0.0;
  double hmax = 0.0;  // the last survey's hours
  for (double h : survey_hours) hmax = std::max(hmax, h);
  // One history of scene s, fitted on its own; booked as run `run` (replicate `replicate`).
  const auto run_and_fit = [&](const Scene& s, int run, int replicate) -> const CalibrationRun& {
    const auto t0 = std::chrono::steady_clock::now();
    WearHistory h = run_history ? run_history(s) : run_wear_history(s);
    throw_if_failed(h);
    CalibrationRun r;
    r.run = run;
    r.replicate = replicate;
    r.seed = s.solver.seed;
    r.c_m3_per_J = h.wear_rate_m3_per_J;
    for (const StageRecord& st : h.stages) r.reached_hours = std::max(r.reached_hours, st.hours);
    r.fit = fit_history(h.stages);
    r.c_estimate = r.fit.scale * r.c_m3_per_J;
    r.events = h.events;
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.runs.push_back(r);
    result.last_history = std::move(h);
    if (on_run) on_run(result.runs.back());
    return result.runs.back();
  };
  // One history at rate c_run (seed + seed_offset) reaching `reach`, fitted. A fit at the end
  // of what the history reaches gives only a lower bound on C: the same history (same seed,
  // same rate: the same draw of the charge) run as far as the first gives the estimate in its
  // place, so that no draw is left out of the mean for having worn little.
  const auto fitted = [&](double c_run, double reach, std::uint64_t seed_offset, int run, int replicate) {
    Scene s = scene_for_survey_hours(scene, survey_hours, c_run, reach);
    s.solver.seed += seed_offset;
    const CalibrationRun* r = &run_and_fit(s, run, replicate);
    if (r->fit.beyond_reach && reach < opt.first_reach) {
      result.runs.pop_back();
      s = scene_for_survey_hours(scene, survey_hours, c_run, opt.first_reach);
      s.solver.seed += seed_offset;
      r = &run_and_fit(s, run, replicate);
    }
    return std::make_pair(s, *r);
  };
  double reach = opt.first_reach;
  for (int run = 1; run <= opt.max_runs; ++run) {
    const auto [s, r] = fitted(c, reach, 0, run, 1);
    c = r.c_estimate;
    // Beyond even that reach, the next history runs as far again, to find the rate rather
    // than creep up on it.
    reach = r.fit.beyond_reach ? opt.first_reach : opt.reach;
    // A scale change inside this history's own statistical error cannot be resolved by
    // another history (it would only draw new noise): that is converged too.
    const double own_error = history_relative_error(s, result.last_history.stages, std::min(hmax, r.reached_hours));
    if (run >= opt.min_runs && std::fabs(r.fit.scale - 1.0) <= std::max(opt.rel_tol, own_error) &&
        !r.fit.at_bound) {
      result.converged = true;
      break;
    }
  }
  // Replicates: the calibrated C again with other seeds, each history fitted on its own.
  for (int k = 2; k <= opt.replicates; ++k)
    fitted(result.runs.back().c_m3_per_J, opt.reach, static_cast<std::uint64_t>(k - 1),
           static_cast<int>(result.runs.size()) + 1, k);
  const CalibrationRun& last = result.runs.back();
  // Every history after the first ran near the answer and gives its own estimate, with its
  // own draw of the charge's noise: their mean is the estimate, and their spread measures
  // that noise directly (rule 2's batch means within a window understate it when the
  // batches are correlated, see the README). A history whose fit stopped at an end of the
  // search gives a bound, not an estimate: it is left out, unless no history gave more (a
  // calibration that did not converge then reports the last bound).
  std::vector<double> estimates;
  for (std::size_t k = result.runs.size() > 1 ? 1 : 0; k < result.runs.size(); ++k)
    if (!result.runs[k].fit.at_bound) estimates.push_back(result.runs[k].c_estimate);
  if (estimates.empty()) estimates.push_back(last.c_estimate);
  const double m = static_cast<double>(estimates.size());
  result.c_m3_per_J = std::accumulate(estimates.begin(), estimates.end(), 0.0) / m;
  double spread = 0.0;  // standard deviation of one history's estimate
  if (estimates.size() >= 2) {
    for (double c_k : estimates) spread += (c_k - result.c_m3_per_J) * (c_k - result.c_m3_per_J);
    spread = std::sqrt(spread / (m - 1.0));
  }
  result.histories_averaged = static_cast<int>(estimates.size());
  const Scene s = scene_for_survey_hours(scene, survey_hours, last.c_m3_per_J, 1.0);
  result.fit_error_known = last.fit.error_known();
  // The surveys are the same for every history: the fit's error does not average out.
  result.sigma_fit_m3_per_J =
      result.fit_error_known ? last.c_m3_per_J * std::max(last.fit.sigma_curvature, last.fit.sigma_spread) : 0.0;
  const double batch_means =
      result.c_m3_per_J * history_relative_error(s, result.last_history.stages, std::min(hmax, last.reached_hours));
  result.sigma_model_m3_per_J = std::max(batch_means, spread) / std::sqrt(m);
  result.sigma_m3_per_J = std::hypot(result.sigma_fit_m3_per_J, result.sigma_model_m3_per_J);
  result.expanded_m3_per_J = 2.0 * result.sigma_m3_per_J;
  result.survey_hours = last.fit.survey_hours;
  for (double sj : last.fit.survey_scale) result.survey_c.push_back(sj * last.c_m3_per_J);
  return result;
}

}  // namespace millwear::validation
