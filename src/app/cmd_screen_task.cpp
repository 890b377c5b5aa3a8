// `millwear screen-task OUT I [I...]`: design(s) I (rows of OUT/designs.csv) of a screen run
// through `millwear run`'s own code path into OUT/designs/NAME (screen/task.hpp): what the
// screen's local pool, GNU parallel and Slurm array tasks run. Its output is the task's log.
// Exit codes: 0 finished, 1 failed, 2 bad input, 130/143 interrupted (run it again to continue).
#include <CLI/CLI.hpp>

#include <cstdio>

#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "app/signals.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "screen/task.hpp"

namespace millwear::app {

using namespace millwear::screen;

namespace {

int screen_task_command(const std::string& out, const std::vector<int>& indices) {
  SignalScope signals;
  TaskOptions opt;
  opt.stop_signal = &g_signal;
  opt.commit = MILLWEAR_COMMIT;
  // The task's log (logs/NAME.log under GNU parallel and Slurm) says how it ended.
  return run_screen_tasks(out, indices, opt, [](const TaskOutcome& t) {
    if (!t.ran) {
      std::fprintf(stderr, "millwear: %s: %s\n", t.exit_code == 2 ? "error" : "run failed", t.reason.c_str());
      return;
    }
    std::printf("%s: %s after %.1f s%s%s\n", t.design.c_str(), t.status.c_str(), t.wall_s,
                t.error.empty() ? "" : ": ", t.error.c_str());
    for (const auto& e : t.events) std::printf("%s: event: %s\n", t.design.c_str(), e.c_str());
    if (!t.figure_error.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", t.figure_error.c_str());
  });
}

}  // namespace

void register_screen_task(CLI::App& app, Action* action) {
  auto out = std::make_shared<std::string>();
  auto idx = std::make_shared<std::vector<int>>();
  CLI::App* cmd = app.add_subcommand(
      "screen-task", "Run design(s) I of a screen's OUT/designs.csv into OUT/designs/NAME (what GNU parallel and Slurm "
                     "array tasks run)");
  cmd->add_option("out", *out, "the screen's output folder")->required()->check(output_folder());
  cmd->add_option("task", *idx, "task numbers (rows of designs.csv, from 0)")
      ->required()
      ->check(CLI::Validator(
          [](std::string& text) -> std::string {
            // Digits only: an empty argument (an unset $SLURM_ARRAY_TASK_ID) is no task 0.
            if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
              return "expected a task number 0, 1, 2, ..., got '" + text + "'";
            return "";
          },
          "I", "task number"));
  cmd->callback([out, idx, action] { *action = [out, idx] { return screen_task_command(*out, *idx); }; });
}

}  // namespace millwear::app
