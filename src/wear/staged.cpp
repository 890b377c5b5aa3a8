// Staged (quasi-static) wear: with the geometry frozen, a window of revolutions gives the
// shear power on every edge; the real operating time then advances by the step that keeps
// the largest depth increment under the scene's bound, and the next window measures the new
// geometry. Statistics (rule 2: the window) and geometry change (rule 1: the depth bound)
// are separate knobs.
#include <algorithm>

#include "common/units.hpp"
#include "wear/archard.hpp"
#include "wear/wear_step.hpp"

namespace millwear {

WearStep staged_step(const Scene& scene, const MillGeometry& mill, const WindowWork& window,
                     double rate_m3_per_J, double max_hours) {
  // m per operating second, per unit edge
  const auto rates = archard_depths(scene, mill, window.unit_power_W, rate_m3_per_J);
  WearStep step;
  step.hours = max_hours;
  const double max_rate_h = deepest(rates) * kSecondsPerHour;
  if (max_rate_h > 0.0) step.hours = std::min(step.hours, scene.wear.max_depth_step_m / max_rate_h);
  step.depths.resize(rates.size());
  for (std::size_t u = 0; u < rates.size(); ++u) {
    step.depths[u].resize(rates[u].size());
    for (std::size_t j = 0; j < rates[u].size(); ++j) step.depths[u][j] = rates[u][j] * step.hours * kSecondsPerHour;
  }
  return step;
}

}  // namespace millwear
