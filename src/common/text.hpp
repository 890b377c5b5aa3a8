#pragma once
// Text helpers of the file readers and the messages.
#include <cstdio>
#include <string>

namespace millwear {

// The text without the blanks around it (space, tab, and the line ends and feeds: a line of
// a file written on Windows keeps its '\r').
inline std::string trim(const std::string& s) {
  constexpr const char* kBlanks = " \t\r\n\f\v";
  const auto b = s.find_first_not_of(kBlanks);
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(kBlanks) - b + 1);
}

// A number in a message, as short as a person would write it: 200, 0.5, 1e-05.
inline std::string short_number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace millwear
