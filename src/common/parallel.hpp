#pragma once
// A parallel loop over independent tasks (designs, replicates, sweep points, ladder rungs):
// each runs on its own engine, so the order they finish in changes no result.
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace millwear {

// The machine's cores (at least 1).
inline int core_count() { return static_cast<int>(std::max(1u, std::thread::hardware_concurrency())); }

// How many of `tasks` run at once: `requested` when given (> 0), else the cores; never more
// than the tasks, at least 1.
inline int jobs_for(int requested, std::size_t tasks) {
  const std::size_t wanted = static_cast<std::size_t>(requested > 0 ? requested : core_count());
  return static_cast<int>(std::max<std::size_t>(1, std::min(wanted, tasks)));
}

// The threads of each engine step while `at_once` tasks run side by side: `requested` when
// given (> 0), else the cores the tasks leave, at least 1 (the results are the same bits
// for any count).
inline int step_threads_beside(int requested, int at_once) {
  return requested > 0 ? requested : std::max(1, core_count() / std::max(1, at_once));
}

// Calls fn(i) for every i in [0, n) on up to `jobs` threads, the caller one of them; each
// index once, in any order. An exception stops the handing out of indices (the tasks under
// way finish), and once every thread is done the one of the lowest index among those that
// threw is thrown again here: no exception leaves a thread, whatever its type.
template <class F>
void for_each_index_parallel(std::size_t n, int jobs, const F& fn) {
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::exception_ptr failure;
  std::size_t failed_at = n;
  const auto worker = [&] {
    for (std::size_t i = next++; i < n; i = next++) {
      try {
        fn(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (i < failed_at) failure = std::current_exception(), failed_at = i;
        next = n;
        return;
      }
    }
  };
  const int threads = static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(std::max(jobs, 1), n)));
  std::vector<std::thread> pool;
  pool.reserve(static_cast<std::size_t>(threads) - 1);
  try {
    for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  } catch (...) {  // a thread that cannot start: the caller and those started do the work
  }
  worker();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace millwear
