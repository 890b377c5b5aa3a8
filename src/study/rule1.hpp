#pragma once
// Rule 1 of the method: scaling C_model by n and simulated time by 1/n gives the same worn
// profiles, as long as the liner changes little within one update. Checked by running the
// wear history in continuous mode at several factors and comparing the final profiles.
#include <string>
#include <vector>

#include "geometry/polyline.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Rule 1 check: the wear history in continuous mode at several factors (C_model = factor
// * C, simulated time scaled by 1/factor), and the profile deviation between neighbours.
struct Rule1Row {
  double factor = 0.0;
  double simulated_s = 0.0;
  double wall_s = 0.0;
  Polyline profile;                 // final unit surface (lifter-local, m)
  double deviation_m = 0.0;         // largest normal distance to the previous (smaller) factor
  double deviation_pct_height = 0.0;
  std::vector<std::string> events;
};
struct Rule1Report {
  std::vector<Rule1Row> rows;       // increasing factor
  double recommended_factor = 0.0;  // largest factor whose deviation stays under tolerance
  double tolerance_pct_height = 0.0;
};
Rule1Report rule1_check(const Scene& scene, std::vector<double> factors, double tolerance_pct_height);

}  // namespace millwear
