#include "engine/soft/contact_solver.hpp"

#include <algorithm>

#include "engine/soft/narrow_phase.hpp"

namespace millwear::soft {

namespace {

// The normal row of one contact at separation s and normal velocity vn; returns the
// change of its impulse. kBias: the soft solve; otherwise the relax (rigid, no bias).
template <bool kBias, class Row>
double solve_normal(Row& c, double s, double vn, const Softness& sf, double inv_h, double push) {
  double mass_scale = 1.0, impulse_scale = 0.0, bias = 0.0;
  if (s > 0.0) {
    bias = s * inv_h;  // speculative: close the gap, no more
  } else if (kBias) {
    bias = std::max(sf.bias_rate * s, -push);
    mass_scale = sf.mass_scale;
    impulse_scale = sf.impulse_scale;
  }
  const double raw = -c.mn * mass_scale * (vn + bias) - impulse_scale * c.ln;
  const double next = std::max(c.ln + raw, 0.0);
  const double d = next - c.ln;
  c.ln = next;
  return d;
}

// Each row below loads its bodies into locals, applies the row, and stores them back once:
// the same arithmetic in the same order as updating the arrays in place, without the
// reloads that possible aliasing would force. The tangent of a contact is left_perp(n);
// r_a = -alpha n gives r_a x t = -alpha.

// The serial disk-pair rows, key order, built lazily. The relax also lists the rows left
// live for the next warm start and adds the impulses to the step sums.
template <bool kBias>
void pass_serial_pairs(const Model& model, const Disks& disks, const StepStart& start,
                       PairSet& pairs, SolverRows& rows, Body* body) {
  const double inv_h = 1.0 / model.substep_s;
  const double push = model.push_out_m_s;
  const Softness& soft = model.pair_softness;
  const std::size_t nrest = rows.serial_n;
  const int* rest = rows.serial.data();
  const PairGap* gaps = pairs.gap.data();
  PairRow* row_of = pairs.row.data();
  std::uint8_t* state = pairs.state.data();
  StepSum* sums = pairs.sum.data();
  int* warm = rows.warm.data();
  std::size_t warm_n = 0;
  for (std::size_t t = 0; t < nrest; ++t) {
    const auto q = static_cast<std::size_t>(rest[t]);
    const PairGap& g = gaps[q];
    Body& A = body[g.a];
    Body& B = body[g.b];
    const double s = g.s0 + g.nx * (A.dpx - B.dpx) + g.ny * (A.dpy - B.dpy);
    const double vn = g.nx * (A.vx - B.vx) + g.ny * (A.vy - B.vy);
    // A speculative row with no impulse whose gap does not close this substep applies
    // nothing (normal impulse max(0 - m (vn + s/h), 0) = 0, friction and rolling bounded by
    // it): skip it. Many rows are such margins kept against tunnelling.
    if (s > 0.0 && vn + s * inv_h >= 0.0 && !(state[q] & kLive)) continue;
    if (!(state[q] & kBuilt)) build_pair_row(model, disks, start, pairs, q);
    PairRow& c = row_of[q];
    double vax = A.vx, vay = A.vy, wa = A.w;
    double vbx = B.vx, vby = B.vy, wb = B.w;
    const double ima = A.im, imb = B.im, iia = A.ii, iib = B.ii;
    const double dn = solve_normal<kBias>(c, s, vn, soft, inv_h, push);
    vax += ima * dn * g.nx;
    vay += ima * dn * g.ny;
    vbx -= imb * dn * g.nx;
    vby -= imb * dn * g.ny;
    // Friction.
    const double tx = -g.ny, ty = g.nx;
    const double vt = tx * (vax - vbx) + ty * (vay - vby) - c.alpha * wa - c.beta * wb;
    const double bound = c.mu * c.ln;
    const double lt = std::clamp(c.lt - c.mt * vt, -bound, bound);
    const double dt_imp = lt - c.lt;
    c.lt = lt;
    vax += ima * dt_imp * tx;
    vay += ima * dt_imp * ty;
    wa -= iia * c.alpha * dt_imp;
    vbx -= imb * dt_imp * tx;
    vby -= imb * dt_imp * ty;
    wb -= iib * c.beta * dt_imp;
    // Rolling resistance.
    if (c.lever > 0.0) {
      const double rb = c.lever * c.ln;
      const double lr = std::clamp(c.lr - c.mr * (wa - wb), -rb, rb);
      const double dr = lr - c.lr;
      c.lr = lr;
      wa += iia * dr;
      wb -= iib * dr;
    }
    A.vx = vax;
    A.vy = vay;
    A.w = wa;
    B.vx = vbx;
    B.vy = vby;
    B.w = wb;
    const std::uint8_t live = has_impulse(c);
    state[q] = (state[q] & kBounce) | kBuilt | live;
    if (!kBias) {
      // The next warm start applies the rows left live (a skipped row stays inert).
      warm[warm_n] = static_cast<int>(q);
      warm_n += live;
      sums[q].pn += c.ln;
      sums[q].pt += c.lt;
      sums[q].pr += c.lr;
    }
  }
  if (!kBias) rows.warm_n = warm_n;
}

// The disk-liner rows. The liner's contact point moves with the mill: its share of the
// separation is its velocity times the time since the step began.
template <bool kBias>
void pass_liner(const Model& model, double elapsed_s, double omega, LinerSet& liner,
                Body* body) {
  const double inv_h = 1.0 / model.substep_s;
  const double push = model.push_out_m_s;
  const Softness& soft = model.liner_softness;
  const std::size_t npl = liner.size();
  const LinerGap* lgaps = liner.gap.data();
  LinerRow* lrows = liner.row.data();
  std::uint8_t* lstate = liner.state.data();
  StepSum* lsums = liner.sum.data();
  for (std::size_t q = 0; q < npl; ++q) {
    const LinerGap& g = lgaps[q];
    Body& A = body[g.a];
    const double s = g.s0 + g.nx * (A.dpx - g.vlx * elapsed_s) + g.ny * (A.dpy - g.vly * elapsed_s);
    const double vn = g.nx * (A.vx - g.vlx) + g.ny * (A.vy - g.vly);
    if (s > 0.0 && vn + s * inv_h >= 0.0 && !(lstate[q] & kLive)) continue;
    LinerRow& c = lrows[q];
    double vax = A.vx, vay = A.vy, wa = A.w;
    const double ima = A.im, iia = A.ii;
    const double dn = solve_normal<kBias>(c, s, vn, soft, inv_h, push);
    vax += ima * dn * g.nx;
    vay += ima * dn * g.ny;
    const double tx = -g.ny, ty = g.nx;
    const double vt = tx * (vax - g.vlx) + ty * (vay - g.vly) - c.alpha * wa;
    const double bound = c.mu * c.ln;
    const double lt = std::clamp(c.lt - c.mt * vt, -bound, bound);
    const double dt_imp = lt - c.lt;
    c.lt = lt;
    vax += ima * dt_imp * tx;
    vay += ima * dt_imp * ty;
    wa -= iia * c.alpha * dt_imp;
    if (c.lever > 0.0) {
      const double rb = c.lever * c.ln;
      const double lr = std::clamp(c.lr - c.mr * (wa - omega), -rb, rb);
      wa += iia * (lr - c.lr);
      c.lr = lr;
    }
    A.vx = vax;
    A.vy = vay;
    A.w = wa;
    lstate[q] = kBuilt | has_impulse(c);
    if (!kBias) {
      lsums[q].pn += c.ln;
      lsums[q].pt += c.lt;
      lsums[q].pr += c.lr;
    }
  }
}

// The coloured rows into their lanes in key order (the padding lanes are filled by the
// layout), with zero step sums.
void load_lanes(const PairSet& pairs, ColouredRows& coloured) {
  for (std::size_t t = 0; t < coloured.coloured(); ++t) {
    const int q = coloured.coloured_contact(t);
    const std::size_t slot = coloured.coloured_slot(t);
    const PairGap& g = pairs.gap[static_cast<std::size_t>(q)];
    const PairRow& c = pairs.row[static_cast<std::size_t>(q)];
    WideRows& w = coloured.chunk_of(slot);
    const std::size_t l = slot % kLanes;
    w.a[l] = g.a;
    w.b[l] = g.b;
    w.nx[l] = g.nx;
    w.ny[l] = g.ny;
    w.s0[l] = g.s0;
    w.alpha[l] = c.alpha;
    w.beta[l] = c.beta;
    w.mn[l] = c.mn;
    w.mt[l] = c.mt;
    w.mr[l] = c.mr;
    w.mu[l] = c.mu;
    w.lever[l] = c.lever;
    w.ln[l] = c.ln;
    w.lt[l] = c.lt;
    w.lr[l] = c.lr;
    WideSums& p = coloured.sums_of(slot);
    p.pn[l] = p.pt[l] = p.pr[l] = 0.0;
  }
}

}  // namespace

// Why only the live rows go into lanes: they act in nearly every pass of the step, where
// most of the others are margins that never act and that the serial pass skips after
// reading their gap; a lane has no skip, so colouring every contact would solve three
// times as many rows. A live row that finds no free colour stays serial and goes into the
// serial warm-start list.
void colour_live_rows(const Model& model, const Disks& disks, const StepStart& start,
                      PairSet& pairs, SolverRows& rows) {
  const std::size_t m = pairs.size();
  if (rows.serial.size() < m) rows.serial.resize(pairs.row.size());
  if (rows.warm.size() < m) rows.warm.resize(pairs.row.size());
  rows.coloured.begin(disks.n, m);
  rows.serial_n = 0;
  rows.warm_n = 0;
  for (std::size_t q = 0; q < m; ++q) {
    const auto qi = static_cast<int>(q);
    if (pairs.state[q] & kLive) {
      build_pair_row(model, disks, start, pairs, q);
      if (rows.coloured.add(qi, pairs.gap[q].a, pairs.gap[q].b)) continue;
      rows.warm[rows.warm_n++] = qi;
    }
    rows.serial[rows.serial_n++] = qi;
  }
  rows.live_n = m - rows.serial_n + rows.warm_n;  // coloured + live ones left serial
  rows.coloured.layout();
  load_lanes(pairs, rows.coloured);
}

void integrate_velocities(const Model& model, Disks& disks) {
  const double gh = kGravity * model.substep_s;
  Body* body = disks.body.data();
  for (int i = 0; i < disks.n; ++i)
    if (body[i].im > 0.0) body[i].vy -= gh;
}

void warm_start(const Contacts& contacts, SolverRows& rows, Disks& disks) {
  Body* body = disks.body.data();
  wide_warm_start(body, rows.coloured.rows(), rows.coloured.chunks());
  // Of the serial rows only the live ones: a row without impulse applies nothing (adding its
  // zero impulses would leave every velocity as it was), and most rows are such margins.
  const PairSet& pairs = contacts.pairs;
  for (std::size_t t = 0; t < rows.warm_n; ++t) {
    const auto q = static_cast<std::size_t>(rows.warm[t]);
    const PairGap& g = pairs.gap[q];
    const PairRow& c = pairs.row[q];
    Body& A = body[g.a];
    Body& B = body[g.b];
    const double px = c.ln * g.nx - c.lt * g.ny, py = c.ln * g.ny + c.lt * g.nx;
    A.vx += A.im * px;
    A.vy += A.im * py;
    A.w += A.ii * (c.lr - c.alpha * c.lt);
    B.vx -= B.im * px;
    B.vy -= B.im * py;
    B.w += B.ii * (-c.lr - c.beta * c.lt);
  }
  const LinerSet& liner = contacts.liner;
  for (std::size_t q = 0; q < liner.size(); ++q) {
    const LinerGap& g = liner.gap[q];
    const LinerRow& c = liner.row[q];
    Body& A = body[g.a];
    const double px = c.ln * g.nx - c.lt * g.ny, py = c.ln * g.ny + c.lt * g.nx;
    A.vx += A.im * px;
    A.vy += A.im * py;
    A.w += A.ii * (c.lr - c.alpha * c.lt);
  }
}

void solve(const Model& model, const StepStart& start, double elapsed_s,
           double mill_speed_rad_s, Contacts& contacts, SolverRows& rows, Disks& disks) {
  Body* body = disks.body.data();
  pass_serial_pairs<true>(model, disks, start, contacts.pairs, rows, body);
  const Softness& soft = model.pair_softness;
  WideSoftness wide;
  wide.inv_h = 1.0 / model.substep_s;
  wide.bias_rate = soft.bias_rate;
  wide.mass_scale = soft.mass_scale;
  wide.impulse_scale = soft.impulse_scale;
  wide.push = model.push_out_m_s;
  wide_solve(body, rows.coloured.rows(), rows.coloured.chunks(), wide);
  pass_liner<true>(model, elapsed_s, mill_speed_rad_s, contacts.liner, body);
}

void integrate_positions(const Model& model, Disks& disks) {
  const double h = model.substep_s;
  Body* body = disks.body.data();
  for (int i = 0; i < disks.n; ++i) {
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

void relax(const Model& model, const StepStart& start, double elapsed_s,
           double mill_speed_rad_s, Contacts& contacts, SolverRows& rows, Disks& disks) {
  Body* body = disks.body.data();
  pass_serial_pairs<false>(model, disks, start, contacts.pairs, rows, body);
  wide_relax(body, rows.coloured.rows(), rows.coloured.sums(), rows.coloured.chunks(),
             1.0 / model.substep_s);
  pass_liner<false>(model, elapsed_s, mill_speed_rad_s, contacts.liner, body);
}

void store_lanes(SolverRows& rows, PairSet& pairs) {
  ColouredRows& coloured = rows.coloured;
  for (std::size_t t = 0; t < coloured.coloured(); ++t) {
    const int q = coloured.coloured_contact(t);
    const std::size_t slot = coloured.coloured_slot(t);
    const auto k = static_cast<std::size_t>(q);
    const WideRows& w = coloured.chunk_of(slot);
    const std::size_t l = slot % kLanes;
    PairRow& c = pairs.row[k];
    c.ln = w.ln[l];
    c.lt = w.lt[l];
    c.lr = w.lr[l];
    const WideSums& p = coloured.sums_of(slot);
    pairs.sum[k] = {p.pn[l], p.pt[l], p.pr[l]};
    pairs.state[k] = (pairs.state[k] & kBounce) | kBuilt | has_impulse(c);
  }
}

void apply_restitution(const Model& model, Contacts& contacts, Disks& disks) {
  const double thr = -model.restitution_threshold_m_s;
  Body* body = disks.body.data();
  PairSet& pairs = contacts.pairs;
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    // Only a row that closed fast enough with some restitution bounces: one byte tells
    // (kBounce), and the cold info and sums of the others stay untouched.
    if (!(pairs.state[q] & kBounce)) continue;
    const ContactInfo& info = pairs.info[q];
    StepSum& sum = pairs.sum[q];
    if (sum.pn == 0.0) continue;
    const PairGap& g = pairs.gap[q];
    PairRow& c = pairs.row[q];
    Body& A = body[g.a];
    Body& B = body[g.b];
    const double vn = g.nx * (A.vx - B.vx) + g.ny * (A.vy - B.vy);
    const double next = std::max(c.ln - c.mn * (vn + info.e * info.vn0), 0.0);
    const double d = next - c.ln;
    c.ln = next;
    pairs.state[q] = kBounce | kBuilt | has_impulse(c);
    sum.pn += d;
    A.vx += A.im * d * g.nx;
    A.vy += A.im * d * g.ny;
    B.vx -= B.im * d * g.nx;
    B.vy -= B.im * d * g.ny;
  }
  LinerSet& liner = contacts.liner;
  for (std::size_t q = 0; q < liner.size(); ++q) {
    const ContactInfo& info = liner.info[q];
    StepSum& sum = liner.sum[q];
    if (sum.pn == 0.0 || info.e == 0.0 || info.vn0 > thr) continue;  // sum.pn != 0: built
    const LinerGap& g = liner.gap[q];
    LinerRow& c = liner.row[q];
    Body& A = body[g.a];
    const double vn = g.nx * (A.vx - g.vlx) + g.ny * (A.vy - g.vly);
    const double next = std::max(c.ln - c.mn * (vn + info.e * info.vn0), 0.0);
    const double d = next - c.ln;
    c.ln = next;
    liner.state[q] = kBuilt | has_impulse(c);
    sum.pn += d;
    A.vx += A.im * d * g.nx;
    A.vy += A.im * d * g.ny;
  }
}

}  // namespace millwear::soft
