#pragma once
// Text helpers of the file readers and the messages.
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

// A field of a file as a message quotes it: a byte below 0x20 (or 0x7f) as \xNN, so that a
// NUL or a control byte is seen; at most kShownBytes bytes of it, then how long it was.
constexpr std::size_t kShownBytes = 40;
inline std::string shown_text(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < kShownBytes; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += s[i];
    }
  }
  if (s.size() > kShownBytes) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

}  // namespace millwear
