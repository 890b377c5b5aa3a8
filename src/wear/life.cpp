// Lifter life from the stages of a wear history.
#include "wear/life.hpp"

#include <cmath>

namespace millwear {

namespace {

struct Life {
  double hours = 0.0;
  bool extrapolated = false;
};

// Life from the lifter metrics of every stage, `metric(stage)` picking the lifter.
template <typename Metric>
Life life_from(const std::vector<StageRecord>& st, double replacement_height_m, Metric metric) {
  Life life;
  if (st.empty()) return life;
  for (std::size_t k = 1; k < st.size(); ++k) {
    const double h0 = metric(st[k - 1]).height_m, h1 = metric(st[k]).height_m;
    if (h1 <= replacement_height_m && h0 > replacement_height_m) {
      const double f = (h0 - replacement_height_m) / (h0 - h1);
      life.hours = st[k - 1].hours + f * (st[k].hours - st[k - 1].hours);
      return life;
    }
  }
  if (metric(st.front()).height_m <= replacement_height_m) return life;
  // Beyond the simulated stages: extrapolate the height trend of the last stages.
  life.extrapolated = true;
  if (st.size() < 2) { life.hours = INFINITY; return life; }
  const std::size_t a = st.size() >= 3 ? st.size() - 3 : 0, b = st.size() - 1;
  const double rate = (metric(st[a]).height_m - metric(st[b]).height_m) / (st[b].hours - st[a].hours);
  life.hours = rate > 0.0 ? st[b].hours + (metric(st[b]).height_m - replacement_height_m) / rate : INFINITY;
  return life;
}

}  // namespace

bool lifter_worn_out(const LifterMetrics& m, const LifterMetrics& new_m) {
  return m.height_m < kWornOutFraction * new_m.height_m || m.area_m2 < kWornOutFraction * new_m.area_m2;
}

void compute_life(WearHistory& h, double replacement_height_m) {
  const Life life = life_from(h.stages, replacement_height_m, [](const StageRecord& r) { return r.lifter; });
  h.life_h = life.hours;
  h.life_extrapolated = life.extrapolated;
  // Each kind of a pattern on its own (stages that carry every kind's metrics).
  h.kind_life_h.clear();
  h.kind_life_extrapolated.clear();
  std::size_t kinds = h.stages.empty() ? 0 : h.stages.front().kinds.size();
  for (const StageRecord& r : h.stages)
    if (r.kinds.size() != kinds) kinds = 0;
  for (std::size_t k = 0; k < kinds; ++k) {
    const Life kl = life_from(h.stages, replacement_height_m, [k](const StageRecord& r) { return r.kinds[k]; });
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
