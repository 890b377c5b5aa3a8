#pragma once
// `millwear run` as a function, so that other commands reuse its one code path: `millwear
// screen-task` runs each screened candidate through it, and the candidate's folder is
// exactly what `millwear run` writes.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear::app {

struct RunArgs {
  std::vector<std::string> scenes;
  std::string out;
  std::string fidelity;
  std::string reference;
  bool resume = false;
  bool quiet = false;
  bool check = false;
  int jobs = 0;
  int stop_after_stage = -1;
};

// Validates every scene, runs the designs, writes OUT, prints the final table to stdout.
// Returns the exit code of `millwear run` (0, 1, 130/143); throws InputError on bad input.
int run_command(const RunArgs& args);

// The designs a scene or comparison file names, loaded and checked as `millwear run` does
// (throws InputError naming the file and key). Their own fidelity is kept.
std::vector<Scene> load_designs(const std::string& path);

}  // namespace millwear::app
