#pragma once
// "default VALUE" for an option's help, read from the variable the option fills, so that the
// help shows the default the command uses (set once, in its struct) and cannot drift from it.
#include <cstdio>
#include <string>
#include <vector>

namespace millwear::app {

inline std::string default_text(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "default %g", value);
  return text;
}

// An option of several numbers: "default V1 V2 ...".
inline std::string default_text(const std::vector<int>& values) {
  std::string text = "default";
  for (int v : values) text += " " + std::to_string(v);
  return text;
}

}  // namespace millwear::app
