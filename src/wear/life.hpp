#pragma once
// Lifter life: when the worn lifter reaches the replacement height, or the shell.
#include <vector>

#include "mill/mill.hpp"
#include "wear/history.hpp"

namespace millwear {

// Worn to the shell: under kWornOutFraction of the new lifter's height or area left.
constexpr double kWornOutFraction = 0.01;
bool lifter_worn_out(const LifterMetrics& worn, const LifterMetrics& new_lifter);

// The life from a lifter's heights at the stages' hours: the line through two stages' heights
// reaches the replacement height at `hours`. Where the height crosses the replacement height
// between stages k and k + 1 those are the two (interpolated); past the last stage, the last
// stage and the one two before it (or the first), their trend (extrapolated; infinite without
// a trend). a = b = -1 when the first stage is at or under the replacement height already
// (hours 0), and with fewer than two stages.
struct LifeLine {
  double hours = 0.0;
  bool extrapolated = false;
  int a = -1, b = -1;
};
LifeLine life_line(const std::vector<double>& hours, const std::vector<double>& height_m, double replacement_height_m);

// Lifter life from stage heights (life_line): interpolated where the height crosses the replacement
// height, otherwise extrapolated from the last stages' trend (infinite without a trend).
// The hours are the stages' own (a history started from a worn liner counts from its
// start_hours). Fills kind_life_h for every kind of a pattern from the stages' kinds; a
// pattern's life_h is then its shortest-lived kind's (the liner is relined when any kind of
// lifter reaches the replacement height).
void compute_life(WearHistory& history, double replacement_height_m);

}  // namespace millwear
