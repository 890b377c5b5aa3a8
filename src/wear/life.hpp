#pragma once
// Lifter life: when the worn lifter reaches the replacement height, or the shell.
#include "mill/mill.hpp"
#include "wear/history.hpp"

namespace millwear {

// Worn to the shell: under kWornOutFraction of the new lifter's height or area left.
constexpr double kWornOutFraction = 0.01;
bool lifter_worn_out(const LifterMetrics& worn, const LifterMetrics& new_lifter);

// Lifter life from stage heights: interpolated where the height crosses the replacement
// height, otherwise extrapolated from the last stages' trend (infinite without a trend).
// The hours are the stages' own (a history started from a worn liner counts from its
// start_hours). Fills kind_life_h for every kind of a pattern from the stages' kinds; a
// pattern's life_h is then its shortest-lived kind's (the liner is relined when any kind of
// lifter reaches the replacement height).
void compute_life(WearHistory& history, double replacement_height_m);

}  // namespace millwear
