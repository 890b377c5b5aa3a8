// Lifter life from the stages of a wear history.
#include "wear/life.hpp"

#include <algorithm>
#include <cmath>

namespace millwear {

LifeLine life_line(const std::vector<double>& hours, const std::vector<double>& height_m, double replacement_height_m) {
  LifeLine life;
  const std::size_t n = std::min(hours.size(), height_m.size());
  if (n == 0) return life;
  for (std::size_t k = 1; k < n; ++k) {
    const double h0 = height_m[k - 1], h1 = height_m[k];
    if (h1 <= replacement_height_m && h0 > replacement_height_m) {
      const double f = (h0 - replacement_height_m) / (h0 - h1);
      life.hours = hours[k - 1] + f * (hours[k] - hours[k - 1]);
      life.a = static_cast<int>(k) - 1;
      life.b = static_cast<int>(k);
      return life;
    }
  }
  if (height_m.front() <= replacement_height_m) return life;
  // Beyond the simulated stages: extrapolate the height trend of the last stages.
  life.extrapolated = true;
  if (n < 2) { life.hours = INFINITY; return life; }
  const std::size_t a = n >= 3 ? n - 3 : 0, b = n - 1;
  const double rate = (height_m[a] - height_m[b]) / (hours[b] - hours[a]);
  life.hours = rate > 0.0 ? hours[b] + (height_m[b] - replacement_height_m) / rate : INFINITY;
  life.a = static_cast<int>(a);
  life.b = static_cast<int>(b);
  return life;
}

namespace {

// Life from the lifter metrics of every stage, `metric(stage)` picking the lifter.
template <typename Metric>
LifeLine life_from(const std::vector<StageRecord>& st, double replacement_height_m, Metric metric) {
  std::vector<double> hours, height;
  for (const StageRecord& r : st) {
    hours.push_back(r.hours);
    height.push_back(metric(r).height_m);
  }
  return life_line(hours, height, replacement_height_m);
}

}  // namespace

bool lifter_worn_out(const LifterMetrics& m, const LifterMetrics& new_m) {
  return m.height_m < kWornOutFraction * new_m.height_m || m.area_m2 < kWornOutFraction * new_m.area_m2;
}

void compute_life(WearHistory& h, double replacement_height_m) {
  const LifeLine life = life_from(h.stages, replacement_height_m, [](const StageRecord& r) { return r.lifter; });
  h.life_h = life.hours;
  h.life_extrapolated = life.extrapolated;
  // Each kind of a pattern on its own (stages that carry every kind's metrics).
  h.kind_life_h.clear();
  h.kind_life_extrapolated.clear();
  std::size_t kinds = h.stages.empty() ? 0 : h.stages.front().kinds.size();
  for (const StageRecord& r : h.stages)
    if (r.kinds.size() != kinds) kinds = 0;
  for (std::size_t k = 0; k < kinds; ++k) {
    const LifeLine kl = life_from(h.stages, replacement_height_m, [k](const StageRecord& r) { return r.kinds[k]; });
    h.kind_life_h.push_back(kl.hours);
    h.kind_life_extrapolated.push_back(kl.extrapolated);
  }
  // A liner of several kinds is relined when any of its kinds reaches the replacement
  // height: the shortest-lived kind's life is the liner's (a plain liner keeps its row-0
  // life above).
  if (kinds > 1) {
    std::size_t first = 0;
    for (std::size_t k = 1; k < kinds; ++k)
      if (h.kind_life_h[k] < h.kind_life_h[first]) first = k;
    h.life_h = h.kind_life_h[first];
    h.life_extrapolated = h.kind_life_extrapolated[first];
  }
}

}  // namespace millwear
