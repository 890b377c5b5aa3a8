#pragma once
// The live view of `millwear run` on a terminal (stderr): one line per design, redrawn in
// place four times a second from the run's progress (study/run_progress.hpp).
#include <algorithm>
#include <cstdio>
#include <string>

#include "app/duration_text.hpp"
#include "study/run_progress.hpp"

namespace millwear::app {

inline std::string progress_line(const study::DesignProgress& p, const std::string& name, int w) {
  char buf[320];
  switch (p.status) {
    case study::DesignStatus::Waiting:
      std::snprintf(buf, sizeof buf, "%-*s  waiting for a free job", w, name.c_str());
      break;
    case study::DesignStatus::Running:
      if (p.measuring)
        std::snprintf(buf, sizeof buf, "%-*s  stage %d/%d  %7.0f h  measuring the %s liner ...  elapsed %s", w,
                      name.c_str(), p.resumed_stage, p.stages, p.start_hours, p.resumed_stage > 0 ? "worn" : "new",
                      duration_text(p.elapsed_s).c_str());
      else
        std::snprintf(buf, sizeof buf,
                      "%-*s  stage %d/%d  %7.0f h  sim %8.1f s  %6.2f M disk-steps/s  elapsed %s  left %s", w,
                      name.c_str(), p.stage, p.stages, p.hours, p.simulated_s, p.disk_steps_per_s / 1e6,
                      duration_text(p.elapsed_s).c_str(), duration_text(p.left_s).c_str());
      break;
    case study::DesignStatus::Done:
      std::snprintf(buf, sizeof buf, "%-*s  finished in %s", w, name.c_str(), duration_text(p.wall_s).c_str());
      break;
    case study::DesignStatus::Failed:
      std::snprintf(buf, sizeof buf, "%-*s  FAILED: %.200s", w, name.c_str(), p.error.c_str());
      break;
    case study::DesignStatus::Interrupted:
      std::snprintf(buf, sizeof buf, "%-*s  interrupted", w, name.c_str());
      break;
  }
  return buf;
}

// One line per design, redrawn in place (the cursor moves up over the last drawing).
// Caller holds the run's mutex.
inline void draw_progress(const study::RunState& state, bool& drawn) {
  std::size_t width = 6;
  for (const auto& d : state.plan.designs) width = std::max(width, d.name.size());
  std::string s;
  if (drawn) s += "\x1b[" + std::to_string(state.plan.designs.size()) + "A";
  for (std::size_t i = 0; i < state.plan.designs.size(); ++i)
    s += "\r\x1b[K" + progress_line(study::design_progress(state, i), state.plan.designs[i].name,
                                     static_cast<int>(width)) + "\n";
  std::fputs(s.c_str(), stderr);
  std::fflush(stderr);
  drawn = true;
}

}  // namespace millwear::app
