#pragma once
// Runs one millwear command as a child process with a wall-clock bound and resource limits,
// so that a hang, a crash or an allocation blow-up of the program under test becomes a
// recorded outcome instead of taking the test (or the machine) down with it.
#include <cstdint>
#include <string>
#include <vector>

namespace mutation {

struct Limits {
  double timeout_s = 30.0;                 // wall clock; the child's process group is killed after it
  std::uint64_t address_space_bytes = 0;   // RLIMIT_AS (0: unlimited)
  std::uint64_t file_bytes = 0;            // RLIMIT_FSIZE (0: unlimited); a runaway writer gets SIGXFSZ
};

struct Finished {
  bool timed_out = false;
  bool signaled = false;
  int signal = 0;
  int exit_code = -1;
  double wall_s = 0.0;
  std::string out;  // the first bytes of stdout and stderr (capped: a hostile value may be echoed)
  std::string err;
};

// argv[0] is the program path. Output goes to log_prefix + ".out" / ".err" and the first
// `keep_bytes` of each are returned. stdin is /dev/null.
Finished run_bounded(const std::vector<std::string>& argv, const std::string& log_prefix, const Limits& limits,
                     std::size_t keep_bytes = 64 * 1024);

}  // namespace mutation
