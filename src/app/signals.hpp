#pragma once
// Ctrl-C and SIGTERM during a run: the first asks the run to stop, heard between pieces of a
// phase's steps (engine/engine.hpp, step_checking_stop; its finished stages stay on disk for
// --resume); a second one stops at once, unless it is the same signal within a second of the
// first: the same stop delivered twice (`timeout` signals the command and then its process
// group; a job controller may repeat a signal, and the screen's pool passes SIGTERM on to
// tasks that may have had it from the process group already).
#include <time.h>
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdint>
#include <string>

namespace millwear::app {

// The signal that asked the run to stop (0: none). Handed to study::RunOptions::stop_signal.
inline std::atomic<int> g_signal{0};
// When it came, ns on the monotonic clock.
inline std::atomic<std::int64_t> g_signal_ns{0};
inline constexpr std::int64_t kSameStopNs = 1'000'000'000;

// The monotonic clock in ns (clock_gettime is async-signal-safe).
inline std::int64_t monotonic_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

inline void on_signal(int sig) {
  const std::int64_t now = monotonic_ns();
  if (g_signal.load() != 0) {
    if (sig == g_signal.load() && now - g_signal_ns.load() < kSameStopNs) return;  // the first one again
    std::signal(sig, SIG_DFL);                             // a second Ctrl-C: stop now
    std::raise(sig);
    return;
  }
  g_signal_ns.store(now);
  g_signal.store(sig);
}

// Only records the signal, every time: for the screen's pool, whose tasks stop on their own
// (Ctrl-C reaches them from the terminal, the pool passes SIGTERM on).
inline void record_signal(int sig) { g_signal.store(sig); }

// The commands that do not stop between pieces (sweep, tradeoff, rule1) die of the signal
// as they would without a handler (exit 128 + signal), first saying what the stop leaves:
// g_stop_note, set before the handler is installed (write(2) is async-signal-safe).
inline std::string g_stop_note;
inline void note_and_die(int sig) {
  if (!g_stop_note.empty()) (void)!::write(2, g_stop_note.data(), g_stop_note.size());
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

// Installs the handler (on_signal unless given) for SIGINT and SIGTERM for its lifetime and
// clears g_signal.
class SignalScope {
 public:
  explicit SignalScope(void (*handler)(int) = on_signal) {
    struct sigaction sa {};
    sa.sa_handler = handler;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
    g_signal.store(0);
  }
  ~SignalScope() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

}  // namespace millwear::app
