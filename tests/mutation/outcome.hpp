#pragma once
// What one case's run of millwear came to: the outcome classes and the checks behind them
// (the message of a refusal, the files a refusal must not leave, the CSV files a success
// writes).
#include <filesystem>
#include <string>
#include <vector>

#include "spawn.hpp"

namespace mutation {

namespace fs = std::filesystem;

enum class Outcome {
  Ok,                // exit 0 and every written CSV well formed, finite and not empty
  Refused,           // exit 2 naming the file and the mutated key (CSV: line), nothing written
  RefusedElsewhere,  // exit 2 naming the file and another key or line, nothing written
  Event,             // exit 1 from a run, with its reason named
  Signal,            // killed by a signal
  Hang,              // the time bound was hit
  Alloc,             // std::bad_alloc or the memory limit
  BadExit,           // anything else (see the detail)
};
const char* outcome_name(Outcome o);
bool is_failure(Outcome o);

// One command of a case and what it must leave behind when it succeeds.
struct Step {
  std::string name;               // "run --check", "charge", ...
  std::vector<std::string> argv;  // argv[0]: the millwear binary
  fs::path out_dir;               // the command's output folder
  bool validation_only = false;   // --check and the like: exit 1 is never an event there
  bool interrupt_is_success = false;  // --stop-after-stage: exit 130 after the stage is a success
  std::vector<std::pair<std::string, std::size_t>> required;  // (file in out_dir, least data rows)
  double timeout_s = 30.0;
};

struct Judged {
  Outcome outcome = Outcome::Ok;
  std::string detail;   // why, for anything but ok
  std::string message;  // the first line of stderr that says something
};

struct Expectation {
  std::string file_name;               // the mutated file's name, which a refusal must contain
  std::vector<std::string> locations;  // exact locations that count as naming the key
  bool any_line = false;               // any "line N" counts
  // Other files of the case (a scene using a mutated profile, the designs of a comparison):
  // a refusal naming one of them with a location is a refusal elsewhere, not a bad exit.
  std::vector<std::string> other_files;
};

// files: the regular files under the case folder before the command ran (a refusal may
// not add any).
Judged judge(const Step& step, const Finished& run, const Expectation& expect, const fs::path& case_dir,
             const std::vector<fs::path>& files_before);

std::vector<fs::path> files_under(const fs::path& dir, const fs::path& skip);

// Every CSV under dir well formed (as many fields as the header, quotes closed) and every
// number in it finite; returns the first problem, or "".
std::string check_csv_tree(const fs::path& dir);

}  // namespace mutation
