// What a cache line costs to move between two cores of this machine: two threads, pinned to
// two CPUs, pass a counter back and forth through one line, and the time of a round trip
// (the line there and back) is printed.
//
//   build/core_to_core [CPU_A CPU_B] [ROUND_TRIPS]
//
// The soft step's threads share a line whenever one writes what the other reads next (a
// stage's hand-out, the disks at the edge of their blocks, a count): its speed-up on two
// threads depends on this figure as much as on the work (docs/benchmarks.md, "Threads").
// On a virtual machine the figure can change while a run goes on, as the host moves the
// virtual CPUs between its cores and sockets. Prints one line; asserts nothing.
#include <pthread.h>
#include <sched.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

namespace {

struct alignas(64) Line {
  std::atomic<long> value{0};
};

bool pin_to(int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  return pthread_setaffinity_np(pthread_self(), sizeof set, &set) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  const int cpu_a = argc > 2 ? std::atoi(argv[1]) : 0;
  const int cpu_b = argc > 2 ? std::atoi(argv[2]) : 1;
  const long trips = argc == 2 ? std::atol(argv[1]) : argc > 3 ? std::atol(argv[3]) : 1000000;
  if (trips < 1 || cpu_a < 0 || cpu_b < 0 || cpu_a == cpu_b) {
    std::fprintf(stderr, "usage: core_to_core [CPU_A CPU_B] [ROUND_TRIPS]   (two different CPUs)\n");
    return 2;
  }
  Line line;
  bool pinned_b = true;
  std::thread other([&] {
    pinned_b = pin_to(cpu_b);
    for (long k = 0; k < trips; ++k) {
      while (line.value.load(std::memory_order_acquire) != 2 * k + 1) {
      }
      line.value.store(2 * k + 2, std::memory_order_release);
    }
  });
  const bool pinned_a = pin_to(cpu_a);
  const auto t0 = std::chrono::steady_clock::now();
  for (long k = 0; k < trips; ++k) {
    line.value.store(2 * k + 1, std::memory_order_release);
    while (line.value.load(std::memory_order_acquire) != 2 * k + 2) {
    }
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  other.join();
  if (!pinned_a || !pinned_b) {
    std::fprintf(stderr, "core_to_core: could not pin the threads to CPUs %d and %d\n", cpu_a, cpu_b);
    return 1;
  }
  std::printf("CPUs %d and %d: %.1f ns a round trip (%ld round trips)\n", cpu_a, cpu_b,
              s / static_cast<double>(trips) * 1e9, trips);
  return 0;
}
