#include "engine/soft/broad_phase.hpp"

#include <algorithm>
#include <cmath>

namespace millwear::soft {

namespace {

// The margin covers a disk that speeds up within the step to 1.5 times its start speed
// plus gravity's dt (broad_phase.hpp, "No tunnelling").
constexpr double kMarginSpeedFactor = 1.5;
// Reordering cells: two interaction ranges (largest radius plus largest margin) wide, so
// that the order follows the positions and not the noise of a finer grid.
constexpr double kReorderCellRanges = 2.0;
// Pair-search cell side over the largest reach.
constexpr double kPairCellReaches = 1.0;
// Above any coordinate in metres: the first disk replaces it.
constexpr double kUnbounded = 1e300;

}  // namespace

void BroadPhase::reserve(int disks) {
  const auto n = static_cast<std::size_t>(disks);
  new_to_old.assign(n, 0);
  ids.assign(n, 0);
  old_to_new.assign(n, 0);
  bytes.assign(n, 0);
  doubles.assign(n, 0.0);
  bodies.resize(n + 1);  // its last body (a dummy) is never written by the reordering
}

StepBounds update_margins(const Model& model, Disks& disks, BroadPhase& broad, Workers& workers) {
  const double g = kGravity;
  const double dt = model.dt_s;
  constexpr std::size_t kPerRange = 1024;
  const int ranges = range_count(static_cast<std::size_t>(disks.n), kPerRange);
  if (broad.partial_bounds.size() < static_cast<std::size_t>(ranges))
    broad.partial_bounds.resize(static_cast<std::size_t>(ranges));
  workers.run(ranges, [&](int r) {
    const std::size_t i0 = static_cast<std::size_t>(r) * kPerRange;
    const std::size_t i1 = std::min(static_cast<std::size_t>(disks.n), i0 + kPerRange);
    double margin_max = 0.0;
    double bx0 = kUnbounded, by0 = kUnbounded, bx1 = -kUnbounded, by1 = -kUnbounded;
    for (std::size_t k = i0; k < i1; ++k) {
      if (!disks.active[k]) continue;
      const Body& b = disks.body[k];
      const double speed = std::sqrt(b.vx * b.vx + b.vy * b.vy);
      disks.margin[k] = model.margin_base_m + kMarginSpeedFactor * (speed + g * dt) * dt;
      margin_max = std::max(margin_max, disks.margin[k]);
      bx0 = std::min(bx0, disks.x[k]);
      bx1 = std::max(bx1, disks.x[k]);
      by0 = std::min(by0, disks.y[k]);
      by1 = std::max(by1, disks.y[k]);
    }
    broad.partial_bounds[static_cast<std::size_t>(r)] = {margin_max, bx0, by0, bx1, by1};
  });
  StepBounds bounds;
  double bx0 = kUnbounded, by0 = kUnbounded, bx1 = -kUnbounded, by1 = -kUnbounded;
  for (int r = 0; r < ranges; ++r) {
    const StepBounds& p = broad.partial_bounds[static_cast<std::size_t>(r)];
    bounds.margin_max_m = std::max(bounds.margin_max_m, p.margin_max_m);
    bx0 = std::min(bx0, p.x0);
    by0 = std::min(by0, p.y0);
    bx1 = std::max(bx1, p.x1);
    by1 = std::max(by1, p.y1);
  }
  if (bx0 > bx1) bx0 = bx1 = by0 = by1 = 0.0;  // no active disk
  bounds.x0 = bx0;
  bounds.y0 = by0;
  bounds.x1 = bx1;
  bounds.y1 = by1;
  return bounds;
}

void reorder_by_cell(const Model& model, const LinerModel& liner, const StepBounds& bounds,
                     BroadPhase& broad, Disks& disks, Contacts& contacts) {
  // Cells over the whole mill: the order depends on the positions (and this width) only.
  const double side = 2.0 * (liner.max_r_m + 2.0 * model.r_max_m);
  Grid& grid = broad.mill_grid;
  grid.fit(-0.5 * side, -0.5 * side, side, side,
           kReorderCellRanges * (model.r_max_m + bounds.margin_max_m));
  grid.build(disks.x.data(), disks.y.data(), disks.active.data(), disks.n);
  int most_in_row = 0;
  for (int row = 0; row < grid.ny; ++row)
    most_in_row = std::max(most_in_row, grid.start[static_cast<std::size_t>((row + 1) * grid.nx)] -
                                            grid.start[static_cast<std::size_t>(row * grid.nx)]);
  broad.block_disks = std::max(kMinBlockDisks, 2 * most_in_row);

  const auto n = static_cast<std::size_t>(disks.n);
  std::vector<int>& perm = broad.new_to_old;
  std::size_t k = 0;
  for (int c = 0; c < grid.placed(); ++c) perm[k++] = grid.order[static_cast<std::size_t>(c)];
  for (std::size_t i = 0; i < n; ++i)
    if (grid.cell_of[i] < 0) perm[k++] = static_cast<int>(i);
  std::vector<int>& inverse = broad.old_to_new;
  for (std::size_t i = 0; i < n; ++i)
    inverse[static_cast<std::size_t>(perm[i])] = static_cast<int>(i);
  auto permute = [&](auto& v, auto& buffer) {
    for (std::size_t i = 0; i < n; ++i) buffer[i] = v[static_cast<std::size_t>(perm[i])];
    v.swap(buffer);
  };
  for (auto* v : {&disks.x, &disks.y, &disks.angle, &disks.radius, &disks.mass, &disks.margin})
    permute(*v, broad.doubles);
  permute(disks.body, broad.bodies);
  permute(disks.active, broad.bytes);
  permute(disks.species, broad.bytes);
  permute(disks.id, broad.ids);
  for (std::size_t i = 0; i < n; ++i) disks.slot[static_cast<std::size_t>(disks.id[i])] = static_cast<int>(i);

  PairSet& pairs = contacts.pairs_old;
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    PairGap& c = pairs.gap[q];
    int a = inverse[static_cast<std::size_t>(c.a)], b = inverse[static_cast<std::size_t>(c.b)];
    if (a > b) {
      // Swapping the roles flips the normal and tangent: the tangent impulse on the new a
      // keeps its sign, the rolling couple on it changes sign.
      std::swap(a, b);
      pairs.impulse[q].lr = -pairs.impulse[q].lr;
    }
    c.a = a;
    c.b = b;
    pairs.key[q].key = pair_key(a, b);
  }
  LinerSet& liner_contacts = contacts.liner_old;
  for (std::size_t q = 0; q < liner_contacts.size(); ++q) {
    LinerGap& c = liner_contacts.gap[q];
    c.a = inverse[static_cast<std::size_t>(c.a)];
    liner_contacts.key[q].key = pair_key(c.a, liner_contacts.info[q].owner);
  }
  // This step's sets hold nothing yet: they serve as the sort buffers.
  sort_by_key(contacts.pairs_old, contacts.pairs, disks.n, contacts.sort_scratch);
  sort_by_key(contacts.liner_old, contacts.liner, disks.n, contacts.sort_scratch);
}

void build_pair_grid(const Model& model, const StepBounds& bounds, const Disks& disks,
                     BroadPhase& broad, Workers& workers) {
  broad.pair_grid.fit(bounds.x0, bounds.y0, bounds.x1 - bounds.x0, bounds.y1 - bounds.y0,
                      kPairCellReaches * (model.r_max_m + bounds.margin_max_m));
  broad.pair_grid.build(disks.x.data(), disks.y.data(), disks.active.data(), disks.n, workers);
}

}  // namespace millwear::soft
