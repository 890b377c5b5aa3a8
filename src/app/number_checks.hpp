#pragma once
// The checks of the commands' number options. CLI11's own Range lets "nan" through (every
// comparison with NaN is false) and prints an open bound as DBL_MAX in full; these refuse
// anything but a finite number in range (exit 2, as every bad command line) and say what
// was expected.
#include <CLI/CLI.hpp>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/text.hpp"

namespace millwear::app {

namespace number_checks_detail {

// The option's text as a finite double; false if it is not one (trailing text, NaN, inf).
inline bool finite_number(const std::string& text, double& v) {
  if (text.empty()) return false;
  const char* begin = text.c_str();
  char* end = nullptr;
  errno = 0;
  v = std::strtod(begin, &end);
  return end != begin && *end == '\0' && errno != ERANGE && std::isfinite(v);
}

// The option's text as a whole number written in plain decimal digits; false for anything
// else: CLI11's integer conversion also takes "0x2", "0b10", "0o2" and blanks around the
// digits, and a count written so is a typo or a script's mistake, not a number it means.
inline bool plain_whole(const std::string& text, long long& v) {
  if (text.empty() || text.size() > 15 || text.find_first_not_of("0123456789") != std::string::npos)
    return false;
  v = std::stoll(text);
  return true;
}

}  // namespace number_checks_detail

// A finite number in [lo, hi].
inline CLI::Validator finite_in(double lo, double hi) {
  using namespace number_checks_detail;
  const std::string range = "[" + short_number(lo) + ", " + short_number(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& text) -> std::string {
        double v = 0.0;
        if (!finite_number(text, v) || v < lo || v > hi) return "expected a number in " + range + ", got " + text;
        return "";
      },
      "NUMBER in " + range, "finite_in");
}

// A whole number in [lo, hi], in plain decimal digits (counts: jobs, threads, frames, ...).
inline CLI::Validator whole_in(long long lo, long long hi) {
  using namespace number_checks_detail;
  const std::string range = "[" + std::to_string(lo) + " - " + std::to_string(hi) + "]";
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        long long v = 0;
        if (!plain_whole(text, v) || v < lo || v > hi)
          return "expected a whole number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                 " in plain decimal digits, got '" + text + "'";
        return "";
      },
      "INT in " + range, "whole_in");
}

// A finite number above zero.
inline CLI::Validator finite_positive() {
  using namespace number_checks_detail;
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0.0;
        if (!finite_number(text, v) || !(v > 0.0)) return "expected a finite number > 0, got " + text;
        return "";
      },
      "NUMBER > 0", "finite_positive");
}

}  // namespace millwear::app
