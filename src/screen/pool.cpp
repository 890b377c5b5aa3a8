// The local worker pool of a screen (see pool.hpp): worker threads each start one task
// process at a time with posix_spawn and wait for it; the calling thread watches for the
// stop signal and reports progress.
#include "screen/pool.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <mutex>
#include <set>
#include <thread>

#include "common/parallel.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"
#include "screen/task.hpp"

extern char** environ;

namespace millwear::screen {

namespace fs = std::filesystem;

std::string self_executable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("millwear") : p.string();
}

namespace {

struct Pool {
  std::mutex mutex;
  std::set<pid_t> running_pids;
  int done = 0, failed = 0, running = 0;
};

// Runs `exe screen-task OUT I` with output to log; returns its exit code (or 128 + signal).
int spawn_task(Pool& pool, const std::string& exe, const std::string& out, int index, const std::string& log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  const std::string idx = std::to_string(index);
  std::vector<char*> argv{const_cast<char*>(exe.c_str()), const_cast<char*>("screen-task"),
                          const_cast<char*>(out.c_str()), const_cast<char*>(idx.c_str()), nullptr};
  pid_t pid = 0;
  int rc;
  {
    std::lock_guard<std::mutex> lock(pool.mutex);
    rc = posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ);
    if (rc == 0) pool.running_pids.insert(pid);
  }
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return 1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  {
    std::lock_guard<std::mutex> lock(pool.mutex);
    pool.running_pids.erase(pid);
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

}  // namespace

PoolOutcome run_task_pool(const std::string& out, const std::vector<Candidate>& designs, const std::vector<int>& todo,
                          int already_done, const PoolOptions& options) {
  PoolOutcome outcome;
  outcome.jobs = jobs_for(options.jobs, todo.size());
  const std::string exe = options.exe.empty() ? self_executable() : options.exe;
  const std::string logs = io::join_path(out, "logs");
  io::ensure_dir(logs);
  Pool pool;
  pool.done = already_done;
  const int total = static_cast<int>(designs.size());
  auto stop = [&options] { return options.stop_signal ? options.stop_signal->load() : 0; };

  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> finished{0};
  std::atomic<bool> go{false};  // the tasks start once on_start has run (it installs the signal handlers)
  const auto work = [&](int) {
    while (!go.load()) std::this_thread::yield();
    for (std::size_t k; (k = next.fetch_add(1)) < todo.size();) {
      if (stop() != 0) break;
      const int i = todo[k];
      {
        std::lock_guard<std::mutex> lock(pool.mutex);
        ++pool.running;
      }
      const Candidate& c = designs[static_cast<std::size_t>(i)];
      const int rc = spawn_task(pool, exe, out, i, io::join_path(logs, c.name + ".log"));
      const bool crashed = rc > 128 && stop() == 0;
      if (crashed) {
        // The task died without a word (a crash, the OOM killer): say so in its status.
        try {
          write_task_status(out, c, "failed", rc,
                            "the task died with signal " + std::to_string(rc - 128) + " (see logs/" + c.name + ".log)");
        } catch (const std::exception&) {
        }
      }
      std::lock_guard<std::mutex> lock(pool.mutex);
      --pool.running;
      if (rc == 0 || (rc == 1 && design_finished(out, c))) ++pool.done;  // 1: its figures failed
      else if (rc == 1 || rc == 2 || crashed) ++pool.failed;
    }
    finished.fetch_add(1);
  };
  // As many of the jobs as the system starts; none started, the tasks run here in turn.
  std::vector<std::thread> workers = start_threads(outcome.jobs, work);
  outcome.jobs = std::max(1, static_cast<int>(workers.size()));
  if (options.on_start) options.on_start(outcome.jobs);
  go = true;
  if (workers.empty()) work(0);
  auto tick = [&] {
    if (!options.on_tick) return;
    std::lock_guard<std::mutex> lock(pool.mutex);
    PoolProgress p;
    p.total = total;
    p.done = pool.done;
    p.running = pool.running;
    p.failed = pool.failed;
    p.elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int fresh = pool.done + pool.failed - already_done;
    const int left = total - pool.done - pool.failed;
    p.left_s = fresh > 0 ? p.elapsed_s * left / fresh : std::nan("");
    options.on_tick(p);
  };
  int last_signal = 0;
  while (finished.load() < workers.size()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const int sig = stop();
    if (sig != 0 && sig != last_signal) {
      // Ctrl-C from a terminal reaches the tasks too; a SIGTERM to this process alone is
      // passed on to the tasks it started, by their process ids.
      std::lock_guard<std::mutex> lock(pool.mutex);
      if (sig == SIGTERM)
        for (pid_t p : pool.running_pids) kill(p, SIGTERM);
      last_signal = sig;
    }
    tick();
  }
  for (auto& w : workers) w.join();
  // The last design may finish after the last tick: the last report has the final counts.
  tick();
  if (options.on_end) options.on_end();
  outcome.signal = stop();
  return outcome;
}

}  // namespace millwear::screen
