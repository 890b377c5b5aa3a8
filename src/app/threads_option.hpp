#pragma once
// --threads of the commands that run one design: the threads of its engine step. The
// results do not depend on the count, bit for bit (docs/soft-solver.md, "Threads").
#include <CLI/CLI.hpp>

#include "common/parallel.hpp"

namespace millwear::app {

inline void add_threads_option(CLI::App* cmd, int& threads) {
  cmd->add_option("--threads", threads,
                  "threads of the soft engine's step (default: one per 4,096 disks, up to the cores the "
                  "designs at once leave; the results are the same bits for any count)")
      ->check(CLI::Range(1, 256));
}

// 0 (not given): every core.
inline int step_threads(int requested) { return step_threads_beside(requested, 1); }

}  // namespace millwear::app
