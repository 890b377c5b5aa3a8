#pragma once
// `millwear run`: parse, plan, run (study/run_designs.hpp), print.
#include <string>
#include <vector>

#include "app/plain_progress.hpp"
#include "scene/scene.hpp"

namespace millwear::app {

struct RunArgs {
  std::vector<std::string> scenes;
  std::string out;
  std::string fidelity;
  std::string reference;
  bool resume = false;
  bool force = false;
  bool quiet = false;
  double progress_every_s = kProgressEveryS;  // without a terminal: plain progress lines this often
  bool check = false;
  int jobs = 0;
  int threads = 0;  // --threads: each design's engine step (0: fit to the charge, up to the cores the designs leave)
  int stop_after_stage = -1;
  std::string continue_from;   // --continue RUN
  int continue_stage = -1;     // --stage N (-1: each design's last finished stage)
  bool vtk = false;                    // as --set outputs.vtk=true
  std::vector<std::string> overrides;  // --set KEY=VALUE on every design
  int replicates = 1;                  // --replicates N: histories per design, seeds s .. s+N-1
};

// Validates every scene, runs the designs, writes OUT, prints the final table to stdout.
// Returns the exit code of `millwear run` (0, 1, 130/143); throws InputError on bad input.
int run_command(const RunArgs& args);

}  // namespace millwear::app
