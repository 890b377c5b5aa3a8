// See workers.hpp.
#include "engine/soft/workers.hpp"

#include <algorithm>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define MW_PAUSE() _mm_pause()
#else
#define MW_PAUSE() ((void)0)
#endif

#include "common/parallel.hpp"

namespace millwear::soft {

namespace {

// Claim word: generation in the top 24 bits, the block's end in the next 20, the next range
// in the low 20.
constexpr int kCountBits = 20;
constexpr std::uint64_t kCountMask = (1ull << kCountBits) - 1;
constexpr std::uint64_t kGenerationMask = (1ull << 24) - 1;
constexpr int kMaxRanges = static_cast<int>(kCountMask);
std::uint64_t generation_of(std::uint64_t w) { return w >> (2 * kCountBits); }
int end_of(std::uint64_t w) { return static_cast<int>((w >> kCountBits) & kCountMask); }
int next_of(std::uint64_t w) { return static_cast<int>(w & kCountMask); }
std::uint64_t pack(std::uint64_t gen, int end, int next) {
  return (gen << (2 * kCountBits)) | (static_cast<std::uint64_t>(end) << kCountBits) |
         static_cast<std::uint64_t>(next);
}

// A helper between stages: pure spinning first (a step hands out a stage every few
// microseconds), then yielding, then sleeping until woken.
constexpr int kSpinPauses = 1 << 14;
constexpr int kYields = 1 << 12;

}  // namespace

Workers::Workers(int threads) {
  const int helpers = std::max(1, threads) - 1;
  claims_ = std::make_unique<Claim[]>(static_cast<std::size_t>(helpers) + 1);
  begins_.assign(static_cast<std::size_t>(helpers) + 2, 0);
  // Fewer helpers when the system cannot start them all: the same bits on fewer threads.
  helpers_ = start_threads(helpers, [this](int t) { helper_loop(t + 1); });
}

Workers::~Workers() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_.store(true);
  }
  wake_.notify_all();
  for (std::thread& t : helpers_) t.join();
}

void Workers::work_on_ranges(std::uint64_t gen, int self) {
  const int threads = this->threads();
  int ran = 0;
  for (int k = 0; k < threads; ++k) {
    std::atomic<std::uint64_t>& claim = claims_[static_cast<std::size_t>((self + k) % threads)].word;
    // Its own block from the front; another's from the back, so that the owner keeps the
    // ranges next to those it has run (and their disks in its cache).
    const bool own = k == 0;
    std::uint64_t w = claim.load(std::memory_order_acquire);
    for (;;) {
      if (generation_of(w) != gen || next_of(w) >= end_of(w)) break;
      const std::uint64_t claimed = own ? w + 1 : w - (1ull << kCountBits);
      if (!claim.compare_exchange_weak(w, claimed, std::memory_order_acq_rel, std::memory_order_acquire)) continue;
      // The range is ours and unfinished: the stage cannot change under us.
      job_(ctx_, own ? next_of(w) : end_of(w) - 1);
      ++ran;
      w = claim.load(std::memory_order_acquire);
    }
  }
  // One addition per thread and stage: the count's cache line moves between the cores once
  // per thread, not once per range.
  if (ran > 0) done_.fetch_add(ran, std::memory_order_release);
}

void Workers::dispatch(int ranges, Job job, const void* ctx, const int* begins) {
  if (ranges > kMaxRanges) {
    // Far beyond any stage of a mill slice; split rather than overflow the claim word.
    for (int r0 = 0; r0 < ranges; r0 += kMaxRanges) {
      struct Offset {
        Job job;
        const void* ctx;
        int r0;
      } off{job, ctx, r0};
      dispatch(std::min(kMaxRanges, ranges - r0),
               [](const void* c, int r) {
                 const auto* o = static_cast<const Offset*>(c);
                 o->job(o->ctx, o->r0 + r);
               },
               &off, nullptr);
    }
    return;
  }
  // Generations wrap at 2^24; a helper compares them for equality only.
  const std::uint64_t gen = (generation_.load(std::memory_order_relaxed) + 1) & kGenerationMask;
  job_ = job;
  ctx_ = ctx;
  done_.store(0, std::memory_order_relaxed);
  const int threads = this->threads();
  for (int t = 0; t < threads; ++t) {
    const int begin = begins ? begins[t] : static_cast<int>(static_cast<std::int64_t>(ranges) * t / threads);
    const int end = begins ? begins[t + 1] : static_cast<int>(static_cast<std::int64_t>(ranges) * (t + 1) / threads);
    claims_[static_cast<std::size_t>(t)].word.store(pack(gen, end, begin), std::memory_order_relaxed);
  }
  generation_.store(gen, std::memory_order_seq_cst);
  if (sleeping_.load(std::memory_order_seq_cst) > 0) {
    { std::lock_guard<std::mutex> lock(mutex_); }
    wake_.notify_all();
  }
  work_on_ranges(gen, 0);
  for (int spins = 0; done_.load(std::memory_order_acquire) < ranges; ++spins) {
    if (spins < kSpinPauses) MW_PAUSE();
    else std::this_thread::yield();  // a helper was descheduled: give it the core
  }
}

void Workers::helper_loop(int self) {
  std::uint64_t seen = 0;
  for (;;) {
    std::uint64_t gen = generation_.load(std::memory_order_acquire);
    for (int spins = 0; gen == seen && !stop_.load(std::memory_order_relaxed); ++spins) {
      if (spins < kSpinPauses) {
        MW_PAUSE();
      } else if (spins < kSpinPauses + kYields) {
        std::this_thread::yield();
      } else {
        std::unique_lock<std::mutex> lock(mutex_);
        sleeping_.fetch_add(1, std::memory_order_seq_cst);
        wake_.wait(lock, [&] { return stop_.load() || generation_.load(std::memory_order_seq_cst) != seen; });
        sleeping_.fetch_sub(1, std::memory_order_seq_cst);
        spins = 0;
      }
      gen = generation_.load(std::memory_order_acquire);
    }
    if (stop_.load()) return;
    seen = gen;
    work_on_ranges(gen, self);
  }
}

}  // namespace millwear::soft
