// Simulated against measured lifter areas, and the calibration of C on area loss (see
// area_fit.hpp; the time-scale fit itself is in calibration.cpp).
#include "study/area_fit.hpp"

#include <algorithm>
#include <cmath>

namespace millwear::validation {

double AreaHistory::area_at(double h) const {
  for (std::size_t k = 0; k < hours.size(); ++k)
    if (std::fabs(hours[k] - h) <= kSameHoursTolerance) return area_m2[k];
  if (hours.size() < 2) return area_m2.front();
  std::size_t k = 1;
  while (k + 1 < hours.size() && hours[k] < h) ++k;
  const double hi = k + 1 == hours.size() ? extrapolation_limit() : hours[k];
  const double t = std::clamp(h, hours[k - 1], hi);
  const double f = (t - hours[k - 1]) / (hours[k] - hours[k - 1]);
  return area_m2[k - 1] + f * (area_m2[k] - area_m2[k - 1]);
}

AreaHistory area_history(const std::vector<StageRecord>& stages) {
  AreaHistory h;
  for (const StageRecord& s : stages) {
    if (s.units.empty()) continue;
    if (!h.hours.empty() && s.hours <= h.hours.back()) continue;
    h.hours.push_back(s.hours);
    h.area_m2.push_back(s.lifter.area_m2);
  }
  return h;
}

std::vector<AreaComparison> compare_areas(const AreaSurveys& surveys, const AreaHistory& history) {
  const double a0 = history.new_area_m2();
  const MeasuredAreas m = measured_areas(surveys, a0, history.start_hours());
  std::vector<AreaComparison> out;
  for (std::size_t i = 0; i < surveys.surveys.size(); ++i) {
    AreaComparison c;
    c.hours = surveys.surveys[i].hours;
    c.line = surveys.surveys[i].line;
    c.measured_area_m2 = m.area_m2[i];
    c.simulated_area_m2 = history.area_at(c.hours);
    c.area_error_m2 = c.simulated_area_m2 - c.measured_area_m2;
    c.area_error_pct = 100.0 * c.area_error_m2 / a0;
    c.measured_loss_m2 = m.loss_m2[i];
    c.simulated_loss_m2 = a0 - c.simulated_area_m2;
    c.loss_error_m2 = c.simulated_loss_m2 - c.measured_loss_m2;
    // A row at the start measured no loss: it is the reference the losses count from. Several
    // lifters there scatter about their mean by a gauge's noise, which is no loss to take a
    // percentage of (it would read -100% whatever the simulation did).
    const bool at_start = std::fabs(c.hours - history.start_hours()) <= kSameHoursTolerance;
    c.loss_error_pct = !at_start && c.measured_loss_m2 != 0.0 ? 100.0 * c.loss_error_m2 / c.measured_loss_m2
                                                              : std::nan("");
    out.push_back(c);
  }
  return out;
}

ScaleFit fit_time_scale(const AreaHistory& history, const AreaSurveys& surveys) {
  const double t0 = history.start_hours();
  const MeasuredAreas m = measured_areas(surveys, history.new_area_m2(), t0);
  std::vector<double> worn_hours, worn_loss;  // hours since the start
  for (std::size_t i = 0; i < surveys.surveys.size(); ++i)
    if (surveys.surveys[i].hours > t0 + kSameHoursTolerance) {  // a row at the start is the reference
      worn_hours.push_back(surveys.surveys[i].hours - t0);
      worn_loss.push_back(m.loss_m2[i]);
    }
  const double limit = history.extrapolation_limit() - t0, a0 = history.new_area_m2();
  ScaleFit fit = fit_time_scale(worn_hours, limit, [&](std::size_t j, double s, std::vector<double>& r) {
    r.push_back(a0 - history.area_at(t0 + std::min(worn_hours[j] * s, limit)) - worn_loss[j]);
  });
  for (double& h : fit.survey_hours) h += t0;
  return fit;
}

CalibrationResult calibrate_wear_rate(const Scene& scene, const AreaSurveys& surveys,
                                      const CalibrationOptions& opt,
                                      const std::function<void(const CalibrationRun&)>& on_run,
                                      const std::function<WearHistory(const Scene&)>& run_history) {
  const auto fit = [&surveys](const std::vector<StageRecord>& stages) {
    return fit_time_scale(area_history(stages), surveys);
  };
  return calibrate_by_time_scale(scene, survey_hours(surveys), fit, opt, on_run, run_history);
}

}  // namespace millwear::validation
