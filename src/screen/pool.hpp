#pragma once
// The local worker pool of a screen: one `millwear screen-task OUT I` process per design
// (the same command GNU parallel and Slurm run), at most `jobs` at a time, each with its
// output in OUT/logs/NAME.log. A crash of one design never takes the others down, and a
// task that dies without a word (a crash, the OOM killer) gets a failed task.status naming
// the signal. Nothing here prints or installs signal handlers: the caller records a signal
// in stop_signal and watches the pool through on_tick.
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "screen/screen.hpp"

namespace millwear::screen {

// The running program (from /proc/self/exe), the one the tasks run; "millwear" (from PATH)
// when that cannot be read.
std::string self_executable();

struct PoolProgress {
  int total = 0;            // designs in the screen
  int done = 0, running = 0, failed = 0;
  double elapsed_s = 0.0;
  double left_s = 0.0;      // elapsed x designs left / designs finished in this pool (NaN before one)
};

struct PoolOptions {
  std::string exe;          // the millwear executable ("": self_executable())
  int jobs = 0;             // tasks at once (0: the hardware's cores; never more than the tasks)
  // Non-zero (a signal number): start no more tasks; SIGTERM is passed on to the running
  // tasks by their process ids (Ctrl-C from a terminal reaches them by itself).
  const std::atomic<int>* stop_signal = nullptr;
  std::function<void(int jobs)> on_start;              // before the first task starts
  // About four times a second and once at the end, from the calling thread.
  std::function<void(const PoolProgress&)> on_tick;
  std::function<void()> on_end;                        // after the last task and the last tick
};

struct PoolOutcome {
  int jobs = 0;
  int signal = 0;           // the stop signal that ended the pool early (0: every task ran)
};

// Runs the tasks `todo` (rows of designs.csv) of the screen in `out`; already_done counts
// the designs finished before (they count as done in the progress).
PoolOutcome run_task_pool(const std::string& out, const std::vector<Candidate>& designs,
                          const std::vector<int>& todo, int already_done, const PoolOptions& options);

}  // namespace millwear::screen
