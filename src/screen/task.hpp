#pragma once
// One screened design run as a task (`millwear screen-task OUT I`): row I of OUT/designs.csv
// through `millwear run`'s own code path (study::run_designs) into OUT/designs/NAME, with
// OUT/designs/NAME/task.status saying how it ended. Whatever runs the task (the local pool,
// GNU parallel, a Slurm array) reads the same folder and the same status.
//
// task.status (key=value): design, status = running (written first), finished, failed (with
// reason) or interrupted, exit_code. A task killed outright leaves `running`.
// Exit codes of a task: 0 finished, 1 failed, 2 bad input, 128 + signal interrupted (run
// it again to continue its stages).
#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "screen/screen.hpp"

namespace millwear::screen {

struct TaskOptions {
  const std::atomic<int>* stop_signal = nullptr;  // non-zero: stop at the next window
  std::string commit;                             // the program's git commit, for the manifest
};

struct TaskOutcome {
  std::string design;
  int exit_code = 1;
  bool ran = false;               // the run ended by itself: status, wall_s, error, events hold
  std::string status;             // study::status_name of the design
  double wall_s = 0.0;
  std::string error;              // the design's own error
  std::vector<std::string> events;
  std::string figure_error;
  std::string reason;             // what task.status says (failed: why); when !ran, the exception's text
  bool figures_only = false;      // the history finished, its figures failed: "finished", exit 1
};

// Runs design `index` of `designs` (read from OUT/designs.csv), holding the lock of its
// folder (io/folder_lock.hpp). Throws InputError for an index out of range, a folder another
// process holds or a replicates count in OUT/screen.key that is not one the screen writes;
// every other failure is the outcome.
TaskOutcome run_screen_task(const std::string& out, const std::vector<Candidate>& designs, int index,
                            const TaskOptions& options = {});

// Runs the tasks in order, handing each outcome to on_task, and stops after one that had
// bad input or was interrupted (its exit code is returned); else returns the worst one.
int run_screen_tasks(const std::string& out, const std::vector<int>& indices, const TaskOptions& options,
                     const std::function<void(const TaskOutcome&)>& on_task);

// OUT/designs/NAME/task.status (atomically); line ends in `reason` become spaces.
void write_task_status(const std::string& out, const Candidate& c, const std::string& status, int exit_code,
                       const std::string& reason);

// True when the design's task.status says finished (with_figures: and its figures drawn, exit
// code 0; a task run again over a finished history only redraws them).
bool design_finished(const std::string& out, const Candidate& c, bool with_figures = false);

}  // namespace millwear::screen
