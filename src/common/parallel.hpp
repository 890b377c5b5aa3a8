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

#include <sched.h>

namespace millwear {

// The CPUs this process may run on (at least 1): its affinity mask, which `taskset`, Slurm's
// allocation or a container's CPU set narrow; the machine's cores where the mask cannot be read.
inline int core_count() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

// Up to `count` threads, thread t running fn(t); fewer when the system cannot start more (a
// process or memory limit): the caller shares the work among those started, or does it
// itself when none started. Every task's result is the same whichever thread runs it.
template <class F>
std::vector<std::thread> start_threads(int count, const F& fn) {
  std::vector<std::thread> threads;
  threads.reserve(static_cast<std::size_t>(std::max(count, 0)));
  try {
    for (int t = 0; t < count; ++t) threads.emplace_back(fn, t);
  } catch (...) {  // std::system_error, or std::bad_alloc for the thread's state
  }
  return threads;
}

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
  std::vector<std::thread> pool = start_threads(threads - 1, [&worker](int) { worker(); });
  worker();
  for (auto& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace millwear
