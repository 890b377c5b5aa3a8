// Rule 1: the wear history at several C_model factors, and how far their profiles part.
#include "study/rule1.hpp"

#include "scene/limits.hpp"

#include <algorithm>
#include <chrono>

#include "common/errors.hpp"
#include "wear/history.hpp"

namespace millwear {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

Rule1Report rule1_check(const Scene& scene, std::vector<double> factors, double tolerance_pct_height) {
  std::sort(factors.begin(), factors.end());
  Rule1Report report;
  report.tolerance_pct_height = tolerance_pct_height;
  // Every factor's run within the limits (steps of a continuous stage, updates) before any runs.
  for (double f : factors) {
    Scene s = scene;
    s.wear.mode = WearMode::Continuous;
    s.wear.factor = f;
    if (!(f > 0.0 && f <= 1e12))
      throw InputError("", "--factors", "factors in (0, 1e12], got " + std::to_string(f));
    check_run_limits(s, scene.source_file);
  }
  const MillGeometry new_mill = build_scene_mill(scene);
  const double height = measure_lifter(new_mill.units[0], new_mill.radius_m).height_m;
  for (double f : factors) {
    Scene s = scene;
    s.wear.mode = WearMode::Continuous;
    s.wear.factor = f;
    const auto t0 = Clock::now();
    Rule1Row row;
    row.factor = f;
    WearHistory h;
    try {
      h = run_wear_history(s);
    } catch (const NumericalError& e) {
      // A factor whose update the reshaping cannot take does not qualify; the others still run.
      row.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
      row.events = {e.what()};
      report.rows.push_back(row);
      continue;
    }
    row.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    for (const auto& st : h.stages) row.simulated_s += st.simulated_s;
    row.profile = h.stages.back().units[0].surface;
    row.events = h.events;
    if (!report.rows.empty() && !report.rows.back().profile.empty()) {
      const Polyline& prev = report.rows.back().profile;
      double d = 0.0;
      for (const Vec2& p : row.profile) d = std::max(d, distance_to_polyline(p, prev));
      for (const Vec2& p : prev) d = std::max(d, distance_to_polyline(p, row.profile));
      row.deviation_m = d;
      row.deviation_pct_height = 100.0 * d / height;
    }
    report.rows.push_back(row);
  }
  // Largest factor that agrees with every smaller one within tolerance (a run that hit the
  // rule-1 bound or another event never qualifies).
  if (!report.rows.empty() && report.rows.front().events.empty())
    report.recommended_factor = report.rows.front().factor;
  for (std::size_t k = 1; k < report.rows.size(); ++k) {
    if (report.rows[k].deviation_pct_height > tolerance_pct_height || !report.rows[k].events.empty()) break;
    report.recommended_factor = report.rows[k].factor;
  }
  return report;
}

}  // namespace millwear
