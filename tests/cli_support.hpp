#pragma once
// Running the built `millwear` binary from a test: its exit code and everything it printed.
// One copy for every command-line test (app, profile, validation, calibrate, screen).
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <functional>
#include <map>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace millwear::testing {

struct CliResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr together
};

// A shell command line, stderr folded into stdout.
inline CliResult run_shell(const std::string& command) {
  CliResult r;
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  std::size_t got;
  while ((got = fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, got);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// `millwear ARGS` (ARGS already quoted as the shell needs).
inline CliResult run_millwear(const std::string& args) {
  return run_shell(std::string("\"") + MILLWEAR_BINARY + "\" " + args);
}

// A path in double quotes for the shell.
inline std::string quoted(const std::filesystem::path& p) { return "\"" + p.string() + "\""; }

// A whole file as text ("" if it cannot be read).
inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Every file under a folder, hidden ones included (relative path -> content).
inline std::map<std::string, std::string> files_under(const std::filesystem::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files[std::filesystem::relative(e.path(), dir).string()] = read_text(e.path());
  return files;
}

// The files of two such listings that differ ("-NAME" gone, "+NAME" new, "~NAME" changed),
// one a line; "" when they are the same.
inline std::string changed_files(const std::map<std::string, std::string>& before,
                                 const std::map<std::string, std::string>& after) {
  std::string changes;
  for (const auto& [name, text] : before) {
    const auto it = after.find(name);
    if (it == after.end()) changes += "-" + name + "\n";
    else if (it->second != text) changes += "~" + name + "\n";
  }
  for (const auto& [name, text] : after)
    if (!before.count(name)) changes += "+" + name + "\n";
  return changes;
}

// `millwear ARGS` started in the background (ARGS quoted for the shell; ENV: settings for its
// environment, "TMPDIR=/x PATH=/y:$PATH"), its output into LOG: its pid (-1 if it could not start).
inline pid_t spawn_millwear(const std::string& args, const std::filesystem::path& log, const std::string& env = "") {
  const std::string cmd = (env.empty() ? "" : "export " + env + "; ") + "exec \"" + MILLWEAR_BINARY + "\" " + args +
                          " >" + quoted(log) + " 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// A started millwear sent `sig` once `ready()` holds (checked every 10 ms, for at most
// `ready_s` seconds; not sent if it never does or the process ended first), then waited for
// at most `stop_s` seconds (then killed): its wait status, and whether it was sent.
struct StopResult {
  int status = 0;
  bool sent = false;
  bool stopped_in_time = true;
};
inline StopResult stop_when(pid_t pid, const std::function<bool()>& ready, int sig, double ready_s = 30.0,
                            double stop_s = 60.0) {
  StopResult r;
  const auto start = std::chrono::steady_clock::now();
  const auto since = [](std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  };
  while (since(start) < ready_s) {
    if (::waitpid(pid, &r.status, WNOHANG) == pid) return r;  // ended before it was ready
    if (ready()) {
      ::kill(pid, sig);
      r.sent = true;
      break;
    }
    ::usleep(10000);
  }
  const auto sent = std::chrono::steady_clock::now();
  while (::waitpid(pid, &r.status, WNOHANG) == 0) {
    if (since(sent) > stop_s) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &r.status, 0);
      r.stopped_in_time = false;
      break;
    }
    ::usleep(10000);
  }
  return r;
}

}  // namespace millwear::testing
