// What the caches of this machine give one core: the latency of a dependent load from a
// buffer of each size (a random cycle through its 64-byte lines, so that no prefetcher can
// guess the next one).
//
//   build/cache_latency [MAX_MB]
//
// The size where the latency jumps to the memory's is the last level this core really has,
// which on a virtual machine may be far below the cache the CPU reports (its other tenants
// share it). The soft step's passes read their arrays once each per pass: a charge whose
// per-pass working set fits below the jump streams from cache, a larger one from memory
// (docs/benchmarks.md, "Cost per disk-step"). Prints a table; asserts nothing.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <random>
#include <vector>

namespace {

constexpr std::size_t kLine = 64;

struct alignas(kLine) Line {
  std::uint32_t next = 0;
};

// Nanoseconds per load of a random cycle through `lines` cache lines.
double chase_ns(std::size_t lines) {
  std::vector<std::uint32_t> order(lines);
  std::iota(order.begin(), order.end(), 0u);
  std::mt19937 rng(12345);
  std::shuffle(order.begin(), order.end(), rng);
  std::vector<Line> buffer(lines);
  for (std::size_t k = 0; k < lines; ++k) buffer[order[k]].next = order[(k + 1) % lines];
  // Warm the buffer (and its pages) with one lap, then time enough loads for a tenth of a
  // second or more.
  std::uint32_t at = order[0];
  for (std::size_t k = 0; k < lines; ++k) at = buffer[at].next;
  std::size_t loads = std::max<std::size_t>(lines, 1u << 22);
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < loads; ++k) at = buffer[at].next;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (at == lines) std::puts("");  // keeps the chase from being optimised away
  return s / static_cast<double>(loads) * 1e9;
}

}  // namespace

int main(int argc, char** argv) {
  const double max_mb = argc > 1 ? std::atof(argv[1]) : 256.0;
  if (!(max_mb >= 0.25)) {
    std::fprintf(stderr, "usage: cache_latency [MAX_MB]   (MAX_MB at least 0.25)\n");
    return 2;
  }
  std::printf("buffer (MB)   ns per dependent load\n");
  for (double mb = 0.25; mb <= max_mb; mb *= 2.0) {
    const auto lines = static_cast<std::size_t>(mb * 1024 * 1024 / kLine);
    std::printf("%11.2f   %.1f\n", mb, chase_ns(lines));
    // Between the powers of two, where last levels of 6, 12 or 24 MB end.
    if (mb >= 2.0 && mb * 1.5 <= max_mb) {
      const auto mid = static_cast<std::size_t>(mb * 1.5 * 1024 * 1024 / kLine);
      std::printf("%11.2f   %.1f\n", mb * 1.5, chase_ns(mid));
    }
  }
  return 0;
}
