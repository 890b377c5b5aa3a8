#pragma once
// Progress where there is no terminal to redraw (a log file, cron, a Slurm job's output): a
// plain line every `every_s` seconds, and at once when something changes (a design finishes
// a stage or ends, a screen finishes a design), each with the elapsed and remaining time.
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "app/duration_text.hpp"
#include "app/run_view.hpp"
#include "screen/pool.hpp"
#include "study/run_progress.hpp"

namespace millwear::app {

// Without a terminal, `run` and `screen` print a plain progress line this often by default.
inline constexpr double kProgressEveryS = 60.0;

// Local wall-clock time, for log lines read hours later.
inline std::string clock_text() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  localtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &tm);
  return buf;
}

class PlainProgress {
 public:
  explicit PlainProgress(double every_s) : every_s_(every_s) {}

  // `millwear run`: a line per design whose state changed, or every design when the period
  // has passed. Caller holds the run's mutex.
  void tick(const study::RunState& state) {
    const std::size_t n = state.plan.designs.size();
    last_.resize(n);
    const bool due = period_passed();
    std::size_t width = 6;
    for (const auto& d : state.plan.designs) width = std::max(width, d.name.size());
    for (std::size_t i = 0; i < n; ++i) {
      const study::DesignProgress p = study::design_progress(state, i);
      const std::string key = std::to_string(static_cast<int>(p.status)) + "/" + std::to_string(p.stage);
      if (!due && key == last_[i]) continue;
      if (!due && p.status == study::DesignStatus::Waiting) continue;
      last_[i] = key;
      std::fprintf(stderr, "%s  %s\n", clock_text().c_str(),
                   progress_line(p, state.plan.designs[i].name, static_cast<int>(width)).c_str());
    }
    std::fflush(stderr);
  }

  // `millwear screen`: a line when a design finishes or fails, or when the period has passed.
  void tick(const screen::PoolProgress& p) {
    const bool changed = p.done != done_ || p.failed != failed_;
    if (!changed && !period_passed()) return;
    done_ = p.done;
    failed_ = p.failed;
    std::fprintf(stderr, "%s  screen: %d/%d done, %d running, %d failed, elapsed %s, left %s\n", clock_text().c_str(),
                 p.done, p.total, p.running, p.failed, duration_text(p.elapsed_s).c_str(),
                 duration_text(p.left_s).c_str());
    std::fflush(stderr);
  }

 private:
  bool period_passed() {
    const auto now = std::chrono::steady_clock::now();
    if (!started_ || std::chrono::duration<double>(now - last_all_).count() >= every_s_) {
      started_ = true;
      last_all_ = now;
      return true;
    }
    return false;
  }
  double every_s_;
  bool started_ = false;
  std::chrono::steady_clock::time_point last_all_;
  std::vector<std::string> last_;
  int done_ = -1, failed_ = -1;
};

}  // namespace millwear::app
