#pragma once
// A duration for the live progress lines of `run` and `screen`: "42s", "3m07s", "2h05m";
// "--" when unknown.
#include <cmath>
#include <cstdio>
#include <string>

namespace millwear::app {

inline std::string duration_text(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  char buf[32];
  if (s < 60) std::snprintf(buf, sizeof buf, "%.0fs", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%dm%02ds", int(s) / 60, int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%dh%02dm", int(s) / 3600, (int(s) % 3600) / 60);
  return buf;
}

}  // namespace millwear::app
