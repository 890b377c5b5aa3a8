#pragma once
// Broad phase of the soft backend: speculative margins, the reordering of the disks by
// cell, and the grid the pair search scans. Uniform grids built by counting sort
// (grid.hpp): deterministic, no allocation once warm.
//
// No tunnelling. A disk gets a speculative margin m = 0.1 r_min + 1.5 (|v| + g dt) dt, and
// a pair or liner contact is created when the gap is under the sum of margins (liner: plus
// the liner's own travel |omega| R dt). A disk that keeps its speed within the step
// therefore always has a constraint before it can reach anything. What this cannot see is
// a disk sped up within the step by a collision to more than 1.5x its start speed and then
// travelling more than its margin: that needs a collision speed above r / dt (a disk of 10 mm
// radius at 1/600 s: 6 m/s gained in one step), beyond the stability envelope of any scene we run.
// Against the liner there is a second line of defence: the liner knows its inside, so a
// disk that ended a step with its centre past a face (by up to half a radius) is pushed
// back out the next step. A centre deeper than that is an escape, reported as an event
// (finish.hpp).
#include <cstdint>
#include <vector>

#include "engine/soft/contact_set.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/grid.hpp"
#include "engine/soft/model.hpp"
#include "engine/soft/workers.hpp"

namespace millwear::soft {

// The disks are reordered by cell every this many steps: often enough that neighbours in
// space stay near in memory as the charge tumbles, rarely enough that the permutation
// costs little.
constexpr int kReorderInterval = 64;

struct StepBounds {
  double margin_max_m = 0.0;             // largest margin of an active disk
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0; // box of the active disks' centres
};

// Smallest block of the threaded solve (contact_solver.hpp, "Threads").
constexpr int kMinBlockDisks = 256;

struct BroadPhase {
  Grid mill_grid;  // square cells over the whole mill, for the reordering
  Grid pair_grid;  // cells over the disks' box, for the pair search
  // Disks per block of the threaded solve, set at each reordering from the positions alone:
  // twice the most disks in one row of reordering cells (at least kMinBlockDisks), so that
  // right after a reordering every pair's disks lie in one block or two neighbouring ones.
  int block_disks = kMinBlockDisks;
  std::vector<StepBounds> partial_bounds;  // per range of update_margins
  // Reordering buffers, at their size from the start.
  std::vector<int> new_to_old, old_to_new, ids;
  std::vector<double> doubles;
  std::vector<Body> bodies;
  std::vector<std::uint8_t> bytes;
  void reserve(int disks);
};

// Every active disk's margin from its speed, and the box and largest margin they give.
// Ranges of disks in parallel; the box and largest margin are minima and maxima, which do
// not depend on the order they are taken in.
StepBounds update_margins(const Model& model, Disks& disks, BroadPhase& broad, Workers& workers);

inline bool reorder_due(std::int64_t step, const Disks& disks) {
  return step % kReorderInterval == 0 && disks.n > 0;
}

// Permute every per-disk array into grid order (active disks by cell, then the inactive)
// and carry last step's contacts over to the new indices, re-sorted by key. The order
// depends only on the positions: deterministic.
void reorder_by_cell(const Model& model, const LinerModel& liner, const StepBounds& bounds,
                     BroadPhase& broad, Disks& disks, Contacts& contacts);

// Cells one largest reach wide over the disks' box: a disk's search box (its reach plus the
// largest) spans at most 5 x 5 of them, of which it scans the half after it.
void build_pair_grid(const Model& model, const StepBounds& bounds, const Disks& disks,
                     BroadPhase& broad, Workers& workers);

}  // namespace millwear::soft
