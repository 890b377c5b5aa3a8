#pragma once
// Job lists for running a screen beyond one machine's worker pool: GNU parallel and Slurm
// job arrays. Every job runs `millwear screen-task OUT I [I...]`, which writes only into
// the designs' own folders (OUT/designs/NAME), atomically; `millwear screen --collect OUT`
// ranks whatever finished. Paths are absolute so jobs run from any working directory.
#include <string>
#include <vector>

namespace millwear::screen {

struct EmitOptions {
  std::string binary;       // absolute path of the millwear executable
  std::string out;          // absolute path of the screen's output folder
  std::string name;         // screen name (job name)
  int chunk = 1;            // designs per job / array task
  int max_running = 0;      // Slurm: at most this many tasks at once (%M); 0 = no limit
};

// The tasks (design indices, rows of designs.csv) grouped into jobs of `chunk`.
std::vector<std::vector<int>> chunk_tasks(const std::vector<int>& tasks, int chunk);

// GNU parallel: one shell command a line (`parallel -j N < OUT/jobs.txt`).
std::string parallel_job_list(const std::vector<int>& tasks, const EmitOptions& o);

// Slurm: an sbatch script with a job array, one array task per chunk. Array task t runs
// the designs on line t+1 of OUT/slurm/tasks.txt (written alongside: `tasks_file`), so a
// re-emit of only the missing designs keeps array indices 0..T-1. Logs go to OUT/slurm/.
std::string slurm_script(const std::vector<int>& tasks, const EmitOptions& o, std::string& tasks_file);

// Quotes a path for a POSIX shell ('...').
std::string shell_quote(const std::string& s);
// A path as one word of a POSIX shell command: as it is when nothing in it means anything to
// the shell (letters, digits and _ . / + - : = , @), quoted otherwise.
std::string shell_word(const std::string& s);

}  // namespace millwear::screen
