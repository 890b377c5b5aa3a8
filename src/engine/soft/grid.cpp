// See grid.hpp.
#include "engine/soft/grid.hpp"

namespace millwear::soft {

namespace {

// Below this many disks the serial build is as fast as handing out its four stages.
constexpr int kThreadedBuildDisks = 4096;
constexpr int kCellsPerRange = 4096;

}  // namespace

// The counting sort of build by blocks of disks, one block per thread. The order it gives,
// by cell and by index within a cell, is the only one there is: the blocks' cut, and so the
// thread count, cannot change it. Block b's disks of cell c go after those of the blocks
// before it: its cursor for c starts at start[c] plus their counts.
void Grid::build(const double* x, const double* y, const unsigned char* active, int n, Workers& workers) {
  const int blocks = workers.threads();
  if (blocks == 1 || n < kThreadedBuildDisks) {
    build(x, y, active, n);
    return;
  }
  const int cell_count = cells();
  const auto cells_n = static_cast<std::size_t>(cell_count);
  if (start.size() < cells_n + 1) start.resize(cells_n + 1);
  cell_of.resize(static_cast<std::size_t>(n));
  order.resize(static_cast<std::size_t>(n));
  counts.resize(static_cast<std::size_t>(blocks) * cells_n);
  const int ranges = range_count(cells_n, kCellsPerRange);
  range_disks.resize(static_cast<std::size_t>(ranges));
  const auto block_begin = [&](int b) { return static_cast<int>(static_cast<std::int64_t>(n) * b / blocks); };
  // Each disk's cell, and the count of each cell's disks in each block.
  workers.run(blocks, [&](int b) {
    int* count = counts.data() + static_cast<std::size_t>(b) * cells_n;
    std::fill(count, count + cell_count, 0);
    for (int i = block_begin(b); i < block_begin(b + 1); ++i) {
      if (!active[i]) { cell_of[static_cast<std::size_t>(i)] = -1; continue; }
      const int c = row(y[i]) * nx + col(x[i]);
      cell_of[static_cast<std::size_t>(i)] = c;
      count[c] += 1;
    }
  });
  // Per cell, the blocks' offsets within it (the counts become them); start[c] holds the
  // cell's disks for now, range_disks each range's.
  workers.run(ranges, [&](int r) {
    const int c0 = r * kCellsPerRange, c1 = std::min(cell_count, c0 + kCellsPerRange);
    int in_range = 0;
    for (int c = c0; c < c1; ++c) {
      int in_cell = 0;
      for (int b = 0; b < blocks; ++b) {
        int& k = counts[static_cast<std::size_t>(b) * cells_n + static_cast<std::size_t>(c)];
        const int t = k;
        k = in_cell;
        in_cell += t;
      }
      start[static_cast<std::size_t>(c)] = in_cell;
      in_range += in_cell;
    }
    range_disks[static_cast<std::size_t>(r)] = in_range;
  });
  // Where each range's disks begin (range_disks becomes that), then each cell's and each
  // block's cursor in it.
  int placed_before = 0;
  for (int& k : range_disks) {
    const int t = k;
    k = placed_before;
    placed_before += t;
  }
  start[cells_n] = placed_before;
  workers.run(ranges, [&](int r) {
    const int c0 = r * kCellsPerRange, c1 = std::min(cell_count, c0 + kCellsPerRange);
    int first = range_disks[static_cast<std::size_t>(r)];
    for (int c = c0; c < c1; ++c) {
      const int in_cell = start[static_cast<std::size_t>(c)];
      start[static_cast<std::size_t>(c)] = first;
      for (int b = 0; b < blocks; ++b)
        counts[static_cast<std::size_t>(b) * cells_n + static_cast<std::size_t>(c)] += first;
      first += in_cell;
    }
  });
  // The scatter, each block into its own slots.
  workers.run(blocks, [&](int b) {
    int* cursor = counts.data() + static_cast<std::size_t>(b) * cells_n;
    for (int i = block_begin(b); i < block_begin(b + 1); ++i) {
      const int c = cell_of[static_cast<std::size_t>(i)];
      if (c >= 0) order[static_cast<std::size_t>(cursor[c]++)] = i;
    }
  });
}

}  // namespace millwear::soft
