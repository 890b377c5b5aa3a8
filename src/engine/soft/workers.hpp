#pragma once
// The soft backend's worker pool: a few persistent threads that run the ranges of one stage
// (Box2D v3's approach, written for our step; no Box2D code is used).
//
// Determinism. Work is cut into ranges whose bounds depend only on the data (a fixed number
// of disks or rows per range), never on the thread count. Within a stage every range writes
// only its own outputs: disks or rows of its own, or its own slot of a partial sum. Which
// thread runs a range, and when, therefore changes nothing; reductions add the ranges'
// partial sums afterwards in range order. The same scene and seed give the same bits with
// 1, 2, 3 or 4 threads (tests/test_threads.cpp, "ThreadCountDoesNotChangeTheBits").
//
// Cost. A stage is handed out by bumping a generation counter that the helpers spin on
// (then yield, then sleep on a condition variable after a long idle spell). Nothing is
// allocated per stage: the job is a function pointer and a context pointer. With one thread,
// or a stage of one range, the ranges run inline on the caller, in order.
//
// Affinity. The ranges of a stage are cut into one contiguous block per thread (thread t of
// T: ranges [R t / T, R (t + 1) / T)), each with its own claim counter on its own cache
// line. A thread runs its own block from the front, then takes what is left of the others'
// from their back. Ranges follow the disks' cell order, so a thread keeps meeting the same
// disks stage after stage (colour after colour, substep after substep) and finds them in its
// own cache (with one shared claim counter instead, the ranges fall to the threads at random
// and a disk's cache line moves between the cores at nearly every colour).
#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace millwear::soft {

class Workers {
 public:
  // The grain of the threads' shares of the disks (run_by_disk, run_disks).
  static constexpr int kDiskGrain = 256;

  // threads: the caller plus threads - 1 helpers (at least 1).
  explicit Workers(int threads);
  ~Workers();
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }

  // Calls fn(r) for every r in [0, ranges) and returns when all have run. fn must not
  // depend on which thread runs it.
  template <class F>
  void run(int ranges, const F& fn) {
    if (ranges <= 0) return;
    if (ranges == 1 || helpers_.empty()) {
      for (int r = 0; r < ranges; ++r) fn(r);
      return;
    }
    dispatch(ranges, &call<F>, &fn, nullptr);
  }

  // fn(i0, i1) over disks [0, n) in ranges of kDiskGrain, cut into the threads' blocks as
  // run_by_disk cuts them: for a stage that does the same to every disk whatever the ranges
  // (integration, the step's start), so that a disk meets the thread that has it in the
  // colours.
  template <class F>
  void run_disks(int n, const F& fn) {
    const auto disk_of = [](int r) { return r * kDiskGrain; };
    run_by_disk((n + kDiskGrain - 1) / kDiskGrain, n, disk_of,
                [&](int r) { fn(r * kDiskGrain, std::min(n, (r + 1) * kDiskGrain)); });
  }

  // As run, with the threads' blocks cut where the stage's disks are: disk_of(r) is the
  // first disk range r touches (non-decreasing in r), and thread t of T starts at the first
  // range at or past disk n t / T rounded up to a whole kDiskGrain. A stage whose ranges
  // hold unequal shares of the disks (the colours, the liner rows) then gives each thread
  // the disks it has in the disk stages, so that their cache lines stay on its core.
  template <class F, class D>
  void run_by_disk(int ranges, int n, const D& disk_of, const F& fn) {
    if (ranges <= 0) return;
    if (ranges == 1 || helpers_.empty()) {
      for (int r = 0; r < ranges; ++r) fn(r);
      return;
    }
    const int threads = this->threads();
    for (int t = 1; t < threads; ++t) {
      // Rounded up to a whole kDiskGrain, where run_disks cuts its blocks too.
      const auto bound = (static_cast<std::int64_t>(n) * t / threads + kDiskGrain - 1) / kDiskGrain * kDiskGrain;
      int lo = begins_[static_cast<std::size_t>(t) - 1], hi = ranges;
      while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (disk_of(mid) < bound) lo = mid + 1;
        else hi = mid;
      }
      begins_[static_cast<std::size_t>(t)] = lo;
    }
    begins_[static_cast<std::size_t>(threads)] = ranges;
    dispatch(ranges, &call<F>, &fn, begins_.data());
  }

 private:
  using Job = void (*)(const void*, int);
  template <class F>
  static void call(const void* ctx, int r) {
    (*static_cast<const F*>(ctx))(r);
  }
  // begins: thread t's block starts at begins[t] (begins[threads] = ranges); null: equal
  // blocks.
  void dispatch(int ranges, Job job, const void* ctx, const int* begins);
  // Claims and runs ranges of generation gen until none is left: thread `self`'s block
  // first, then the others' in turn.
  void work_on_ranges(std::uint64_t gen, int self);
  void helper_loop(int self);

  // A thread's claim word: the stage's generation, the end of the thread's block and the
  // next range of it to claim. A range is claimed by compare-and-swap, so a helper late from
  // an earlier stage can never claim a range of a later one (its generation differs), and
  // the job it then reads cannot change before that range is done.
  struct alignas(64) Claim {
    std::atomic<std::uint64_t> word{0};
  };

  std::vector<std::thread> helpers_;
  // The stage being run.
  Job job_ = nullptr;
  const void* ctx_ = nullptr;
  std::unique_ptr<Claim[]> claims_;         // one per thread, the caller's first
  std::vector<int> begins_;                 // run_by_disk's blocks: threads + 1, begins_[0] = 0
  std::atomic<std::uint64_t> generation_{0};  // bumped when every claim word is set
  std::atomic<int> done_{0};     // ranges of the current stage finished
  std::atomic<int> sleeping_{0};
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::condition_variable wake_;
};

// The count of ranges of a stage over n items, size items a range (the last may be shorter).
inline int range_count(std::size_t n, std::size_t size) {
  return static_cast<int>((n + size - 1) / size);
}

}  // namespace millwear::soft
