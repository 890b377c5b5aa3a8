#pragma once
// --threads of the commands that run a design's engine: the threads of its step. The
// results do not depend on the count, bit for bit (docs/soft-solver.md, "Threads").
#include <CLI/CLI.hpp>
#include <string>

#include "app/number_checks.hpp"
#include "common/parallel.hpp"
#include "engine/engine.hpp"

namespace millwear::app {

// whose: the step the threads run ("each design's engine step"); up_to: the cores a step
// may take without --threads ("every core", "the cores the designs at once leave").
inline void add_threads_option(CLI::App* cmd, int& threads, const std::string& whose = "the soft engine's step",
                               const std::string& up_to = "every core") {
  cmd->add_option("--threads", threads,
                  "threads of " + whose + " (default: one per " + std::to_string(kDisksPerStepThread) +
                      " disks, up to " + up_to + "; the results are the same bits for any count)")
      ->check(whole_in(1, 256));
}

// 0 (not given): every core.
inline int step_threads(int requested) { return step_threads_beside(requested, 1); }

}  // namespace millwear::app
