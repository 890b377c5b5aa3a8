// Job lists for GNU parallel and Slurm arrays (see jobs.hpp).
#include "screen/jobs.hpp"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <sstream>

namespace millwear::screen {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string shell_word(const std::string& s) {
  const bool plain = !s.empty() && std::all_of(s.begin(), s.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./+-:=,@", c) != nullptr;
  });
  return plain ? s : shell_quote(s);
}

std::vector<std::vector<int>> chunk_tasks(const std::vector<int>& tasks, int chunk) {
  std::vector<std::vector<int>> out;
  const std::size_t k = static_cast<std::size_t>(chunk < 1 ? 1 : chunk);
  for (std::size_t i = 0; i < tasks.size(); i += k)
    out.emplace_back(tasks.begin() + static_cast<long>(i),
                     tasks.begin() + static_cast<long>(std::min(tasks.size(), i + k)));
  return out;
}

std::string parallel_job_list(const std::vector<int>& tasks, const EmitOptions& o) {
  std::ostringstream s;
  for (const auto& job : chunk_tasks(tasks, o.chunk)) {
    s << shell_quote(o.binary) << " screen-task " << shell_quote(o.out);
    for (int i : job) s << " " << i;
    s << "\n";
  }
  return s.str();
}

std::string slurm_script(const std::vector<int>& tasks, const EmitOptions& o, std::string& tasks_file) {
  const auto jobs = chunk_tasks(tasks, o.chunk);
  std::ostringstream tf;
  for (const auto& job : jobs) {
    for (std::size_t k = 0; k < job.size(); ++k) tf << (k ? " " : "") << job[k];
    tf << "\n";
  }
  tasks_file = tf.str();
  std::ostringstream s;
  s << "#!/bin/bash\n"
    << "# millwear screen " << o.name << ": " << tasks.size() << " design(s) in " << jobs.size()
    << " array task(s) of up to " << o.chunk << ".\n"
    << "# Submit: sbatch " << shell_quote(o.out + "/screen.sbatch") << "; when done: millwear screen --collect "
    << shell_quote(o.out) << "\n"
    << "#SBATCH --job-name=millwear-" << o.name << "\n"
    << "#SBATCH --array=0-" << (jobs.empty() ? 0 : jobs.size() - 1);
  if (o.max_running > 0) s << "%" << o.max_running;
  s << "\n"
    << "#SBATCH --ntasks=1\n"
    << "#SBATCH --cpus-per-task=1\n"
    // Slurm reads an #SBATCH path up to the first space and expands its % signs, so the log
    // is opened by the shell instead, with the folder quoted as the other commands have it.
    << "#SBATCH --output=/dev/null\n"
    << "set -u\n"
    << "exec >" << shell_quote(o.out + "/slurm/task-") << "\"${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}.out\" 2>&1\n"
    << "designs=$(sed -n \"$((SLURM_ARRAY_TASK_ID + 1))p\" " << shell_quote(o.out + "/slurm/tasks.txt") << ")\n"
    << "exec " << shell_quote(o.binary) << " screen-task " << shell_quote(o.out) << " $designs\n";
  return s.str();
}

}  // namespace millwear::screen
