#pragma once
// --threads of the commands that run a design's engine: the threads of its step. The
// results do not depend on the count, bit for bit (docs/soft-solver.md, "Threads").
#include <CLI/CLI.hpp>
#include <string>

#include "common/parallel.hpp"
#include "engine/engine.hpp"

namespace millwear::app {

// A thread count as plain decimal digits, 1 to 256. CLI11's integer conversion also takes
// "0x2", "0b10", "0o2" and blanks around the digits; a count written so is a typo or a
// script's mistake, refused (exit 2) rather than read as a number it might not mean.
inline CLI::Validator thread_count() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const bool digits = !text.empty() && text.size() <= 9 &&
                            text.find_first_not_of("0123456789") == std::string::npos;
        const int n = digits ? std::stoi(text) : 0;
        if (!digits || n < 1 || n > 256)
          return "expected a whole number of threads from 1 to 256 in plain decimal digits, got '" + text + "'";
        return "";
      },
      "INT in [1 - 256]", "thread_count");
}

// whose: the step the threads run ("each design's engine step"); up_to: the cores a step
// may take without --threads ("every core", "the cores the designs at once leave").
inline void add_threads_option(CLI::App* cmd, int& threads, const std::string& whose = "the soft engine's step",
                               const std::string& up_to = "every core") {
  cmd->add_option("--threads", threads,
                  "threads of " + whose + " (default: one per " + std::to_string(kDisksPerStepThread) +
                      " disks, up to " + up_to + "; the results are the same bits for any count)")
      ->check(thread_count());
}

// 0 (not given): every core.
inline int step_threads(int requested) { return step_threads_beside(requested, 1); }

}  // namespace millwear::app
