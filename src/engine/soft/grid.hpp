#pragma once
// Uniform grid broad phase for the soft backend: cells at least as wide as the largest
// disk plus twice the largest speculative margin, so every candidate pair sits in the 3x3
// block of cells around a disk. Built from scratch each step by counting sort (two passes
// over the disks, no allocation once the arrays reached their size).
#include <algorithm>
#include <cmath>
#include <vector>

namespace millwear::soft {

struct Grid {
  double origin = 0.0;   // the grid covers [origin, origin + side]^2
  double side = 0.0;
  double cell = 1.0;
  int dim = 1;
  std::vector<int> cell_of;   // per disk (-1: not in the grid)
  std::vector<int> start;     // per cell + 1: first index into order
  std::vector<int> order;     // disks sorted by cell, stable (by index within a cell)

  int coord(double v) const {
    const int c = static_cast<int>((v - origin) / cell);
    return std::clamp(c, 0, dim - 1);
  }

  // x, y, active: disk arrays of length n; cell_m at least the interaction range.
  void build(const double* x, const double* y, const unsigned char* active, int n, double cell_m) {
    cell = cell_m;
    dim = std::max(1, static_cast<int>(std::ceil(side / cell)));
    const std::size_t cells = static_cast<std::size_t>(dim) * static_cast<std::size_t>(dim);
    if (start.size() < cells + 1) start.resize(cells + 1);
    std::fill(start.begin(), start.begin() + static_cast<std::ptrdiff_t>(cells) + 1, 0);
    cell_of.resize(static_cast<std::size_t>(n));
    order.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      if (!active[i]) { cell_of[static_cast<std::size_t>(i)] = -1; continue; }
      const int c = coord(y[i]) * dim + coord(x[i]);
      cell_of[static_cast<std::size_t>(i)] = c;
      start[static_cast<std::size_t>(c) + 1] += 1;
    }
    for (std::size_t c = 0; c < cells; ++c) start[c + 1] += start[c];
    // Scatter with a running cursor per cell: reuse the next cell's start as the cursor
    // and shift back afterwards.
    for (int i = 0; i < n; ++i) {
      const int c = cell_of[static_cast<std::size_t>(i)];
      if (c < 0) continue;
      order[static_cast<std::size_t>(start[static_cast<std::size_t>(c)]++)] = i;
    }
    for (std::size_t c = cells; c > 0; --c) start[c] = start[c - 1];
    start[0] = 0;
  }
  int cells() const { return dim * dim; }
  int placed() const { return start[static_cast<std::size_t>(cells())]; }
};

}  // namespace millwear::soft
