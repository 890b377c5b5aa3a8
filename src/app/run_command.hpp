#pragma once
// `millwear run`: parse, plan, run (study/run_designs.hpp), print.
#include <string>
#include <vector>

#include "app/plain_progress.hpp"
#include "study/plan.hpp"
#include "study/run_designs.hpp"

namespace millwear::app {

struct RunArgs {
  study::PlanArgs plan;    // the scenes, fidelity, reference, OUT, --continue, --set, --replicates
  study::RunOptions run;   // --resume, --force, --jobs, --threads, --stop-after-stage (run.out: plan.out)
  bool quiet = false;
  double progress_every_s = kProgressEveryS;  // without a terminal: plain progress lines this often
  bool check = false;
  bool vtk = false;        // as --set outputs.vtk=true
};

// Validates every scene, runs the designs, writes OUT, prints the final table to stdout.
// Returns the exit code of `millwear run` (0, 1, 130/143); throws InputError on bad input.
int run_command(const RunArgs& args);

}  // namespace millwear::app
