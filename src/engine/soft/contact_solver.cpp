#include "engine/soft/contact_solver.hpp"

#include <algorithm>

#include "engine/soft/narrow_phase.hpp"

namespace millwear::soft {

namespace {

// The normal row of one contact at separation s and normal velocity vn; returns the
// change of its impulse. kBias: the soft solve; otherwise the relax (rigid, no bias).
template <bool kBias>
double solve_normal(double mn, double& ln, double s, double vn, const Softness& sf, double inv_h,
                    double push) {
  double mass_scale = 1.0, impulse_scale = 0.0, bias = 0.0;
  if (s > 0.0) {
    bias = s * inv_h;  // speculative: close the gap, no more
  } else if (kBias) {
    bias = std::max(sf.bias_rate * s, -push);
    mass_scale = sf.mass_scale;
    impulse_scale = sf.impulse_scale;
  }
  const double raw = -mn * mass_scale * (vn + bias) - impulse_scale * ln;
  const double next = std::max(ln + raw, 0.0);
  const double d = next - ln;
  ln = next;
  return d;
}

// Each row below loads its bodies into locals, applies the row, and stores them back once:
// the same arithmetic in the same order as updating the arrays in place, without the
// reloads that possible aliasing would force. The tangent of a contact is left_perp(n);
// r_a = -alpha n gives r_a x t = -alpha.

// Serial disk-pair rows (one list: a block's phase, key order, rest_gap their gaps in the
// list's order), built lazily. The relax
// also lists the rows left live for the next warm start and adds the impulses to the step
// sums.
template <bool kBias>
void pass_serial_pairs(const Model& model, const Disks& disks, const StepStart& start,
                       PairSet& pairs, const int* rest, const PairGap* rest_gap, std::size_t nrest,
                       int* warm, int& warm_count, Body* body) {
  const double inv_h = 1.0 / model.substep_s;
  const double push = model.push_out_m_s;
  const Softness& soft = model.pair_softness;
  const PairRow* row_of = pairs.row.data();
  Impulse* impulse = pairs.impulse.data();
  std::uint8_t* state = pairs.state.data();
  StepSum* sums = pairs.sum.data();
  std::size_t warm_n = 0;
  for (std::size_t t = 0; t < nrest; ++t) {
    const auto q = static_cast<std::size_t>(rest[t]);
    const PairGap& g = rest_gap[t];
    Body& A = body[g.a];
    Body& B = body[g.b];
    const double s = g.s0 + g.nx * (A.dpx - B.dpx) + g.ny * (A.dpy - B.dpy);
    const double vn = g.nx * (A.vx - B.vx) + g.ny * (A.vy - B.vy);
    // A speculative row with no impulse whose gap does not close this substep applies
    // nothing (normal impulse max(0 - m (vn + s/h), 0) = 0, friction and rolling bounded by
    // it): skip it. Many rows are such margins kept against tunnelling.
    if (s > 0.0 && vn + s * inv_h >= 0.0 && !(state[q] & kLive)) continue;
    if (!(state[q] & kBuilt)) build_pair_row(model, disks, start, pairs, q);
    const PairRow& c = row_of[q];
    Impulse& p = impulse[q];
    double vax = A.vx, vay = A.vy, wa = A.w;
    double vbx = B.vx, vby = B.vy, wb = B.w;
    const double ima = A.im, imb = B.im, iia = A.ii, iib = B.ii;
    const double dn = solve_normal<kBias>(c.mn, p.ln, s, vn, soft, inv_h, push);
    vax += ima * dn * g.nx;
    vay += ima * dn * g.ny;
    vbx -= imb * dn * g.nx;
    vby -= imb * dn * g.ny;
    // Friction.
    const double tx = -g.ny, ty = g.nx;
    const double vt = tx * (vax - vbx) + ty * (vay - vby) - c.alpha * wa - c.beta * wb;
    const double bound = c.mu * p.ln;
    const double lt = std::clamp(p.lt - c.mt * vt, -bound, bound);
    const double dt_imp = lt - p.lt;
    p.lt = lt;
    vax += ima * dt_imp * tx;
    vay += ima * dt_imp * ty;
    wa -= iia * c.alpha * dt_imp;
    vbx -= imb * dt_imp * tx;
    vby -= imb * dt_imp * ty;
    wb -= iib * c.beta * dt_imp;
    // Rolling resistance.
    if (c.lever > 0.0) {
      const double rb = c.lever * p.ln;
      const double lr = std::clamp(p.lr - c.mr * (wa - wb), -rb, rb);
      const double dr = lr - p.lr;
      p.lr = lr;
      wa += iia * dr;
      wb -= iib * dr;
    }
    A.vx = vax;
    A.vy = vay;
    A.w = wa;
    B.vx = vbx;
    B.vy = vby;
    B.w = wb;
    const std::uint8_t live = has_impulse(p);
    state[q] = (state[q] & kBounce) | kBuilt | live;
    if (!kBias) {
      // The next warm start applies the rows left live (a skipped row stays inert).
      warm[warm_n] = static_cast<int>(q);
      warm_n += live;
      sums[q].pn += p.ln;
      sums[q].pt += p.lt;
      sums[q].pr += p.lr;
    }
  }
  if (!kBias) warm_count = static_cast<int>(warm_n);
}

// The disk-liner rows. The liner's contact point moves with the mill: its share of the
// separation is its velocity times the time since the step began.
template <bool kBias>
void pass_liner(const Model& model, double elapsed_s, double omega, LinerSet& liner,
                std::size_t q0, std::size_t q1, Body* body) {
  const double inv_h = 1.0 / model.substep_s;
  const double push = model.push_out_m_s;
  const Softness& soft = model.liner_softness;
  const LinerGap* lgaps = liner.gap.data();
  const LinerRow* lrows = liner.row.data();
  Impulse* limpulse = liner.impulse.data();
  std::uint8_t* lstate = liner.state.data();
  StepSum* lsums = liner.sum.data();
  for (std::size_t q = q0; q < q1; ++q) {
    const LinerGap& g = lgaps[q];
    Body& A = body[g.a];
    const double s = g.s0 + g.nx * (A.dpx - g.vlx * elapsed_s) + g.ny * (A.dpy - g.vly * elapsed_s);
    const double vn = g.nx * (A.vx - g.vlx) + g.ny * (A.vy - g.vly);
    if (s > 0.0 && vn + s * inv_h >= 0.0 && !(lstate[q] & kLive)) continue;
    const LinerRow& c = lrows[q];
    Impulse& p = limpulse[q];
    double vax = A.vx, vay = A.vy, wa = A.w;
    const double ima = A.im, iia = A.ii;
    const double dn = solve_normal<kBias>(c.mn, p.ln, s, vn, soft, inv_h, push);
    vax += ima * dn * g.nx;
    vay += ima * dn * g.ny;
    const double tx = -g.ny, ty = g.nx;
    const double vt = tx * (vax - g.vlx) + ty * (vay - g.vly) - c.alpha * wa;
    const double bound = c.mu * p.ln;
    const double lt = std::clamp(p.lt - c.mt * vt, -bound, bound);
    const double dt_imp = lt - p.lt;
    p.lt = lt;
    vax += ima * dt_imp * tx;
    vay += ima * dt_imp * ty;
    wa -= iia * c.alpha * dt_imp;
    if (c.lever > 0.0) {
      const double rb = c.lever * p.ln;
      const double lr = std::clamp(p.lr - c.mr * (wa - omega), -rb, rb);
      wa += iia * (lr - p.lr);
      p.lr = lr;
    }
    A.vx = vax;
    A.vy = vay;
    A.w = wa;
    lstate[q] = kBuilt | has_impulse(p);
    if (!kBias) {
      lsums[q].pn += p.ln;
      lsums[q].pt += p.lt;
      lsums[q].pr += p.lr;
    }
  }
}

// The coloured rows built straight into their lanes in key order (the padding lanes are
// filled by the layout), with zero step sums: the lane takes its gap, the impulses carried
// into the step and the material; its anchors and masses come from the bodies in each pass
// (colour_solve.hpp), so the serial row's are never computed for it.
void load_lanes(const Model& model, const Disks& disks, const StepStart& start, PairSet& pairs,
                ColouredRows& coloured, std::size_t t0, std::size_t t1) {
  for (std::size_t t = t0; t < t1; ++t) {
    const auto q = static_cast<std::size_t>(coloured.coloured_contact(t));
    const std::size_t slot = coloured.coloured_slot(t);
    const PairMaterial mat = build_pair_contact(model, disks, start, pairs, q);
    const PairGap& g = pairs.gap[q];
    const Impulse& c = pairs.impulse[q];  // live: its impulses were carried into the step
    WideRows& w = coloured.chunk_of(slot);
    const std::size_t l = slot % kLanes;
    w.a[l] = g.a;
    w.b[l] = g.b;
    w.nx[l] = g.nx;
    w.ny[l] = g.ny;
    w.s0[l] = g.s0;
    w.mu[l] = mat.mu;
    w.lever[l] = mat.lever;
    w.ln[l] = c.ln;
    w.lt[l] = c.lt;
    w.lr[l] = c.lr;
    WideSums& p = coloured.sums_of(slot);
    p.pn[l] = p.pt[l] = p.pr[l] = 0.0;
  }
}

// Chunks per range of a colour, coloured rows per range of the lane loading: enough work to
// outweigh handing a range out.
constexpr std::size_t kChunksPerRange = 32;
constexpr std::size_t kColouredPerRange = 2048;

// fn(phase, block) for every block's list of every phase, in the order and with the
// concurrency of "Threads" (contact_solver.hpp), in two stages rather than three: a range
// takes blocks 2r and 2r + 1, their inside rows and then the rows from 2r into 2r + 1. The
// rows of one range touch only its two blocks, and each disk still meets its inside rows
// before its rows into the next block, so the bits are those of running every inside row,
// then the even blocks' next rows, then the odd ones'.
template <class Fn>
void for_phases(Workers& workers, const SolverRows& rows, const Fn& fn) {
  const int blocks = rows.blocks;
  workers.run((blocks + 1) / 2, [&](int r) {
    fn(kInside, 2 * r);
    if (2 * r + 1 < blocks) fn(kInside, 2 * r + 1);
    fn(kNext, 2 * r);
  });
  workers.run(blocks / 2, [&](int r) { fn(kNext, 2 * r + 1); });
  for (int k = 0; k < blocks; ++k) fn(kFar, k);
}

// fn(chunk0, chunk1) over the chunks of each colour in turn, a colour's ranges at once.
// The threads' blocks are cut by disk (Workers::run_by_disk): a colour's chunks are in key
// order, so a chunk's first lane holds its lowest disk.
template <class Fn>
void for_colours(Workers& workers, int disks, const ColouredRows& coloured, const Fn& fn) {
  const WideRows* wide = coloured.rows();
  for (int c = 0; c < coloured.colours(); ++c) {
    const std::size_t c0 = coloured.colour_begin(c), c1 = coloured.colour_begin(c + 1);
    const auto disk_of = [&](int r) { return wide[c0 + static_cast<std::size_t>(r) * kChunksPerRange].a[0]; };
    workers.run_by_disk(range_count(c1 - c0, kChunksPerRange), disks, disk_of, [&](int r) {
      const std::size_t k0 = c0 + static_cast<std::size_t>(r) * kChunksPerRange;
      fn(k0, std::min(c1, k0 + kChunksPerRange));
    });
  }
}

// fn(i0, i1, q0, q1) over the disk stages' ranges [i0, i1) (Workers::run_disks) with
// their liner rows [q0, q1): the liner rows are in key order, so by disk, and a range's rows
// touch its own disks only.
template <class Fn>
void for_liner_ranges(Workers& workers, int disks, const SolverRows& rows, const Fn& fn) {
  workers.run_disks(disks, [&](int i0, int i1) {
    const auto r = static_cast<std::size_t>(i0 / Workers::kDiskGrain);
    fn(i0, i1, rows.liner_at[r], rows.liner_at[r + 1]);
  });
}

// What a pass does to each disk after its last row (in the liner stage, range by range).
enum class PassTail { kNothing, kIntegratePositions, kGravity };

// Symplectic Euler with the new velocity; dp accumulates the displacement of the step.
void integrate_position_range(const Model& model, Disks& disks, int i0, int i1) {
  const double h = model.substep_s;
  Body* body = disks.body.data();
  for (int i = i0; i < i1; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!disks.active[k]) continue;
    Body& b = body[i];
    const double ddx = h * b.vx, ddy = h * b.vy;
    disks.x[k] += ddx;
    disks.y[k] += ddy;
    b.dpx += ddx;
    b.dpy += ddy;
    disks.angle[k] += h * b.w;
  }
}

// Gravity's share of a substep.
void gravity_range(const Model& model, Disks& disks, int i0, int i1) {
  const double gh = kGravity * model.substep_s;
  Body* body = disks.body.data();
  for (int i = i0; i < i1; ++i)
    if (body[i].im > 0.0) body[i].vy -= gh;
}

// A row of a pair whose lower disk is in block k, which ends before disk `end`: which phase
// it belongs to (b > a, so b is in block k or after it; compared, not divided: this runs for
// every row of every step).
Phase phase_of(int b, int end, int block_disks) {
  return static_cast<Phase>(static_cast<int>(b >= end) + static_cast<int>(b - end >= block_disks));
}

// State bit of a row placed in a lane this step (the colouring's; store_lanes rewrites the
// state of every lane row at the end of the step).
constexpr std::uint8_t kInLane = 8;

}  // namespace

// Why only the live rows go into lanes: they act in nearly every pass of the step, where
// most of the others are margins that never act and that the serial pass skips after
// reading their gap; a lane has no skip, so colouring every contact would solve three
// times as many rows. A live row that finds no free colour stays serial and goes into the
// serial warm-start list. The colouring itself is greedy in key order (one thread); the
// lanes' loading (which builds the coloured rows) and the phase lists (which build the
// other live rows) run by range or block.
void colour_live_rows(const Model& model, const Disks& disks, const StepStart& start,
                      int block_disks, Contacts& contacts, SolverRows& rows, Workers& workers) {
  PairSet& pairs = contacts.pairs;
  const std::size_t m = pairs.size();
  const std::size_t capacity = pairs.row.size();
  for (int p = 0; p < kPhases; ++p) {
    if (rows.list[p].size() < m) rows.list[p].resize(capacity);
    if (rows.warm[p].size() < m) rows.warm[p].resize(capacity);
  }
  if (rows.live.size() < m) {
    rows.list_gap.resize(capacity);
    rows.live.resize(capacity);
    rows.live_disks.resize(capacity);
    rows.in_lane.resize(capacity);
  }
  // Blocks and where their rows start (the rows are in key order: by lower disk).
  rows.block_disks = std::max(1, block_disks);
  rows.blocks = std::max(1, (disks.n + rows.block_disks - 1) / rows.block_disks);
  const auto blocks = static_cast<std::size_t>(rows.blocks);
  rows.first.resize(blocks + 1);
  for (int p = 0; p < kPhases; ++p) {
    rows.n[p].assign(blocks, 0);
    rows.warm_n[p].assign(blocks, 0);
  }
  rows.live_count.assign(blocks, 0);
  const PairGap* gap = pairs.gap.data();
  for (std::size_t k = 0; k <= blocks; ++k) {
    const int a0 = static_cast<int>(std::min<std::size_t>(k * static_cast<std::size_t>(rows.block_disks),
                                                          static_cast<std::size_t>(disks.n)));
    rows.first[k] = static_cast<std::size_t>(
        std::lower_bound(gap, gap + m, a0, [](const PairGap& g, int a) { return g.a < a; }) - gap);
  }
  rows.first[blocks] = m;
  // The live rows, block by block.
  workers.run(rows.blocks, [&](int k) {
    const std::size_t q0 = rows.first[static_cast<std::size_t>(k)], q1 = rows.first[static_cast<std::size_t>(k) + 1];
    // Written whether live or not, counted only if live: no branch on the state (a third
    // of the rows are live, in no pattern a predictor learns).
    // The live rows' disks go into a list of their own: the colouring, on one thread, then
    // reads those alone and not the rows around them, which another thread wrote.
    int* live = rows.live.data() + q0;
    SolverRows::Pair* live_disks = rows.live_disks.data() + q0;
    const std::uint8_t* state = pairs.state.data();
    int count = 0;
    for (std::size_t q = q0; q < q1; ++q) {
      live[count] = static_cast<int>(q);
      live_disks[count] = {gap[q].a, gap[q].b};
      count += state[q] & kLive;
    }
    rows.live_count[static_cast<std::size_t>(k)] = count;
  });
  // Colour them in key order.
  ColouredRows& coloured = rows.coloured;
  coloured.begin(disks.n, m);
  std::size_t live_n = 0;
  for (std::size_t k = 0; k < blocks; ++k) {
    const int* live = rows.live.data() + rows.first[k];
    const SolverRows::Pair* live_disks = rows.live_disks.data() + rows.first[k];
    std::uint8_t* in_lane = rows.in_lane.data() + rows.first[k];
    for (int t = 0; t < rows.live_count[k]; ++t)
      in_lane[t] = coloured.add(live[t], live_disks[t].a, live_disks[t].b);
    live_n += static_cast<std::size_t>(rows.live_count[k]);
  }
  rows.live_n = live_n;
  coloured.layout();
  workers.run(range_count(coloured.coloured(), kColouredPerRange), [&](int r) {
    const std::size_t t0 = static_cast<std::size_t>(r) * kColouredPerRange;
    load_lanes(model, disks, start, pairs, coloured, t0, std::min(coloured.coloured(), t0 + kColouredPerRange));
  });
  // The rows in lanes flagged; the other rows into their block's phase lists, the live ones
  // among them built (the warm start applies them) and into the warm lists too.
  workers.run(rows.blocks, [&](int k) {
    const auto kk = static_cast<std::size_t>(k);
    const std::size_t q0 = rows.first[kk], q1 = rows.first[kk + 1];
    const int end = (k + 1) * rows.block_disks;
    const int* live = rows.live.data() + q0;
    const std::uint8_t* in_lane = rows.in_lane.data() + q0;
    for (int t = 0; t < rows.live_count[kk]; ++t)
      if (in_lane[t]) pairs.state[static_cast<std::size_t>(live[t])] |= kInLane;
    int count[kPhases] = {}, warm_count[kPhases] = {};
    int* list[kPhases];
    for (int p = 0; p < kPhases; ++p) list[p] = rows.list[p].data() + q0;
    for (std::size_t q = q0; q < q1; ++q) {
      // As the live rows above: every row written, only those outside the lanes counted.
      const std::uint8_t st = pairs.state[q];
      const int p = phase_of(gap[q].b, end, rows.block_disks);
      list[p][count[p]] = static_cast<int>(q);
      count[p] += !(st & kInLane);
      if ((st & (kInLane | kLive)) != kLive) continue;
      build_pair_row(model, disks, start, pairs, q);
      rows.warm[p][q0 + static_cast<std::size_t>(warm_count[p]++)] = static_cast<int>(q);
    }
    PairGap* list_gap = rows.list_gap.data() + q0;
    for (int p = 0; p < kPhases; ++p) {
      rows.n[p][kk] = count[p];
      rows.warm_n[p][kk] = warm_count[p];
      // The block's gaps were read just above: from the cache.
      for (int t = 0; t < count[p]; ++t) *list_gap++ = gap[list[p][t]];
    }
  });
  // The liner rows of each of the disk stages' ranges.
  const LinerSet& liner = contacts.liner;
  const std::size_t ranges = static_cast<std::size_t>(range_count(static_cast<std::size_t>(disks.n), Workers::kDiskGrain));
  rows.liner_at.resize(ranges + 1);
  std::size_t q = 0;
  for (std::size_t r = 0; r < ranges; ++r) {
    rows.liner_at[r] = q;
    const auto end = static_cast<int>(std::min<std::size_t>((r + 1) * Workers::kDiskGrain, static_cast<std::size_t>(disks.n)));
    while (q < liner.size() && liner.gap[q].a < end) ++q;
  }
  rows.liner_at[ranges] = liner.size();
}

void integrate_velocities(const Model& model, Disks& disks, Workers& workers) {
  workers.run_disks(disks.n, [&](int i0, int i1) { gravity_range(model, disks, i0, i1); });
}

void warm_start(const Contacts& contacts, SolverRows& rows, Disks& disks, Workers& workers) {
  Body* body = disks.body.data();
  WideRows* wide = rows.coloured.rows();
  for_colours(workers, disks.n, rows.coloured,
              [&](std::size_t k0, std::size_t k1) { wide_warm_start(body, wide + k0, k1 - k0); });
  // Of the serial rows only the live ones: a row without impulse applies nothing (adding its
  // zero impulses would leave every velocity as it was), and most rows are such margins.
  const PairSet& pairs = contacts.pairs;
  for_phases(workers, rows, [&](int p, int k) {
    const auto kk = static_cast<std::size_t>(k);
    const int* warm = rows.warm[p].data() + rows.first[kk];
    const int count = rows.warm_n[p][kk];
    for (int t = 0; t < count; ++t) {
      const auto q = static_cast<std::size_t>(warm[t]);
      const PairGap& g = pairs.gap[q];
      const PairRow& c = pairs.row[q];
      const Impulse& p = pairs.impulse[q];
      Body& A = body[g.a];
      Body& B = body[g.b];
      const double px = p.ln * g.nx - p.lt * g.ny, py = p.ln * g.ny + p.lt * g.nx;
      A.vx += A.im * px;
      A.vy += A.im * py;
      A.w += A.ii * (p.lr - c.alpha * p.lt);
      B.vx -= B.im * px;
      B.vy -= B.im * py;
      B.w += B.ii * (-p.lr - c.beta * p.lt);
    }
  });
  const LinerSet& liner = contacts.liner;
  for_liner_ranges(workers, disks.n, rows, [&](int, int, std::size_t q0, std::size_t q1) {
    for (std::size_t q = q0; q < q1; ++q) {
      const LinerGap& g = liner.gap[q];
      const LinerRow& c = liner.row[q];
      const Impulse& p = liner.impulse[q];
      Body& A = body[g.a];
      const double px = p.ln * g.nx - p.lt * g.ny, py = p.ln * g.ny + p.lt * g.nx;
      A.vx += A.im * px;
      A.vy += A.im * py;
      A.w += A.ii * (p.lr - c.alpha * p.lt);
    }
  });
}

namespace {

// The serial phases, the colours, then the liner: one pass of the solve (kBias) or relax.
// Each disk's tail follows its liner rows in the same range: the last stage of the pass.
template <bool kBias>
void pass(const Model& model, const StepStart& start, double elapsed_s, double omega,
          Contacts& contacts, SolverRows& rows, Disks& disks, Workers& workers, PassTail tail) {
  Body* body = disks.body.data();
  for_phases(workers, rows, [&](int p, int k) {
    const auto kk = static_cast<std::size_t>(k);
    const std::size_t q0 = rows.first[kk];
    int unused = 0;
    pass_serial_pairs<kBias>(model, disks, start, contacts.pairs, rows.list[p].data() + q0,
                             rows.list_gap.data() + rows.list_gap_at(p, kk),
                             static_cast<std::size_t>(rows.n[p][kk]), rows.warm[p].data() + q0,
                             kBias ? unused : rows.warm_n[p][kk], body);
  });
  WideRows* wide = rows.coloured.rows();
  if (kBias) {
    const Softness& soft = model.pair_softness;
    WideSoftness sf;
    sf.inv_h = 1.0 / model.substep_s;
    sf.bias_rate = soft.bias_rate;
    sf.mass_scale = soft.mass_scale;
    sf.impulse_scale = soft.impulse_scale;
    sf.push = model.push_out_m_s;
    for_colours(workers, disks.n, rows.coloured,
                [&](std::size_t k0, std::size_t k1) { wide_solve(body, wide + k0, k1 - k0, sf); });
  } else {
    WideSums* sums = rows.coloured.sums();
    const double inv_h = 1.0 / model.substep_s;
    for_colours(workers, disks.n, rows.coloured, [&](std::size_t k0, std::size_t k1) {
      wide_relax(body, wide + k0, sums + k0, k1 - k0, inv_h);
    });
  }
  for_liner_ranges(workers, disks.n, rows, [&](int i0, int i1, std::size_t q0, std::size_t q1) {
    pass_liner<kBias>(model, elapsed_s, omega, contacts.liner, q0, q1, body);
    if (tail == PassTail::kIntegratePositions) integrate_position_range(model, disks, i0, i1);
    else if (tail == PassTail::kGravity) gravity_range(model, disks, i0, i1);
  });
}

}  // namespace

void solve_and_integrate_positions(const Model& model, const StepStart& start, double elapsed_s,
                                   double mill_speed_rad_s, Contacts& contacts, SolverRows& rows,
                                   Disks& disks, Workers& workers) {
  pass<true>(model, start, elapsed_s, mill_speed_rad_s, contacts, rows, disks, workers,
             PassTail::kIntegratePositions);
}

void relax(const Model& model, const StepStart& start, double elapsed_s,
           double mill_speed_rad_s, bool gravity_after, Contacts& contacts, SolverRows& rows,
           Disks& disks, Workers& workers) {
  pass<false>(model, start, elapsed_s, mill_speed_rad_s, contacts, rows, disks, workers,
              gravity_after ? PassTail::kGravity : PassTail::kNothing);
}

void store_lanes(SolverRows& rows, PairSet& pairs, Workers& workers) {
  ColouredRows& coloured = rows.coloured;
  workers.run(range_count(coloured.coloured(), kColouredPerRange), [&](int r) {
    const std::size_t t0 = static_cast<std::size_t>(r) * kColouredPerRange;
    const std::size_t t1 = std::min(coloured.coloured(), t0 + kColouredPerRange);
    for (std::size_t t = t0; t < t1; ++t) {
      const int q = coloured.coloured_contact(t);
      const std::size_t slot = coloured.coloured_slot(t);
      const auto k = static_cast<std::size_t>(q);
      const WideRows& w = coloured.chunk_of(slot);
      const std::size_t l = slot % kLanes;
      Impulse& c = pairs.impulse[k];
      c.ln = w.ln[l];
      c.lt = w.lt[l];
      c.lr = w.lr[l];
      const WideSums& p = coloured.sums_of(slot);
      pairs.sum[k] = {p.pn[l], p.pt[l], p.pr[l]};
      pairs.state[k] = (pairs.state[k] & kBounce) | kBuilt | has_impulse(c);
    }
  });
}

void apply_restitution(const Model& model, Contacts& contacts, SolverRows& rows, Disks& disks,
                       Workers& workers) {
  const double thr = -model.restitution_threshold_m_s;
  Body* body = disks.body.data();
  PairSet& pairs = contacts.pairs;
  LinerSet& liner = contacts.liner;
  // Which rows bounce, by ranges at once: a row bounces if it closed fast enough with some
  // restitution (one byte tells: kBounce, so the cold info of the others stays untouched)
  // and carried load, which no other row's bounce changes. Each range lists its own in its
  // slice of the scratch: pair block k's at bounce[first[k] ..], liner range r's at
  // liner_bounce[liner_at[r] ..].
  const auto blocks = static_cast<std::size_t>(rows.blocks);
  const auto liner_ranges = rows.liner_at.size() - 1;
  if (rows.bounce.size() < pairs.size()) rows.bounce.resize(pairs.row.size());
  if (rows.liner_bounce.size() < liner.size()) rows.liner_bounce.resize(liner.row.size());
  rows.bounce_n.resize(blocks + liner_ranges);
  workers.run(rows.blocks + static_cast<int>(liner_ranges), [&](int k) {
    const auto kk = static_cast<std::size_t>(k);
    int count = 0;
    if (kk < blocks) {
      const std::size_t q0 = rows.first[kk], q1 = rows.first[kk + 1];
      int* out = rows.bounce.data() + q0;
      for (std::size_t q = q0; q < q1; ++q)
        if ((pairs.state[q] & kBounce) && pairs.sum[q].pn != 0.0) out[count++] = static_cast<int>(q);
    } else {
      const std::size_t r = kk - blocks, q0 = rows.liner_at[r], q1 = rows.liner_at[r + 1];
      int* out = rows.liner_bounce.data() + q0;
      for (std::size_t q = q0; q < q1; ++q) {
        const LinerInfo& info = liner.info[q];
        // sum.pn != 0: built.
        if (liner.sum[q].pn != 0.0 && info.e != 0.0 && !(info.vn0 > thr)) out[count++] = static_cast<int>(q);
      }
    }
    rows.bounce_n[kk] = count;
  });
  // The bounces themselves one after another, in key order: a disk may bounce off several
  // partners, and each bounce starts from the velocities the earlier ones left.
  for (std::size_t k = 0; k < blocks; ++k) {
    const int* list = rows.bounce.data() + rows.first[k];
    for (int t = 0; t < rows.bounce_n[k]; ++t) {
      const auto q = static_cast<std::size_t>(list[t]);
      const PairInfo& info = pairs.info[q];
      StepSum& sum = pairs.sum[q];
      const PairGap& g = pairs.gap[q];
      Impulse& c = pairs.impulse[q];
      Body& A = body[g.a];
      Body& B = body[g.b];
      const double vn = g.nx * (A.vx - B.vx) + g.ny * (A.vy - B.vy);
      // The normal mass as build_pair_row computes it (a row in lanes stores none).
      const double im = A.im + B.im;
      const double mn = im > 0.0 ? 1.0 / im : 0.0;
      const double next = std::max(c.ln - mn * (vn + info.e * info.vn0), 0.0);
      const double d = next - c.ln;
      c.ln = next;
      pairs.state[q] = kBounce | kBuilt | has_impulse(c);
      sum.pn += d;
      A.vx += A.im * d * g.nx;
      A.vy += A.im * d * g.ny;
      B.vx -= B.im * d * g.nx;
      B.vy -= B.im * d * g.ny;
    }
  }
  for (std::size_t r = 0; r < liner_ranges; ++r) {
    const int* list = rows.liner_bounce.data() + rows.liner_at[r];
    for (int t = 0; t < rows.bounce_n[blocks + r]; ++t) {
      const auto q = static_cast<std::size_t>(list[t]);
      const LinerInfo& info = liner.info[q];
      StepSum& sum = liner.sum[q];
      const LinerGap& g = liner.gap[q];
      Impulse& c = liner.impulse[q];
      Body& A = body[g.a];
      const double vn = g.nx * (A.vx - g.vlx) + g.ny * (A.vy - g.vly);
      const double next = std::max(c.ln - liner.row[q].mn * (vn + info.e * info.vn0), 0.0);
      const double d = next - c.ln;
      c.ln = next;
      liner.state[q] = kBuilt | has_impulse(c);
      sum.pn += d;
      A.vx += A.im * d * g.nx;
      A.vy += A.im * d * g.ny;
    }
  }
}

}  // namespace millwear::soft
