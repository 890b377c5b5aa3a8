// Profile comparison, interpolation between stages, and the calibration of C (see
// profile_fit.hpp for the method).
#include "validation/profile_fit.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/errors.hpp"
#include "io/csv.hpp"

namespace millwear::validation {

namespace {

// Nearest point of segment [a, b] to p, and its parameter u in [0, 1].
Vec2 nearest_on_segment(Vec2 p, Vec2 a, Vec2 b, double& u) {
  const Vec2 d = b - a;
  const double l2 = length_sq(d);
  u = l2 > 0.0 ? std::clamp(dot(p - a, d) / l2, 0.0, 1.0) : 0.0;
  return a + u * d;
}

Vec2 nearest_on_polyline(Vec2 p, const Polyline& line) {
  Vec2 best = line.front();
  double best_d2 = std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j + 1 < line.size(); ++j) {
    double u;
    const Vec2 q = nearest_on_segment(p, line[j], line[j + 1], u);
    const double d2 = length_sq(p - q);
    if (d2 < best_d2) { best_d2 = d2; best = q; }
  }
  return best;
}

// Unit normal at vertex i of a surface running toward +x, pointing into the metal (right).
Vec2 vertex_normal_into_metal(const Polyline& s, std::size_t i) {
  Vec2 n;
  if (i > 0) n += normalized(right_perp(s[i] - s[i - 1]));
  if (i + 1 < s.size()) n += normalized(right_perp(s[i + 1] - s[i]));
  return normalized(n);
}

// Sutherland-Hodgman clip of a polygon to the half plane f(p) >= 0 (f linear).
template <class F>
Polygon clip_half_plane(const Polygon& poly, F f) {
  Polygon out;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = poly[i], b = poly[(i + 1) % n];
    const double fa = f(a), fb = f(b);
    if (fa >= 0.0) out.push_back(a);
    if ((fa >= 0.0) != (fb >= 0.0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
  }
  return out;
}

// Least-squares 1D minimum of fn over [lo, hi]: a log-spaced scan, then golden section
// between the best scan point's neighbours (the misfit need not be unimodal far away).
double minimize_scale(const std::function<double(double)>& fn, double lo, double hi, bool& at_bound) {
  constexpr int kScan = 80;
  std::vector<double> s(kScan), v(kScan);
  for (int k = 0; k < kScan; ++k) {
    s[k] = lo * std::pow(hi / lo, static_cast<double>(k) / (kScan - 1));
    v[k] = fn(s[k]);
  }
  const int best = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  at_bound = best == kScan - 1;
  double a = s[std::max(0, best - 1)], b = s[std::min(kScan - 1, best + 1)];
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = fn(c), fd = fn(d);
  for (int it = 0; it < 60 && (b - a) > 1e-7 * b; ++it) {
    if (fc < fd) { b = d; d = c; fd = fc; c = b - g * (b - a); fc = fn(c); }
    else { a = c; c = d; fc = fd; d = a + g * (b - a); fd = fn(d); }
  }
  const double m = 0.5 * (a + b);
  return fn(m) <= v[best] ? m : s[best];
}

}  // namespace

Polyline interpolate_profile(const Polyline& a, const Polyline& b, double f) {
  if (f <= 0.0) return a;
  Polyline out(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec2 p = a[i], n = vertex_normal_into_metal(a, i);
    // Ray p + t n against b: the crossing nearest to p (either side; smoothing may push a
    // point out slightly).
    double best_t = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j + 1 < b.size(); ++j) {
      const Vec2 q0 = b[j], e = b[j + 1] - b[j];
      const double den = cross(n, e);
      if (std::fabs(den) < 1e-300) continue;
      const Vec2 w = q0 - p;
      const double t = cross(w, e) / den, u = cross(w, n) / den;
      if (u >= -1e-12 && u <= 1.0 + 1e-12 && std::fabs(t) < std::fabs(best_t)) best_t = t;
    }
    const Vec2 target = std::isfinite(best_t) ? p + best_t * n : nearest_on_polyline(p, b);
    out[i] = p + f * (target - p);
  }
  return out;
}

Polyline ProfileHistory::profile_at(double h) const {
  for (std::size_t k = 0; k < hours.size(); ++k)
    if (std::fabs(hours[k] - h) <= 1e-6) return surfaces[k];
  if (hours.size() < 2) return surfaces.front();
  std::size_t k = 1;
  while (k + 1 < hours.size() && hours[k] < h) ++k;
  const double f_max = (extrapolation_limit() - hours[hours.size() - 2]) / (hours.back() - hours[hours.size() - 2]);
  const double f = std::clamp((h - hours[k - 1]) / (hours[k] - hours[k - 1]), 0.0, k + 1 == hours.size() ? f_max : 1.0);
  return interpolate_profile(surfaces[k - 1], surfaces[k], f);
}

ProfileHistory profile_history(const std::vector<StageRecord>& stages) {
  ProfileHistory h;
  for (const StageRecord& s : stages) {
    if (s.units.empty()) continue;
    if (!h.hours.empty() && s.hours <= h.hours.back()) continue;
    h.hours.push_back(s.hours);
    h.surfaces.push_back(s.units.front().surface);
  }
  return h;
}

double signed_distance(Vec2 p, const Polyline& s) {
  double best_d2 = std::numeric_limits<double>::infinity(), side = 0.0;
  for (std::size_t j = 0; j + 1 < s.size(); ++j) {
    double u;
    const Vec2 q = nearest_on_segment(p, s[j], s[j + 1], u);
    const double d2 = length_sq(p - q);
    if (d2 >= best_d2) continue;
    best_d2 = d2;
    // Side: left of the segment is the charge side. At a shared vertex use the vertex's
    // pseudo-normal so a point outside a convex corner gets the right sign.
    Vec2 left = left_perp(normalized(s[j + 1] - s[j]));
    if (u <= 0.0 && j > 0) left += left_perp(normalized(s[j] - s[j - 1]));
    if (u >= 1.0 && j + 2 < s.size()) left += left_perp(normalized(s[j + 2] - s[j + 1]));
    side = dot(p - q, left) >= 0.0 ? 1.0 : -1.0;
  }
  return side * std::sqrt(best_d2);
}

double area_between(const Polyline& surface, double x_from, double x_to, double radius_m) {
  if (surface.size() < 2) return 0.0;
  double ymin = 0.0;
  for (const Vec2& p : surface) ymin = std::min(ymin, p.y);
  Polygon region = surface;
  region.push_back({surface.back().x, ymin - 1.0});
  region.push_back({surface.front().x, ymin - 1.0});
  region = clip_half_plane(region, [](Vec2 p) { return p.y; });
  region = clip_half_plane(region, [x_from](Vec2 p) { return p.x - x_from; });
  region = clip_half_plane(region, [x_to](Vec2 p) { return x_to - p.x; });
  if (region.size() < 3) return 0.0;
  // Polar map: dA_mill = (R - y) dx dy / R (as measure_lifter).
  double a2 = 0.0, my6 = 0.0;
  for (std::size_t i = 0; i < region.size(); ++i) {
    const Vec2 p = region[i], q = region[(i + 1) % region.size()];
    const double c = cross(p, q);
    a2 += c;
    my6 += c * (p.y + q.y);
  }
  return std::abs(0.5 * a2 - my6 / 6.0 / radius_m);
}

ProfileComparison compare_profile(const Survey& measured, const Polyline& simulated, double radius_m,
                                  double new_height_m, const Polyline& new_surface) {
  ProfileComparison c;
  c.hours = measured.hours;
  c.points = static_cast<int>(measured.profile_m.size());
  double sum_abs = 0.0, sum = 0.0;
  for (const Vec2& p : measured.profile_m) {
    const double d = signed_distance(p, simulated);
    sum_abs += std::fabs(d);
    sum += d;
    c.max_distance_m = std::max(c.max_distance_m, std::fabs(d));
  }
  c.mean_distance_m = sum_abs / c.points;
  c.bias_m = sum / c.points;
  c.mean_pct_height = 100.0 * c.mean_distance_m / new_height_m;
  c.max_pct_height = 100.0 * c.max_distance_m / new_height_m;
  const double xa = measured.profile_m.front().x, xb = measured.profile_m.back().x;
  c.measured_area_m2 = area_between(measured.profile_m, xa, xb, radius_m);
  c.simulated_area_m2 = area_between(simulated, xa, xb, radius_m);
  c.area_error_m2 = c.simulated_area_m2 - c.measured_area_m2;
  const double new_area = area_between(new_surface, xa, xb, radius_m);
  c.area_error_pct = new_area > 0.0 ? 100.0 * c.area_error_m2 / new_area : std::nan("");
  return c;
}

double common_stage_hours(const std::vector<Survey>& surveys, int max_stages) {
  double hmin = INFINITY, hmax = 0.0;
  for (const Survey& s : surveys)
    if (s.hours > 0.0) { hmin = std::min(hmin, s.hours); hmax = std::max(hmax, s.hours); }
  if (!(hmax > 0.0)) return 0.0;
  for (int k = 1; k <= max_stages; ++k) {
    const double h0 = hmin / k;
    if (hmax / h0 > max_stages + 1e-6) return 0.0;
    bool ok = true;
    for (const Survey& s : surveys) {
      const double q = s.hours / h0;
      if (std::fabs(q - std::round(q)) > 1e-6 * std::max(1.0, q)) { ok = false; break; }
    }
    if (ok) return h0;
  }
  return 0.0;
}

Scene scene_for_surveys(const Scene& scene, const std::vector<Survey>& surveys, double c, double reach) {
  Scene s = scene;
  double hmax = 0.0;
  for (const Survey& v : surveys) hmax = std::max(hmax, v.hours);
  const double h0 = common_stage_hours(surveys);
  if (h0 > 0.0) s.wear.stage_hours = h0;
  s.wear.stages = std::max(1, static_cast<int>(std::ceil(reach * hmax / s.wear.stage_hours - 1e-9)));
  if (c > 0.0) {
    s.wear.rate_source = WearRateSource::Given;
    s.wear.wear_rate_m3_per_J = c;
  }
  return s;
}

ScaleFit fit_time_scale(const ProfileHistory& history, const std::vector<Survey>& surveys) {
  std::vector<const Survey*> worn;
  for (const Survey& s : surveys)
    if (s.hours > 0.0) worn.push_back(&s);
  if (worn.empty()) throw InputError("", "surveys", "at least one survey after 0 h (a worn profile) to calibrate on");
  if (!(history.last_hours() > 0.0)) throw RunError("the wear history has no worn stage to compare with");

  // Residuals of a set of surveys at scale s.
  auto residuals = [&](const std::vector<const Survey*>& set, double s, std::vector<double>& r) {
    r.clear();
    for (const Survey* v : set) {
      const Polyline sim = history.profile_at(std::min(v->hours * s, history.extrapolation_limit()));
      for (const Vec2& p : v->profile_m) r.push_back(signed_distance(p, sim));
    }
  };
  auto misfit = [&](const std::vector<const Survey*>& set) {
    return [&history, &residuals, set](double s) {
      (void)history;
      std::vector<double> r;
      residuals(set, s, r);
      double ss = 0.0;
      for (double x : r) ss += x * x;
      return ss;
    };
  };
  double hmax = 0.0;
  for (const Survey* v : worn) hmax = std::max(hmax, v->hours);

  ScaleFit fit;
  const double s_hi = history.extrapolation_limit() / hmax;
  fit.scale = minimize_scale(misfit(worn), 1e-3 * s_hi, s_hi, fit.at_bound);

  std::vector<double> r, rp, rm;
  residuals(worn, fit.scale, r);
  fit.points = static_cast<int>(r.size());
  double rss = 0.0;
  for (double x : r) rss += x * x;
  fit.rms_m = std::sqrt(rss / r.size());
  // Gauss-Newton: J = d r / d s by central differences (one-sided at the history's end);
  // the step spans several geometry updates so the piecewise-linear interpolation is smooth.
  const double ds = 0.02 * fit.scale;
  const double s_up = std::min(fit.scale + ds, s_hi), s_dn = fit.scale - ds;
  residuals(worn, s_up, rp);
  residuals(worn, s_dn, rm);
  double jj = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const double j = (rp[i] - rm[i]) / (s_up - s_dn);
    jj += j * j;
  }
  fit.sigma_curvature = (jj > 0.0 && r.size() > 1) ? std::sqrt(rss / (r.size() - 1) / jj) : INFINITY;

  for (const Survey* v : worn) {
    bool bound;
    const double sj = minimize_scale(misfit({v}), 1e-3 * history.extrapolation_limit() / v->hours,
                                     history.extrapolation_limit() / v->hours, bound);
    fit.survey_hours.push_back(v->hours);
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
    if (stages[k].hours >= hours - 1e-6) break;
    const double n = std::max(1.0, std::round(stages[k].simulated_s / window_s));
    n_total += n;
    var_sum += n * stages[k].area_loss_rate_rel_sem * stages[k].area_loss_rate_rel_sem;
  }
  return n_total > 0.0 ? std::sqrt(var_sum) / n_total : 0.0;
}

CalibrationResult calibrate_wear_rate(const Scene& scene, const std::vector<Survey>& surveys,
                                      const CalibrationOptions& opt,
                                      const std::function<void(const CalibrationRun&)>& on_run,
                                      const std::function<WearHistory(const Scene&)>& run_history) {
  CalibrationResult result;
  double c = scene.wear.rate_source == WearRateSource::Given ? scene.wear.wear_rate_m3_per_J : 0.0;
  for (int run = 1; run <= opt.max_runs; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    const Scene s = scene_for_surveys(scene, surveys, c, run == 1 ? opt.first_reach : opt.reach);
    WearHistory h = run_history ? run_history(s) : run_wear_history(s);
    CalibrationRun r;
    r.run = run;
    r.c_m3_per_J = h.wear_rate_m3_per_J;
    const ProfileHistory ph = profile_history(h.stages);
    r.reached_hours = ph.last_hours();
    r.fit = fit_time_scale(ph, surveys);
    r.c_estimate = r.fit.scale * r.c_m3_per_J;
    r.events = h.events;
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result.runs.push_back(r);
    result.last_history = std::move(h);
    if (on_run) on_run(r);
    c = r.c_estimate;
    if (std::fabs(r.fit.scale - 1.0) <= opt.rel_tol && !r.fit.at_bound) {
      result.converged = true;
      break;
    }
  }
  const CalibrationRun& last = result.runs.back();
  result.c_m3_per_J = last.c_estimate;
  double hmax = 0.0;
  for (const Survey& v : surveys) hmax = std::max(hmax, v.hours);
  const Scene s = scene_for_surveys(scene, surveys, last.c_m3_per_J, 1.0);
  result.sigma_fit_m3_per_J = last.c_m3_per_J * std::max(last.fit.sigma_curvature, last.fit.sigma_spread);
  result.sigma_model_m3_per_J =
      result.c_m3_per_J * history_relative_error(s, result.last_history.stages, std::min(hmax, last.reached_hours));
  result.sigma_m3_per_J = std::hypot(result.sigma_fit_m3_per_J, result.sigma_model_m3_per_J);
  result.expanded_m3_per_J = 2.0 * result.sigma_m3_per_J;
  result.survey_hours = last.fit.survey_hours;
  for (double sj : last.fit.survey_scale) result.survey_c.push_back(sj * last.c_m3_per_J);
  return result;
}

}  // namespace millwear::validation
