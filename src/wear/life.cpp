// Lifter life from the stages of a wear history.
#include "wear/life.hpp"

#include <cmath>

namespace millwear {

bool lifter_worn_out(const LifterMetrics& m, const LifterMetrics& new_m) {
  return m.height_m < kWornOutFraction * new_m.height_m || m.area_m2 < kWornOutFraction * new_m.area_m2;
}

void compute_life(WearHistory& h, double replacement_height_m) {
  h.life_h = 0.0;
  h.life_extrapolated = false;
  const auto& st = h.stages;
  if (st.empty()) return;
  for (std::size_t k = 1; k < st.size(); ++k) {
    const double h0 = st[k - 1].lifter.height_m, h1 = st[k].lifter.height_m;
    if (h1 <= replacement_height_m && h0 > replacement_height_m) {
      const double f = (h0 - replacement_height_m) / (h0 - h1);
      h.life_h = st[k - 1].hours + f * (st[k].hours - st[k - 1].hours);
      return;
    }
  }
  if (st.front().lifter.height_m <= replacement_height_m) return;
  // Beyond the simulated stages: extrapolate the height trend of the last stages.
  h.life_extrapolated = true;
  if (st.size() < 2) { h.life_h = INFINITY; return; }
  const std::size_t a = st.size() >= 3 ? st.size() - 3 : 0, b = st.size() - 1;
  const double rate = (st[a].lifter.height_m - st[b].lifter.height_m) / (st[b].hours - st[a].hours);
  h.life_h = rate > 0.0 ? st[b].hours + (st[b].lifter.height_m - replacement_height_m) / rate : INFINITY;
}

}  // namespace millwear
