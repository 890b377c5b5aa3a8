#pragma once
// Error types shared by every module. The app maps them to exit codes:
// InputError -> 2 (bad scene, profile or command line), RunError -> 1 (a run that failed).
#include <stdexcept>
#include <string>

namespace millwear {

// Bad input: carries the file, the key or line, and what was expected.
struct InputError : std::runtime_error {
  std::string file;      // path as the user gave it (may be empty for command-line input)
  std::string where;     // key path ("charge.species[1].density") or "line 12"
  std::string expected;  // what was expected, in the user's units
  InputError(std::string file_, std::string where_, std::string expected_)
      : std::runtime_error(format(file_, where_, expected_)),
        file(std::move(file_)), where(std::move(where_)), expected(std::move(expected_)) {}

  static std::string format(const std::string& f, const std::string& w, const std::string& e) {
    std::string s;
    if (!f.empty()) s += f;
    if (!w.empty()) s += (s.empty() ? "" : ": ") + w;
    s += (s.empty() ? "" : ": ") + e;
    return s;
  }
};

// A run that failed after validation (numerical trouble, I/O failure).
struct RunError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A run stopped by numerical trouble (a state or a liner update that is no longer valid):
// the stages finished before it are kept, and it is never booked as a result.
struct NumericalError : RunError {
  using RunError::RunError;
};

}  // namespace millwear
