// Profile comparison, interpolation between stages, and the calibration of C on profiles
// (see profile_fit.hpp; the time-scale fit itself is in calibration.cpp).
#include "study/profile_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/csv.hpp"
#include "wear/life.hpp"

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
    if (std::fabs(hours[k] - h) <= kSameHoursTolerance) return surfaces[k];
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
  Polygon region = region_above_zero(surface);
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

void check_surveys_over_lifter(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double radius_m,
                               const std::string& file) {
  for (const Survey& s : surveys) {
    const double xa = s.profile_m.front().x, xb = s.profile_m.back().x;
    if (area_between(new_unit.surface, xa, xb, radius_m) > 0.0) continue;
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "a survey over part of the lifter; the survey at %s h spans x = %.4g to %.4g mm, where the new "
                  "lifter has no metal above the shell line (its base spans x = %.4g to %.4g mm)",
                  io::format_number(s.hours).c_str(), xa * 1e3, xb * 1e3, -in_mm(new_unit.lifter_half_base_m),
                  in_mm(new_unit.lifter_half_base_m));
    throw InputError(file, "line " + std::to_string(s.first_line), buf);
  }
}

namespace {

// What each later survey is judged against, as check_areas_shrink does: the survey at the
// start (a file has one survey per hours), else the scene's lifter. Two later surveys are not
// compared with each other: surveys hours apart, or of other lifters of the row (which wear at
// other rates), may differ by more than the wear between them.
struct StartLifter {
  const Survey* survey = nullptr;  // null: the scene's lifter
  const Polyline* surface = nullptr;
  std::string reference;  // how messages name it
};

// Null surface where there is no reference: no survey at the start of a pattern's lifters
// (of which lifter would the scene's be?).
StartLifter start_lifter(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double start_hours,
                         bool one_shape) {
  StartLifter l;
  for (const Survey& s : surveys)
    if (std::fabs(s.hours - start_hours) <= kSameHoursTolerance) l.survey = &s;
  if (!l.survey && !one_shape) return l;
  l.surface = l.survey ? &l.survey->profile_m : &new_unit.surface;
  l.reference = l.survey ? "the survey at the start, " + io::format_number(start_hours) + " h (line " +
                               std::to_string(l.survey->first_line) + ")"
                         : "the scene's lifter at the history's start (" + io::format_number(start_hours) + " h)";
  return l;
}

// fn(later, lo, hi, start_m2, later_m2) for each survey after the start, over the span of x it
// shares with the lifter at the start: the metal above the shell line of either there.
template <class Fn>
void for_later_surveys(const std::vector<Survey>& surveys, const Polyline& start_surface, double start_hours,
                       double radius_m, const Fn& fn) {
  for (const Survey& later : surveys) {
    if (!(later.hours > start_hours + kSameHoursTolerance)) continue;
    const double lo = std::max(later.profile_m.front().x, start_surface.front().x);
    const double hi = std::min(later.profile_m.back().x, start_surface.back().x);
    if (!(hi > lo)) continue;
    fn(later, lo, hi, area_between(start_surface, lo, hi, radius_m), area_between(later.profile_m, lo, hi, radius_m));
  }
}

}  // namespace

void check_surveys_lose_metal(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double radius_m,
                              double start_hours, const std::string& file, bool one_shape) {
  const double new_area_m2 = measure_lifter(new_unit, radius_m).area_m2;
  const StartLifter lifter = start_lifter(surveys, new_unit, start_hours, one_shape);
  if (!lifter.surface) return;
  const Survey* start = lifter.survey;
  const std::string& reference = lifter.reference;
  // Judged by the drawing, a survey may also be of a casting bigger than drawn.
  const double share = kGainNoiseShare + (start ? 0.0 : kCastOverDrawingShare);
  const double allowed_m2 = share * new_area_m2;
  for_later_surveys(surveys, *lifter.surface, start_hours, radius_m, [&](const Survey& later, double lo, double hi,
                                                                         double start_m2, double later_m2) {
    // A lifter worn to the shell (kWornOutFraction of it left) ends its history: no history
    // reaches a survey with less, whose y_mm are most likely measured down, not up.
    if (start_m2 > 0.0 && later_m2 < kWornOutFraction * start_m2) {
      char buf[640];
      std::snprintf(buf, sizeof buf,
                    "surveys that keep some of the lifter (one worn to under %s%% of its metal reached the shell, "
                    "which ends a history; y_mm is measured up from the original shell line, toward the mill "
                    "axis): over x = %s to %s mm the survey at %s h has %s mm^2 of metal above the shell line, "
                    "against %s mm^2 in %s",
                    io::format_number(100.0 * kWornOutFraction).c_str(), io::format_number(in_mm(lo), 6).c_str(),
                    io::format_number(in_mm(hi), 6).c_str(), io::format_number(later.hours).c_str(),
                    io::format_number(in_mm2(later_m2), 4).c_str(), io::format_number(in_mm2(start_m2), 4).c_str(),
                    reference.c_str());
      throw InputError(file, "line " + std::to_string(later.first_line), buf);
    }
    const double gain_m2 = later_m2 - start_m2;
    if (!(gain_m2 > allowed_m2)) return;
    const std::string allowed =
        start ? "a gauge's noise of up to " + io::format_number(100.0 * kGainNoiseShare) + "%"
              : "a gauge's noise and a casting bigger than drawn, up to " +
                    io::format_number(100.0 * kGainNoiseShare) + "% + " +
                    io::format_number(100.0 * kCastOverDrawingShare) + "%";
    const std::string exact =
        start ? "" : "; a survey at the start, " + io::format_number(start_hours) + " h, gives the lifter as cast, "
                     "the exact reference";
    char buf[800];
    std::snprintf(buf, sizeof buf,
                  "surveys that lose metal with operating hours (wear removes it; %s of the new lifter's %s mm^2, "
                  "%s mm^2, is allowed): over x = %s to %s mm the survey at %s h has %s mm^2 more metal than %s%s",
                  allowed.c_str(), io::format_number(in_mm2(new_area_m2), 6).c_str(),
                  io::format_number(in_mm2(allowed_m2), 4).c_str(), io::format_number(in_mm(lo), 6).c_str(),
                  io::format_number(in_mm(hi), 6).c_str(), io::format_number(later.hours).c_str(),
                  io::format_number(in_mm2(gain_m2), 4).c_str(), reference.c_str(), exact.c_str());
    throw InputError(file, "line " + std::to_string(later.first_line), buf);
  });
}

void check_surveys_show_wear(const std::vector<Survey>& surveys, const LinerUnit& new_unit, double radius_m,
                             double start_hours, const std::string& file, bool one_shape) {
  const StartLifter lifter = start_lifter(surveys, new_unit, start_hours, one_shape);
  if (!lifter.surface) return;
  double moment_m2h = 0.0;  // hours since the start times the metal lost, summed
  const Survey* last = nullptr;
  const Survey* most = nullptr;  // the survey that lost the most
  double most_m2 = 0.0;
  for_later_surveys(surveys, *lifter.surface, start_hours, radius_m,
                    [&](const Survey& later, double, double, double start_m2, double later_m2) {
                      moment_m2h += (later.hours - start_hours) * (start_m2 - later_m2);
                      last = &later;
                      if (!most || start_m2 - later_m2 > most_m2) {
                        most = &later;
                        most_m2 = start_m2 - later_m2;
                      }
                    });
  if (!last) return;
  const std::string& reference = lifter.reference;
  if (!(moment_m2h > 0.0))
    throw InputError(file, "line " + std::to_string(last->first_line),
                     "surveys that lose metal with operating hours (a wear rate is fitted to the metal lost); over the "
                     "spans they share with " + reference + " the later surveys have lost none: the metal lost times "
                     "the hours since the start, summed, is " + io::format_number(moment_m2h / (kMm * kMm), 4) +
                     " mm^2 h, not above 0");
  // A loss within a gauge's noise (the share of metal a survey may show above its lifter) is
  // not told from none: a rate fitted to it is fitted to the noise, and the histories shrink C
  // toward nothing without converging.
  const double noise_m2 = kGainNoiseShare * measure_lifter(new_unit, radius_m).area_m2;
  if (most_m2 > noise_m2) return;
  throw InputError(file, "line " + std::to_string(most->first_line),
                   "a survey that lost more metal than a gauge's noise (" +
                       io::format_number(100.0 * kGainNoiseShare) + "% of the new lifter's area, " +
                       io::format_number(in_mm2(noise_m2), 4) + " mm^2) to fit a wear rate to; over the spans "
                       "they share with " + reference + ", the survey that lost the most, at " +
                       io::format_number(most->hours) + " h, lost " + io::format_number(in_mm2(most_m2), 4) +
                       " mm^2 (a survey later in the lifter's life shows its wear)");
}

double common_stage_hours(const std::vector<Survey>& surveys, int max_stages) {
  return common_stage_hours(survey_hours(surveys), max_stages);
}

ScaleFit fit_time_scale(const ProfileHistory& history, const std::vector<Survey>& surveys) {
  const double t0 = history.hours.empty() ? 0.0 : history.hours.front();
  std::vector<const Survey*> worn;
  std::vector<double> worn_hours;  // since the start
  for (const Survey& s : surveys)
    if (s.hours > t0 + kSameHoursTolerance) {
      worn.push_back(&s);
      worn_hours.push_back(s.hours - t0);
    }
  const double limit = history.extrapolation_limit() - t0;
  ScaleFit fit = fit_time_scale(worn_hours, limit, [&](std::size_t j, double s, std::vector<double>& r) {
    const Polyline sim = history.profile_at(t0 + std::min(worn_hours[j] * s, limit));
    for (const Vec2& p : worn[j]->profile_m) r.push_back(signed_distance(p, sim));
  });
  for (double& h : fit.survey_hours) h += t0;
  return fit;
}

CalibrationResult calibrate_wear_rate(const Scene& scene, const std::vector<Survey>& surveys,
                                      const CalibrationOptions& opt,
                                      const std::function<void(const CalibrationRun&)>& on_run,
                                      const std::function<WearHistory(const Scene&)>& run_history) {
  const auto fit = [&surveys](const std::vector<StageRecord>& stages) {
    return fit_time_scale(profile_history(stages), surveys);
  };
  return calibrate_by_time_scale(scene, survey_hours(surveys), fit, opt, on_run, run_history);
}

}  // namespace millwear::validation
