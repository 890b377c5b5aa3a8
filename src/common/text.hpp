#pragma once
// Text helpers of the file readers and the messages.
#include <cmath>
#include <cstddef>
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

// An angle in whole degrees for a line people read: rounded as "%.0f" rounds, and never
// "-0" (a toe at -0.3 deg is at 0).
inline double whole_degrees(double deg) {
  const double r = std::nearbyint(deg);
  return r == 0.0 ? 0.0 : r;
}

// Text as shown in a message: control characters as \xNN escapes, cut after `max` characters.
inline std::string printable(const std::string& text, std::size_t max) {
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < max; ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c == 0x7f) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\x%02x", c);
      out += esc;
    } else {
      out += text[i];
    }
  }
  return text.size() > max ? out + "..." : out;
}

// A field of a file as a message quotes it: printable, at most kShownBytes bytes of it, then
// how long it was (a NUL, a control byte or a cell of megabytes is seen, not echoed).
constexpr std::size_t kShownBytes = 40;
inline std::string shown_text(const std::string& s) {
  return printable(s, kShownBytes) + (s.size() > kShownBytes ? " (" + std::to_string(s.size()) + " bytes)" : "");
}

}  // namespace millwear
