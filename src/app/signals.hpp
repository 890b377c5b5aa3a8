#pragma once
// Ctrl-C and SIGTERM during a run: the first asks the run to stop, heard between pieces of a
// phase's steps (engine/engine.hpp, step_checking_stop; its finished stages stay on disk for
// --resume); a second Ctrl-C stops at once.
#include <atomic>
#include <csignal>

namespace millwear::app {

// The signal that asked the run to stop (0: none). Handed to study::RunOptions::stop_signal.
inline std::atomic<int> g_signal{0};

inline void on_signal(int sig) {
  if (g_signal.load() != 0) {  // second Ctrl-C: stop now
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_signal.store(sig);
}

// Only records the signal, every time: for the screen's pool, whose tasks stop on their own
// (Ctrl-C reaches them from the terminal, the pool passes SIGTERM on).
inline void record_signal(int sig) { g_signal.store(sig); }

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
