#pragma once
// Uniform grid for the soft backend, built from scratch by counting sort (two passes over
// the disks, no allocation once the arrays reached their size). Two uses: the reordering
// of the disks for locality (square cells over the whole mill, at least the interaction
// range wide, so the order depends only on positions), and the pair search (cells over the
// disks' bounding box, one largest reach wide, each disk scanning the cells within its own
// reach plus the largest: broad_phase.hpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/soft/workers.hpp"

namespace millwear::soft {

struct Grid {
  double ox = 0.0, oy = 0.0;  // lower left corner of the grid
  double cell = 1.0;
  int nx = 1, ny = 1;         // columns, rows
  std::vector<int> cell_of;   // per disk (-1: not in the grid)
  std::vector<int> start;     // per cell + 1: first index into order
  std::vector<int> order;     // disks sorted by cell, stable (by index within a cell)
  // Scratch of the threaded build: per block of disks, each cell's count and then cursor
  // (block b's at counts[b * cells ..]); per range of cells, its disks.
  std::vector<int> counts, range_disks;

  // Covers [x0, x0 + w] x [y0, y0 + h] with cells of side cell_m; a point outside falls
  // into the nearest edge cell.
  void fit(double x0, double y0, double w, double h, double cell_m) {
    ox = x0;
    oy = y0;
    cell = cell_m;
    nx = std::max(1, static_cast<int>(std::ceil(w / cell)));
    ny = std::max(1, static_cast<int>(std::ceil(h / cell)));
  }
  int col(double x) const { return std::clamp(static_cast<int>((x - ox) / cell), 0, nx - 1); }
  int row(double y) const { return std::clamp(static_cast<int>((y - oy) / cell), 0, ny - 1); }

  // x, y, active: disk arrays of length n.
  void build(const double* x, const double* y, const unsigned char* active, int n) {
    const std::size_t cells = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
    if (start.size() < cells + 1) start.resize(cells + 1);
    std::fill(start.begin(), start.begin() + static_cast<std::ptrdiff_t>(cells) + 1, 0);
    cell_of.resize(static_cast<std::size_t>(n));
    order.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      if (!active[i]) { cell_of[static_cast<std::size_t>(i)] = -1; continue; }
      const int c = row(y[i]) * nx + col(x[i]);
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
  // The same order, built by the threads at once (grid.cpp); runs build itself on one
  // thread or few disks.
  void build(const double* x, const double* y, const unsigned char* active, int n, Workers& workers);

  int cells() const { return nx * ny; }
  int placed() const { return start[static_cast<std::size_t>(cells())]; }
};

}  // namespace millwear::soft
