#pragma once
// Small helpers shared by the validate and calibrate commands.
#include <cstdio>
#include <string>

#include "app/plain_progress.hpp"
#include "common/units.hpp"
#include "wear/wear.hpp"

namespace millwear::app {

// The --measured file formats, for the help of validate and calibrate (validation/README.md).
inline constexpr const char* kMeasuredFileHelp =
    "Measured file (--measured), CSV; lines starting with # are comments:\n"
    "  profiles    hours,x_mm,y_mm     one block of consecutive rows per survey, points in order\n"
    "                                  along the lifter (lifter-local mm: x along the shell, +x the\n"
    "                                  leading face; y up from the original shell line)\n"
    "  areas only  hours,area_mm2      one row per lifter surveyed (hours may repeat): the lifter's\n"
    "                                  cross-section above the original shell line, mm^2; a row at the\n"
    "                                  history's start (0 h, or lifters.start_hours) is the reference of\n"
    "                                  the area loss (else the scene's lifter at that start)\n"
    "         or   hours,area_loss_mm2 one row per lifter: the area lost since the start, mm^2\n"
    "Examples: validation/lab-mill-surveys.csv, validation/lab-mill-areas.csv.";

// A plain line per finished stage, with the time of day (the histories are read in logs too).
inline WearCallbacks progress_callbacks() {
  WearCallbacks cb;
  cb.on_stage = [](const StageRecord& r) {
    std::printf("  %s  stage %d at %.0f h: lifter area %.1f mm^2, height %.2f mm (%.1f s wall)\n", clock_text().c_str(),
                r.stage, r.hours, in_mm2(r.lifter.area_m2), in_mm(r.lifter.height_m), r.wall_s);
    std::fflush(stdout);
  };
  return cb;
}

}  // namespace millwear::app
