#include "engine/soft/narrow_phase.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/vec2.hpp"

namespace millwear::soft {

namespace {

// The liner lookup is built for this many times the reach asked of it, so that a charge
// speeding up does not rebuild it step after step.
constexpr double kLinerReachHeadroom = 1.5;
// Of a disk at rest: its radius plus the margins of two disks at rest.
constexpr double kRestMargins = 2.0;

// The gap of a new disk-pair contact (all that the skip test of the passes reads).
void add_pair_contact(const Disks& disks, PairSet& pairs, std::size_t q, int i, int j) {
  const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
  PairGap& g = pairs.gap[q];
  ContactKey& key = pairs.key[q];
  g.a = i;
  g.b = j;
  pairs.state[q] = 0;
  key.key = pair_key(i, j);
  key.event_J = 0.0;
  const double dx = disks.x[a] - disks.x[b], dy = disks.y[a] - disks.y[b];
  const double dist = std::sqrt(dx * dx + dy * dy);
  if (dist > 0.0) {
    g.nx = dx / dist;
    g.ny = dy / dist;
  } else {
    g.nx = 0.0;
    g.ny = 1.0;
  }
  g.s0 = dist - disks.radius[a] - disks.radius[b];
}

}  // namespace

void build_liner_search(const Model& model, const LinerModel& liner, LinerSearch& search) {
  const double rest_reach =
      kLinerReachHeadroom * (model.r_max_m + kRestMargins * model.margin_base_m);
  search.lookup.build(liner.mill, std::max(search.reach_needed_m, rest_reach));
}

void fit_liner_search(const Model& model, const LinerModel& liner, const StepBounds& bounds,
                      double mill_speed_rad_s, LinerSearch& search) {
  const double reach = model.r_max_m + bounds.margin_max_m +
                       std::fabs(mill_speed_rad_s) * liner.max_r_m * model.dt_s;
  if (reach <= search.lookup.reach_m()) return;
  search.reach_needed_m = kLinerReachHeadroom * reach;
  search.lookup.build(liner.mill, search.reach_needed_m);
}

// Each pair is found once: a disk scans only the cells after its own in grid order (the
// rest of its own cell and row, the rows above) within its reach plus the largest reach,
// which holds every partner it can have. The pairs are then bucketed by their lower index
// and each bucket sorted, so the list comes out in key order.
void find_pairs(const Model& model, const Disks& disks, const Grid& grid,
                const StepBounds& bounds, PairSearch& search, PairSet& pairs,
                Workers& workers) {
  using Candidate = PairSearch::Candidate;
  constexpr std::size_t kPerRange = 1024;  // candidates (disks) per range of the scan
  pairs.clear();
  const int nx = grid.nx;
  const int* start = grid.start.data();
  const double* x = disks.x.data();
  const double* y = disks.y.data();
  const double* r = disks.radius.data();
  const double* margin = disks.margin.data();
  const int placed = grid.placed();
  search.candidates.resize(static_cast<std::size_t>(placed));
  const int ranges = range_count(static_cast<std::size_t>(placed), kPerRange);
  if (search.found_keys.size() < static_cast<std::size_t>(ranges)) {
    search.found_keys.resize(static_cast<std::size_t>(ranges));
    search.found.resize(static_cast<std::size_t>(ranges));
  }
  workers.run(ranges, [&](int rg) {
    const std::size_t k0 = static_cast<std::size_t>(rg) * kPerRange;
    const std::size_t k1 = std::min(static_cast<std::size_t>(placed), k0 + kPerRange);
    for (std::size_t k = k0; k < k1; ++k) {
      const int j = grid.order[k];
      search.candidates[k] = {x[j], y[j], r[j] + margin[j], j};
    }
  });
  const Candidate* cd = search.candidates.data();
  // Any partner's reach is at most this; the slack (far above rounding) keeps a pair at
  // the edge of the box from being lost to the rounding of the box.
  const double reach_max = model.r_max_m + bounds.margin_max_m + 1e-6 * model.r_min_m;
  workers.run(ranges, [&](int rg) {
    std::vector<std::uint64_t>& keys = search.found_keys[static_cast<std::size_t>(rg)];
    std::size_t found = 0;
    // Branch-free: whether a neighbour is a pair follows no pattern a predictor can learn,
    // so every one is tested and stored, and only counted if it passes (room for a whole
    // range is made first).
    auto scan = [&](const Candidate& p, int k0, int k1) {
      if (keys.size() < found + static_cast<std::size_t>(k1 - k0))
        keys.resize(2 * (found + static_cast<std::size_t>(k1 - k0)));
      std::uint64_t* out = keys.data();
      for (int k = k0; k < k1; ++k) {
        const Candidate& q = cd[k];
        const double dx = p.x - q.x, dy = p.y - q.y;
        // (r_p + margin_p) + (r_q + margin_q): a sum of two terms is the same whichever
        // disk scans, so the pair set does not depend on the grid.
        const double reach = p.reach + q.reach;
        // The lower index by masks: the compiler turns a select of two indices into a
        // branch, and which disk comes first follows no pattern either.
        const auto pj = static_cast<std::uint64_t>(p.j), qj = static_cast<std::uint64_t>(q.j);
        const std::uint64_t p_low = 0 - static_cast<std::uint64_t>(pj < qj);
        const std::uint64_t lo = qj ^ ((pj ^ qj) & p_low);
        out[found] = (lo << 32) | (pj ^ qj ^ lo);
        found += dx * dx + dy * dy < reach * reach ? 1 : 0;
      }
    };
    const int k_end = static_cast<int>(std::min(static_cast<std::size_t>(placed),
                                                (static_cast<std::size_t>(rg) + 1) * kPerRange));
    for (int k = rg * static_cast<int>(kPerRange); k < k_end; ++k) {
      const Candidate& p = cd[k];
      const double box = p.reach + reach_max;
      const int x_lo = grid.col(p.x - box), x_hi = grid.col(p.x + box);
      const int row = grid.row(p.y);
      // The rest of this row: the disks after p in its own cell, then the cells to its right.
      scan(p, k + 1, start[row * nx + x_hi + 1]);
      for (int gy = row + 1, y_hi = grid.row(p.y + box); gy <= y_hi; ++gy)
        scan(p, start[gy * nx + x_lo], start[gy * nx + x_hi + 1]);
    }
    search.found[static_cast<std::size_t>(rg)] = found;
  });
  // Bucket by the lower index (counting sort), then sort each bucket by the upper one.
  const auto n = static_cast<std::size_t>(disks.n);
  std::vector<int>& bucket = search.bucket_end;
  bucket.assign(n + 1, 0);
  std::size_t total = 0;
  for (int rg = 0; rg < ranges; ++rg) {
    const std::uint64_t* keys = search.found_keys[static_cast<std::size_t>(rg)].data();
    const std::size_t found = search.found[static_cast<std::size_t>(rg)];
    for (std::size_t t = 0; t < found; ++t) bucket[(keys[t] >> 32) + 1] += 1;
    total += found;
  }
  for (std::size_t i = 0; i < n; ++i) bucket[i + 1] += bucket[i];
  if (search.upper.size() < total) search.upper.resize(2 * total);
  for (int rg = 0; rg < ranges; ++rg) {
    const std::uint64_t* keys = search.found_keys[static_cast<std::size_t>(rg)].data();
    const std::size_t found = search.found[static_cast<std::size_t>(rg)];
    for (std::size_t t = 0; t < found; ++t) {
      const std::uint64_t key = keys[t];
      const auto slot = static_cast<std::size_t>(bucket[key >> 32]++);
      search.upper[slot] = static_cast<int>(key & 0xffffffffu);
    }
  }
  // bucket[i] is now the end of bucket i, and the start of bucket i + 1; a pair's slot is
  // its index in the key-ordered list.
  pairs.resize(total);
  int* upper = search.upper.data();
  // By disk, in the disk stages' ranges: the work per disk varies with its pair count, and
  // small ranges even it out between the threads.
  workers.run_disks(disks.n, [&](int i0, int i1) {
    int b0 = i0 == 0 ? 0 : bucket[static_cast<std::size_t>(i0) - 1];
    for (int i = i0; i < i1; ++i) {
      const int b1 = bucket[static_cast<std::size_t>(i)];
      // A handful per disk: insertion sort.
      for (int p = b0 + 1; p < b1; ++p)
        for (int q = p; q > b0 && upper[q - 1] > upper[q]; --q) std::swap(upper[q - 1], upper[q]);
      for (int p = b0; p < b1; ++p)
        add_pair_contact(disks, pairs, static_cast<std::size_t>(p), i, upper[p]);
      b0 = b1;
    }
  });
}

void find_liner_contacts(const Model& model, const LinerModel& liner, LinerSearch& search,
                         const Disks& disks, double mill_angle_rad, double mill_speed_rad_s,
                         LinerSet& contacts, Workers& workers) {
  constexpr std::size_t kPerRange = 1024;  // disks per range
  const double omega = mill_speed_rad_s;
  const double cs = std::cos(mill_angle_rad), sn = std::sin(mill_angle_rad);
  const double liner_travel = std::fabs(omega) * liner.max_r_m * model.dt_s;
  const Materials& mat = model.materials;
  const auto n = static_cast<std::size_t>(disks.n);
  const int ranges = range_count(n, kPerRange);
  if (search.found.size() < static_cast<std::size_t>(ranges)) {
    search.found.resize(static_cast<std::size_t>(ranges));
    search.count.resize(static_cast<std::size_t>(ranges));
    search.offset.resize(static_cast<std::size_t>(ranges));
    search.hits.resize(static_cast<std::size_t>(ranges));
  }
  const auto max_hits = static_cast<std::size_t>(search.lookup.max_hits());
  for (int r = 0; r < ranges; ++r) {
    std::vector<LinerHit>& hits = search.hits[static_cast<std::size_t>(r)];
    if (hits.size() < max_hits) hits.resize(max_hits);  // grows with the bins, rarely
  }
  // The hits of each range of disks.
  workers.run(ranges, [&](int r) {
    std::vector<LinerSearch::Found>& found = search.found[static_cast<std::size_t>(r)];
    std::size_t count = 0;
    LinerHit* hits = search.hits[static_cast<std::size_t>(r)].data();
    const std::size_t k0 = static_cast<std::size_t>(r) * kPerRange, k1 = std::min(n, k0 + kPerRange);
    for (std::size_t k = k0; k < k1; ++k) {
      if (!disks.active[k]) continue;
      const double margin = disks.margin[k] + liner_travel;
      const double rad = disks.radius[k];
      const double x = disks.x[k], y = disks.y[k];
      // Into the mill frame (rotate by -theta).
      const Vec2 pm{cs * x + sn * y, -sn * x + cs * y};
      if (!search.lookup.may_touch(pm, rad + margin)) continue;
      const int hit_n = search.lookup.query(pm, rad, margin, hits);
      if (found.size() < count + static_cast<std::size_t>(hit_n)) found.resize(2 * (count + static_cast<std::size_t>(hit_n)));
      for (int h = 0; h < hit_n; ++h) found[count++] = {static_cast<int>(k), hits[h]};
    }
    search.count[static_cast<std::size_t>(r)] = count;
  });
  std::size_t total = 0;
  for (int r = 0; r < ranges; ++r) {
    search.offset[static_cast<std::size_t>(r)] = total;
    total += search.count[static_cast<std::size_t>(r)];
  }
  contacts.resize(total);
  // The contacts, in disk order (each range at its offset).
  workers.run(ranges, [&](int r) {
    const LinerSearch::Found* found = search.found[static_cast<std::size_t>(r)].data();
    const std::size_t count = search.count[static_cast<std::size_t>(r)];
    std::size_t q = search.offset[static_cast<std::size_t>(r)];
    for (std::size_t t = 0; t < count; ++t, ++q) {
      const int i = found[t].disk;
      const LinerHit& hit = found[t].hit;
      const auto k = static_cast<std::size_t>(i);
      const double rad = disks.radius[k];
      const double x = disks.x[k], y = disks.y[k];
      const Body& A = disks.body[k];
      const std::uint8_t sp = disks.species[k];
      LinerGap& g = contacts.gap[q];
      LinerRow& c = contacts.row[q];
      LinerInfo& info = contacts.info[q];
      g.a = i;
      contacts.impulse[q] = Impulse{};
      contacts.state[q] = kBuilt;
      contacts.sum[q] = StepSum{};
      contacts.key[q] = {pair_key(i, hit.owner), 0.0};
      info.edge = hit.edge;
      info.owner = hit.owner;
      g.nx = cs * hit.normal.x - sn * hit.normal.y;  // back to the world frame
      g.ny = sn * hit.normal.x + cs * hit.normal.y;
      g.s0 = hit.gap;
      c.alpha = rad + 0.5 * g.s0;
      info.px = x - c.alpha * g.nx;
      info.py = y - c.alpha * g.ny;
      g.vlx = -omega * info.py;
      g.vly = omega * info.px;
      c.mn = A.im > 0.0 ? 1.0 / A.im : 0.0;
      const double it = A.im + A.ii * c.alpha * c.alpha;
      c.mt = it > 0.0 ? 1.0 / it : 0.0;
      c.mr = A.ii > 0.0 ? 1.0 / A.ii : 0.0;
      c.mu = mat.liner_friction[sp];
      info.e = mat.liner_restitution[sp];
      c.lever = mat.rolling[sp] * rad;
      info.vn0 = (A.vx - g.vlx) * g.nx + (A.vy - g.vly) * g.ny;
    }
  });
}

void match_warm_start(Contacts& contacts, Accounting& accounting, MatchScratch& scratch,
                      Workers& workers) {
  constexpr std::size_t kPerRange = 2048;
  const bool spectrum = accounting.options.collision_spectrum;
  auto merge = [&](auto& now, const auto& old, bool events) {
    const std::size_t m = old.size(), count = now.size();
    const int ranges = std::max(1, range_count(count, kPerRange));
    if (scratch.ended.size() < static_cast<std::size_t>(ranges)) {
      scratch.ended.resize(static_cast<std::size_t>(ranges));
      scratch.count.resize(static_cast<std::size_t>(ranges));
    }
    // Where this step's key k falls in last step's list (the first old key not below it).
    auto old_from = [&](std::size_t q) -> std::size_t {
      if (q >= count) return m;
      const std::uint64_t k = now.key[q].key;
      std::size_t lo = 0, hi = m;
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (old.key[mid].key < k) lo = mid + 1; else hi = mid;
      }
      return lo;
    };
    workers.run(ranges, [&](int r) {
      const std::size_t q0 = static_cast<std::size_t>(r) * kPerRange;
      const std::size_t q1 = std::min(count, q0 + kPerRange);
      // The first range also takes the old keys below this step's first; the last, those
      // above its last.
      std::size_t p = r == 0 ? 0 : old_from(q0);
      const std::size_t p_end = r == ranges - 1 ? m : old_from(q1);
      std::vector<double>& ended = scratch.ended[static_cast<std::size_t>(r)];
      std::size_t ended_n = 0;
      auto end_event = [&](double energy_J) {
        if (ended_n == ended.size()) ended.resize(2 * ended_n + 16);
        ended[ended_n++] = energy_J;
      };
      for (std::size_t q = q0; q < q1; ++q) {
        ContactKey& c = now.key[q];
        while (p < p_end && old.key[p].key < c.key) {
          if (events && old.key[p].event_J > 0.0) end_event(old.key[p].event_J);
          ++p;
        }
        if (p < p_end && old.key[p].key == c.key) {
          // Only a live row carries impulses; a row that is not live stores none (its
          // slot holds whatever it held, read by nobody), so the slot is copied either way:
          // a third of the rows are live, in no pattern a branch predictor learns.
          now.impulse[q] = old.impulse[p];
          now.state[q] |= old.state[p] & kLive;
          if (events) c.event_J = old.key[p].event_J;  // otherwise zero in both
          ++p;
        }
      }
      for (; p < p_end; ++p)
        if (events && old.key[p].event_J > 0.0) end_event(old.key[p].event_J);
      scratch.count[static_cast<std::size_t>(r)] = ended_n;
    });
    for (int r = 0; r < ranges; ++r)
      for (std::size_t e = 0; e < scratch.count[static_cast<std::size_t>(r)]; ++e)
        account_collision_event(accounting, scratch.ended[static_cast<std::size_t>(r)][e]);
  };
  merge(contacts.pairs, contacts.pairs_old, spectrum);
  merge(contacts.liner, contacts.liner_old, false);
}

}  // namespace millwear::soft
