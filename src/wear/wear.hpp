#pragma once
// Wear: Archard's law per liner edge and the wear history, one stage a file:
//   window     simulate_window: the charge on a frozen liner, shear work per edge, batch errors
//   archard    archard_depths: shear work -> depth per edge (A dh = C dw), the wear rate C
//   wear_step  staged_step / continuous_step: the depths of one update and the hours they stand for
//   reshape    reshape: apply the depths, re-smooth, check (a numerical failure is an error)
//   history    run_wear_history: the stages of one design, as named calls
//   life       compute_life: hours to the replacement height
#include "wear/archard.hpp"
#include "wear/history.hpp"
#include "wear/life.hpp"
#include "wear/reshape.hpp"
#include "wear/window.hpp"
