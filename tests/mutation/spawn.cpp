#include "spawn.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <thread>

namespace mutation {

namespace {

std::string head_of(const std::string& path, std::size_t n) {
  std::ifstream in(path, std::ios::binary);
  std::string s(n, '\0');
  in.read(&s[0], static_cast<std::streamsize>(n));
  s.resize(static_cast<std::size_t>(in.gcount()));
  return s;
}

void set_limit(int resource, std::uint64_t bytes) {
  if (bytes == 0) return;
  struct rlimit rl;
  rl.rlim_cur = rl.rlim_max = static_cast<rlim_t>(bytes);
  setrlimit(resource, &rl);
}

}  // namespace

Finished run_bounded(const std::vector<std::string>& argv, const std::string& log_prefix, const Limits& limits,
                     std::size_t keep_bytes) {
  Finished f;
  const std::string out_path = log_prefix + ".out", err_path = log_prefix + ".err";
  // Everything the child needs is prepared before fork: between fork and exec only
  // async-signal-safe calls are made (the parent runs several workers as threads).
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int out_fd = open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int err_fd = open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int null_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
  if (out_fd < 0 || err_fd < 0 || null_fd < 0) {
    f.exit_code = -1;
    f.err = "mutation: cannot open the log files " + log_prefix + ".*";
    if (out_fd >= 0) close(out_fd);
    if (err_fd >= 0) close(err_fd);
    if (null_fd >= 0) close(null_fd);
    return f;
  }
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);  // its own process group, so a timeout also ends whatever it started (gnuplot)
    set_limit(RLIMIT_AS, limits.address_space_bytes);
    set_limit(RLIMIT_FSIZE, limits.file_bytes);
    struct rlimit no_core{0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    dup2(null_fd, 0);
    dup2(out_fd, 1);
    dup2(err_fd, 2);
    execv(args[0], args.data());
    _exit(127);
  }
  close(out_fd);
  close(err_fd);
  close(null_fd);
  if (pid < 0) {
    f.err = "mutation: fork failed";
    return f;
  }
  setpgid(pid, pid);  // the same as the child does, whichever runs first
  int status = 0;
  for (;;) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (elapsed > limits.timeout_s) {
      f.timed_out = true;
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(elapsed < 1.0 ? 2 : 20));
  }
  kill(-pid, SIGKILL);  // anything of its group still running (none after a normal exit)
  f.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!f.timed_out) {
    if (WIFSIGNALED(status)) {
      f.signaled = true;
      f.signal = WTERMSIG(status);
    } else if (WIFEXITED(status)) {
      f.exit_code = WEXITSTATUS(status);
    }
  }
  f.out = head_of(out_path, keep_bytes);
  f.err = head_of(err_path, keep_bytes);
  return f;
}

}  // namespace mutation
