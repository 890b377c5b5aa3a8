// One screened design as a task (see task.hpp).
#include "screen/task.hpp"

#include <algorithm>
#include <csignal>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "io/atomic_write.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "screen/collect.hpp"
#include "study/plan.hpp"
#include "study/run_designs.hpp"

namespace millwear::screen {

namespace {

// A task number outside designs.csv's rows; a list of no design is a damaged file (a screen
// writes every valid candidate and refuses a family with none), not a range to name.
[[noreturn]] void refuse_task_number(const std::string& out, std::size_t designs, int index) {
  if (designs == 0)
    throw InputError(designs_csv(out), "line 2", "at least one design (a screen writes every valid candidate)");
  throw InputError(designs_csv(out), "I",
                   "task numbers in [0, " + std::to_string(designs - 1) + "], got " + std::to_string(index));
}

// The histories each task runs, as the screen wrote them in screen.key (1 without the file).
// Read before any task starts: a damaged count is bad input naming the file, not a task that
// fails or runs another number of histories.
int screen_replicates(const std::string& out) {
  const std::string key_file = screen_key_path(out);
  if (!io::file_exists(key_file)) return 1;
  const std::string text = io::find_value(io::read_key_values(key_file), "replicates", "1");
  const bool digits = !text.empty() && text.size() <= 9 && text.find_first_not_of("0123456789") == std::string::npos;
  const int n = digits ? std::stoi(text) : 0;
  if (n < 1 || n > study::kMaxReplicates)
    throw InputError(key_file, "replicates",
                     "a whole number of histories per design in [1, " + std::to_string(study::kMaxReplicates) +
                         "], as the screen writes it, got '" + printable(text, 40) + "'");
  return n;
}

}  // namespace

void write_task_status(const std::string& out, const Candidate& c, const std::string& status, int exit_code,
                       const std::string& reason) {
  io::KeyValues kv{{"design", c.name}, {"status", status}, {"exit_code", std::to_string(exit_code)}};
  std::string r = reason;
  std::replace(r.begin(), r.end(), '\n', ' ');
  std::replace(r.begin(), r.end(), '\r', ' ');
  if (!r.empty()) kv.emplace_back("reason", r);
  io::write_file_atomic(task_status_path(out, c.name), io::format_key_values(kv, "millwear screen-task"));
}

bool design_finished(const std::string& out, const Candidate& c, bool with_figures) {
  if (!io::file_exists(task_status_path(out, c.name))) return false;
  try {
    const io::KeyValues kv = io::read_key_values(task_status_path(out, c.name));
    return io::find_value(kv, "status") == "finished" && (!with_figures || io::find_value(kv, "exit_code", "0") == "0");
  } catch (const std::exception&) {
    return false;
  }
}

TaskOutcome run_screen_task(const std::string& out, const std::vector<Candidate>& designs, int index,
                            const TaskOptions& options) {
  if (index < 0 || index >= static_cast<int>(designs.size())) refuse_task_number(out, designs.size(), index);
  const Candidate& c = designs[static_cast<std::size_t>(index)];
  const int replicates = screen_replicates(out);
  const std::string dir = design_dir(out, c.name);
  const io::FolderLock lock(dir);  // before the status: a task refused here changes nothing
  write_task_status(out, c, "running", -1, "");
  TaskOutcome o;
  o.design = c.name;
  try {
    // The same code path as `millwear run`: the candidate's folder is what run writes. A
    // re-run task (Slurm requeue, re-emitted job) continues its stages.
    // Replicates as the screen asked (screen.key, read above): N histories, one after another
    // in this task.
    const study::Plan plan =
        study::make_plan({{io::join_path(out, c.scene_file)}, "", "", dir, "", -1, {}, replicates});
    study::RunState state(plan);
    study::RunOptions opt;
    opt.out = dir;
    opt.resume = true;
    opt.lock_folder = false;  // held above
    opt.jobs = 1;
    // One thread per task: the pool (or GNU parallel, or Slurm) already runs a task per core.
    opt.threads = 1;
    opt.stop_signal = options.stop_signal;
    opt.commit = options.commit;
    const study::RunOutcome r = study::run_designs(state, opt);
    o.exit_code = r.interrupted ? 128 + (r.signal == SIGTERM ? SIGTERM : SIGINT) : r.failed || r.figures_failed ? 1 : 0;
    o.figures_only = !r.interrupted && !r.failed && r.figures_failed;
    const study::DesignState& st = *state.designs[0];
    if (o.exit_code == 1) {
      o.reason = st.error;
      if (o.reason.empty()) o.reason = "figures failed (see plots/gnuplot.log in the design's folder): " + r.figure_error;
    }
    o.ran = true;
    o.status = study::status_name(st.status);
    o.wall_s = r.wall_s;
    o.error = st.error;
    o.events = st.events;
    o.figure_error = r.figure_error;
  } catch (const std::exception& e) {
    o.exit_code = dynamic_cast<const InputError*>(&e) ? 2 : 1;
    o.reason = e.what();
  }
  // A finished history whose figures failed is ranked; its exit (1) and reason say so.
  if (o.exit_code == 0 || o.figures_only) write_task_status(out, c, "finished", o.exit_code, o.reason);
  else if (o.exit_code == 1 || o.exit_code == 2) write_task_status(out, c, "failed", o.exit_code, o.reason);
  else
    write_task_status(out, c, "interrupted", o.exit_code,
                      "interrupted (exit " + std::to_string(o.exit_code) + "); run it again to continue");
  return o;
}

int run_screen_tasks(const std::string& out, const std::vector<int>& indices, const TaskOptions& options,
                     const std::function<void(const TaskOutcome&)>& on_task) {
  const std::vector<Candidate> designs = read_designs(out);
  screen_replicates(out);
  // Every task number before the first task runs: a bad one is refused with nothing run.
  for (int i : indices)
    if (i < 0 || i >= static_cast<int>(designs.size())) refuse_task_number(out, designs.size(), i);
  int worst = 0;
  for (int i : indices) {
    const TaskOutcome o = run_screen_task(out, designs, i, options);
    if (on_task) on_task(o);
    // Interrupted: stop here (run the task again to continue). A design that failed or whose
    // inputs are bad is that design's: the task's other designs still run.
    if (o.exit_code >= 128) return o.exit_code;
    worst = std::max(worst, o.exit_code);
  }
  return worst;
}

}  // namespace millwear::screen
