// The soft backend: our own disk solver, derived from the method of Box2D v3 (soft step with
// substeps and relax, warm starting, restitution once per step) and specialised to a mill
// slice. No Box2D code is used; the method is written for disks from its description.
//
// One step (step_once) reads top to bottom:
//   1. margins     every disk gets a speculative margin that grows with its speed * dt;
//   2. broad phase uniform grids built by counting sort: disks reordered by cell every
//                  kReorderInterval steps (deterministic), for cache locality; a finer grid
//                  over the disks for the pair search;
//   3. narrow      disk pairs, each found once from the cells a disk's reach can touch
//                  (half of them), bucketed into key order; disk-liner contacts from the angle-bin
//                  lookup in the mill frame; both lists come out sorted by pair key and are
//                  matched against last step's to warm start;
//   4. solve       the disk pairs that carry load coloured into lanes; n substeps of
//                  {gravity, warm start, soft solve, integrate positions, relax}, then
//                  restitution once;
//   5. finish      write the state back, catch NaN and escaped disks, feed every contact to
//                  the shared accounting once with its impulses summed over the substeps.
//
// Units are SI throughout (doubles); every tolerance is a fraction of the particle size.
//
// Data. The substep passes touch a disk's velocity, displacement and inverse mass and
// inertia: one 64-byte Body per disk (body.hpp), plus a dummy after the last disk for the
// padding lanes of the wide solve. A contact is a gap (what every pass reads to decide
// whether the row acts), a row (anchors, masses, impulses; built lazily, the first time the
// row acts), a state byte, its step sums (relax), its key (matching) and its cold info
// (restitution, accounting; built with the row): flat arrays in key order kept at their
// high-water mark, no allocation per step once warm. The warm start walks a list of the live rows only.
//
// Colours and lanes (colour_solve.hpp, after Box2D v3's graph colouring and wide solver).
// The disk-pair rows live at the start of a step (they carried an impulse out of the last
// one: a third of the pairs, and nearly all that act in a pass) are coloured greedily in
// key order so that no two rows of a colour share a disk, and are solved four at a time in
// vector lanes; the serial pass keeps the rest, with its skip of inert rows and lazy
// building. In each pass the serial rows go first, then the colours in order, then the
// liner contacts (last, so that they win). Gauss-Seidel order is therefore not key order;
// it is still fixed by the contact list, so results are bit-identical run to run, and the
// same with four (AVX2) or two (SSE2) lanes per register.
//
// Contacts. A contact's normal, anchors and liner velocity are fixed for the step (computed
// once, as Box2D does); substeps update only the separation, s = s0 + n . (dp_a - dp_b),
// with dp the displacement since the step began (the liner's: its velocity at the contact
// times the elapsed time). For disks the anchors lie on the normal, so the normal row has no
// rotational term.
//
// Soft contact. A penetrating contact is an implicit spring-damper of frequency f and
// damping ratio zeta solved at the substep h. With w = 2 pi f the implicit update gives
//   bias_rate = w / (2 zeta + h w),  mass_scale = h w (2 zeta + h w) / (1 + h w (2 zeta + h w)),
//   impulse_scale = 1 / (1 + h w (2 zeta + h w)),
//   d_lambda = -m_n * mass_scale * (vn + max(bias_rate * s, -push_out)) - impulse_scale * lambda.
// The relax pass solves the same rows rigidly with no bias, which takes out the velocity
// the bias added (the position it pushed stays pushed): the energy that bias puts in or
// takes out shows up only as the position correction, reported in solver_position_J.
// A contact still apart (s > 0) is speculative: it allows the disks to close exactly the
// gap this substep (bias s / h) and no more, which is what stops tunnelling.
//
// No tunnelling. A disk gets a speculative margin m = 0.1 r_min + 1.5 (|v| + g dt) dt, and a
// pair or liner contact is created when the gap is under the sum of margins (liner: plus the
// liner's own travel |omega| R dt). A disk that keeps its speed within the step therefore
// always has a constraint before it can reach anything. What this cannot see is a disk
// sped up within the step by a collision to more than 1.5x its start speed and then
// travelling more than its margin: that needs a collision speed above r / dt (a 10 mm disk at
// 1/600 s: 6 m/s gained in one step), beyond the stability envelope of any scene we run.
// Against the liner there is a second line of defence: the liner knows its inside, so a
// disk that ended a step with its centre past a face (by up to half a radius) is pushed back
// out the next step. A centre deeper than that is an escape, reported as an event.
//
// Energy. With anchors and directions fixed for the step, every disk's velocity change is
// exactly gravity * dt plus the sum of its contact impulses / mass, so the sum over contacts
// of P . (v_rel before + v_rel after) / 2, with "before" = start velocity + g dt, is exactly
// the kinetic energy the impulses change: dissipation is split per contact without residue.
// Rolling resistance couples are accounted in the same way (added to the tangential
// dissipation, and through the liner to the drive torque).
#include "common/units.hpp"
#include "engine/soft/soft_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "engine/soft/body.hpp"
#include "engine/soft/broad_phase.hpp"
#include "engine/soft/colour_solve.hpp"
#include "engine/soft/contact_set.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/model.hpp"
#include "engine/soft/narrow_phase.hpp"

namespace millwear {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

using soft::Body;
using soft::ContactInfo;
using soft::ContactKey;
using soft::ContactSet;
using soft::has_impulse;
using soft::kBounce;
using soft::kBuilt;
using soft::kLive;
using soft::LinerGap;
using soft::LinerRow;
using soft::PairGap;
using soft::PairRow;
using soft::Softness;
using soft::StepSum;

class SoftEngine final : public Engine {
 public:
  SoftEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
             const AccountingOptions& opts);

  void set_liner(const MillGeometry& mill) override;
  void set_mill_speed(double omega_rad_s) override { state_.mill_speed_rad_s = omega_rad_s; }
  void step(int n) override {
    if (n <= 0) return;
    for (int k = 0; k < n; ++k) step_once();
    // The window's end energies: only the last step's count, so they are taken once here
    // rather than after every step (two passes over the charge saved per step).
    const auto t0 = Clock::now();
    accounting_.kinetic_J_end = charge_kinetic_J(state_);
    accounting_.potential_J_end = charge_potential_J(state_, kGravity);
    timing_.account_s += seconds_since(t0);
  }
  const ChargeState& state() const override { return state_; }
  double time_step_s() const override { return model_.dt_s; }
  const char* backend_name() const override { return "soft"; }

 private:
  void step_once();
  void colour_live_rows();
  void load_lanes();
  void store_lanes();
  void solve();
  template <bool kBias>
  void solve_pass(double elapsed_s);
  void warm_start();
  void restitution();
  void finish();
  void account_contacts();
  void check_inside_liner();
  void remove_disk(int i, const std::string& why);

  // The model: the constants from the scene, the mill and the charge's sizes, and the liner.
  const soft::Model model_;
  soft::LinerModel liner_;

  // The disks in the solver's (cell) order, and what the step started from (disks.hpp).
  soft::Disks disks_;
  soft::StepStart start_;
  // The disk-pair rows that carry an impulse into the step are solved coloured, in lanes
  // (colour_solve.hpp); the others (rest_, key order) serially. The live rows among the
  // serial ones (some impulse not zero) in key order, for the warm start: set by the
  // colouring for the first substep and by each relax pass for the next.
  soft::ColouredRows coloured_;
  std::vector<int> rest_;
  std::size_t rest_n_ = 0;
  std::vector<int> warm_rows_;
  std::size_t warm_n_ = 0;
  std::size_t live_rows_ = 0;  // pair rows carrying an impulse into this step (timing only)
  soft::Contacts contacts_;
  // Scratch of the broad and narrow phases.
  soft::BroadPhase broad_;
  soft::PairSearch pair_search_;
  soft::LinerSearch liner_search_;

  ChargeState state_;
};

SoftEngine::SoftEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
                       const AccountingOptions& opts)
    : model_(soft::build_model(scene, mill, initial)),
      disks_(soft::load_disks(initial)),
      start_(soft::make_step_start(disks_.n)),
      state_(initial) {
  accounting_.options = opts;
  broad_.reserve(disks_.n);
  contacts_.reserve(disks_.n);
  pair_search_.reserve(disks_.n);
  set_liner(mill);
  reset_window();
}

void SoftEngine::set_liner(const MillGeometry& mill) {
  liner_ = soft::build_liner_model(mill);
  soft::build_liner_search(model_, liner_, liner_search_);
  const std::size_t n = mill.boundary.size();
  edge_count_ = n;
  reset_accounting(accounting_, n);
  // Edge ids changed: liner contacts start cold.
  contacts_.liner.clear();
  contacts_.liner_old.clear();
}

void SoftEngine::remove_disk(int i, const std::string& why) {
  const auto k = static_cast<std::size_t>(i);
  disks_.active[k] = 0;
  disks_.body[k].im = 0.0;
  disks_.body[k].ii = 0.0;
  state_.active[static_cast<std::size_t>(disks_.id[k])] = 0;
  events_.push_back({state_.time_s, "disk " + std::to_string(disks_.id[k]) + " " + why});
}

// ---- 4. solve ---------------------------------------------------------------------------

// Which disk-pair rows are solved in lanes: the live ones (an impulse carried over from the
// last step). They act in nearly every pass of the step, where most of the others are
// margins that never act and that the serial pass skips after reading their gap; a lane
// has no skip, so colouring every contact would solve three times as many rows. The live
// rows are built now (the warm start applies them); a live row that finds no free colour
// stays serial and goes into the serial warm-start list.
void SoftEngine::colour_live_rows() {
  const std::size_t m = contacts_.pairs.size();
  if (rest_.size() < m) rest_.resize(contacts_.pairs.row.size());
  if (warm_rows_.size() < m) warm_rows_.resize(contacts_.pairs.row.size());
  coloured_.begin(disks_.n, m);
  rest_n_ = 0;
  warm_n_ = 0;
  for (std::size_t q = 0; q < m; ++q) {
    const auto qi = static_cast<int>(q);
    if (contacts_.pairs.state[q] & kLive) {
      soft::build_pair_row(model_, disks_, start_, contacts_.pairs, q);
      if (coloured_.add(qi, contacts_.pairs.gap[q].a, contacts_.pairs.gap[q].b)) continue;
      warm_rows_[warm_n_++] = qi;
    }
    rest_[rest_n_++] = qi;
  }
  live_rows_ = m - rest_n_ + warm_n_;  // coloured + live ones left serial
  coloured_.layout();
  load_lanes();
}

// The coloured rows into their lanes in key order (the padding lanes are filled by the
// layout), with zero step sums.
void SoftEngine::load_lanes() {
  for (std::size_t t = 0; t < coloured_.coloured(); ++t) {
    const int q = coloured_.coloured_contact(t);
    const std::size_t slot = coloured_.coloured_slot(t);
    const PairGap& g = contacts_.pairs.gap[static_cast<std::size_t>(q)];
    const PairRow& c = contacts_.pairs.row[static_cast<std::size_t>(q)];
    soft::WideRows& w = coloured_.chunk_of(slot);
    const std::size_t l = slot % soft::kLanes;
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
    soft::WideSums& p = coloured_.sums_of(slot);
    p.pn[l] = p.pt[l] = p.pr[l] = 0.0;
  }
}

// The lanes' impulses, step sums and live bits back to the contact arrays, for the
// restitution, the accounting and the next step's warm start.
void SoftEngine::store_lanes() {
  for (std::size_t t = 0; t < coloured_.coloured(); ++t) {
    const int q = coloured_.coloured_contact(t);
    const std::size_t slot = coloured_.coloured_slot(t);
    const auto k = static_cast<std::size_t>(q);
    const soft::WideRows& w = coloured_.chunk_of(slot);
    const std::size_t l = slot % soft::kLanes;
    PairRow& c = contacts_.pairs.row[k];
    c.ln = w.ln[l];
    c.lt = w.lt[l];
    c.lr = w.lr[l];
    const soft::WideSums& p = coloured_.sums_of(slot);
    contacts_.pairs.sum[k] = {p.pn[l], p.pt[l], p.pr[l]};
    contacts_.pairs.state[k] = (contacts_.pairs.state[k] & kBounce) | kBuilt | has_impulse(c);
  }
}

// Every pass below loads the two bodies of a row into locals, applies the row, and stores
// them back once: the same arithmetic in the same order as updating the arrays in place,
// without the reloads that possible aliasing would force.
void SoftEngine::warm_start() {
  Body* body = disks_.body.data();
  soft::wide_warm_start(body, coloured_.rows(), coloured_.chunks());
  // Of the serial rows only the live ones: a row without impulse applies nothing (adding its
  // zero impulses would leave every velocity as it was), and most rows are such margins.
  for (std::size_t t = 0; t < warm_n_; ++t) {
    const auto q = static_cast<std::size_t>(warm_rows_[t]);
    const PairGap& g = contacts_.pairs.gap[q];
    const PairRow& c = contacts_.pairs.row[q];
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
  for (std::size_t q = 0; q < contacts_.liner.size(); ++q) {
    const LinerGap& g = contacts_.liner.gap[q];
    const LinerRow& c = contacts_.liner.row[q];
    Body& A = body[g.a];
    const double px = c.ln * g.nx - c.lt * g.ny, py = c.ln * g.ny + c.lt * g.nx;
    A.vx += A.im * px;
    A.vy += A.im * py;
    A.w += A.ii * (c.lr - c.alpha * c.lt);
  }
}

// One Gauss-Seidel pass over the serial disk pairs (key order), the coloured ones (colour
// order, in lanes), then the liner contacts (solved last, so they win: the liner must not
// be pushed through). kBias: the soft solve; otherwise the relax,
// which also adds the substep's impulses to the step sums.
// Friction is bounded by mu times the normal impulse, rolling resistance by its lever times
// it (the tangent of a contact is left_perp(n); r_a = -alpha n gives r_a x t = -alpha).
template <bool kBias>
void SoftEngine::solve_pass(double elapsed_s) {
  const double h = model_.dt_s / model_.substeps;
  const double inv_h = 1.0 / h;
  const Softness& soft = model_.pair_softness;
  const Softness& soft_liner = model_.liner_softness;
  const double push = model_.push_out_m_s;
  Body* body = disks_.body.data();

  auto normal_row = [&](auto& c, double s, double vn, const Softness& sf) {
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
  };

  const std::size_t nrest = rest_n_;
  const int* rest = rest_.data();
  const PairGap* gaps = contacts_.pairs.gap.data();
  PairRow* rows = contacts_.pairs.row.data();
  std::uint8_t* state = contacts_.pairs.state.data();
  StepSum* sums = contacts_.pairs.sum.data();
  int* warm = warm_rows_.data();
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
    if (!(state[q] & kBuilt)) soft::build_pair_row(model_, disks_, start_, contacts_.pairs, q);
    PairRow& c = rows[q];
    double vax = A.vx, vay = A.vy, wa = A.w;
    double vbx = B.vx, vby = B.vy, wb = B.w;
    const double ima = A.im, imb = B.im, iia = A.ii, iib = B.ii;
    const double dn = normal_row(c, s, vn, soft);
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
  if (!kBias) warm_n_ = warm_n;
  // The coloured rows, after the serial ones.
  if (kBias) {
    soft::WideSoftness wide;
    wide.inv_h = inv_h;
    wide.bias_rate = soft.bias_rate;
    wide.mass_scale = soft.mass_scale;
    wide.impulse_scale = soft.impulse_scale;
    wide.push = push;
    soft::wide_solve(body, coloured_.rows(), coloured_.chunks(), wide);
  } else {
    soft::wide_relax(body, coloured_.rows(), coloured_.sums(), coloured_.chunks(), inv_h);
  }
  const double omega = state_.mill_speed_rad_s;
  const std::size_t npl = contacts_.liner.size();
  const LinerGap* lgaps = contacts_.liner.gap.data();
  LinerRow* lrows = contacts_.liner.row.data();
  std::uint8_t* lstate = contacts_.liner.state.data();
  StepSum* lsums = contacts_.liner.sum.data();
  for (std::size_t q = 0; q < npl; ++q) {
    const LinerGap& g = lgaps[q];
    Body& A = body[g.a];
    const double s = g.s0 + g.nx * (A.dpx - g.vlx * elapsed_s) + g.ny * (A.dpy - g.vly * elapsed_s);
    const double vn = g.nx * (A.vx - g.vlx) + g.ny * (A.vy - g.vly);
    if (s > 0.0 && vn + s * inv_h >= 0.0 && !(lstate[q] & kLive)) continue;
    LinerRow& c = lrows[q];
    double vax = A.vx, vay = A.vy, wa = A.w;
    const double ima = A.im, iia = A.ii;
    const double dn = normal_row(c, s, vn, soft_liner);
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

// Once per step, after the substeps: contacts that closed faster than the threshold and
// carried load get the restitution impulse that sends them apart at e times that speed.
void SoftEngine::restitution() {
  const double thr = -model_.restitution_threshold_m_s;
  Body* body = disks_.body.data();
  for (std::size_t q = 0; q < contacts_.pairs.size(); ++q) {
    // Only a row that closed fast enough with some restitution bounces: one byte tells
    // (kBounce), and the cold info and sums of the others stay untouched.
    if (!(contacts_.pairs.state[q] & kBounce)) continue;
    const ContactInfo& info = contacts_.pairs.info[q];
    StepSum& sum = contacts_.pairs.sum[q];
    if (sum.pn == 0.0) continue;
    const PairGap& g = contacts_.pairs.gap[q];
    PairRow& c = contacts_.pairs.row[q];
    Body& A = body[g.a];
    Body& B = body[g.b];
    const double vn = g.nx * (A.vx - B.vx) + g.ny * (A.vy - B.vy);
    const double next = std::max(c.ln - c.mn * (vn + info.e * info.vn0), 0.0);
    const double d = next - c.ln;
    c.ln = next;
    contacts_.pairs.state[q] = kBounce | kBuilt | has_impulse(c);
    sum.pn += d;
    A.vx += A.im * d * g.nx;
    A.vy += A.im * d * g.ny;
    B.vx -= B.im * d * g.nx;
    B.vy -= B.im * d * g.ny;
  }
  for (std::size_t q = 0; q < contacts_.liner.size(); ++q) {
    const ContactInfo& info = contacts_.liner.info[q];
    StepSum& sum = contacts_.liner.sum[q];
    if (sum.pn == 0.0 || info.e == 0.0 || info.vn0 > thr) continue;  // sum.pn != 0: built
    const LinerGap& g = contacts_.liner.gap[q];
    LinerRow& c = contacts_.liner.row[q];
    Body& A = body[g.a];
    const double vn = g.nx * (A.vx - g.vlx) + g.ny * (A.vy - g.vly);
    const double next = std::max(c.ln - c.mn * (vn + info.e * info.vn0), 0.0);
    const double d = next - c.ln;
    c.ln = next;
    contacts_.liner.state[q] = kBuilt | has_impulse(c);
    sum.pn += d;
    A.vx += A.im * d * g.nx;
    A.vy += A.im * d * g.ny;
  }
}

void SoftEngine::solve() {
  const double h = model_.dt_s / model_.substeps;
  const double gh = kGravity * h;
  Body* body = disks_.body.data();
  colour_live_rows();
  for (int sub = 0; sub < model_.substeps; ++sub) {
    for (int i = 0; i < disks_.n; ++i)
      if (body[i].im > 0.0) body[i].vy -= gh;
    warm_start();
    solve_pass<true>(sub * h);
    for (int i = 0; i < disks_.n; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (!disks_.active[k]) continue;
      Body& b = body[i];
      const double ddx = h * b.vx, ddy = h * b.vy;
      disks_.x[k] += ddx;
      disks_.y[k] += ddy;
      b.dpx += ddx;
      b.dpy += ddy;
      disks_.angle[k] += h * b.w;
    }
    solve_pass<false>((sub + 1) * h);
  }
  store_lanes();
  restitution();
}

// ---- 5. finish: state, checks, accounting -----------------------------------------------

void SoftEngine::account_contacts() {
  const double omega = state_.mill_speed_rad_s;
  const bool spectrum = accounting_.options.collision_spectrum;
  const Body* body = disks_.body.data();
  ContactRecord rec;
  for (std::size_t q = 0; q < contacts_.pairs.size(); ++q) {
    const StepSum& sum = contacts_.pairs.sum[q];
    ContactKey& key = contacts_.pairs.key[q];
    // An unbuilt row never acted: its sums are zero.
    if (!(contacts_.pairs.state[q] & kBuilt) || (sum.pn == 0.0 && sum.pt == 0.0 && sum.pr == 0.0)) {
      // Apart all step: a collision that was going on has ended.
      if (spectrum && key.event_J > 0.0) account_collision_event(accounting_, key.event_J);
      key.event_J = 0.0;
      continue;
    }
    const ContactInfo& info = contacts_.pairs.info[q];
    const PairGap& g = contacts_.pairs.gap[q];
    const PairRow& c = contacts_.pairs.row[q];
    const auto a = static_cast<std::size_t>(g.a), b = static_cast<std::size_t>(g.b);
    if (!disks_.active[a] || !disks_.active[b]) continue;
    const double tx = -g.ny, ty = g.nx;
    const double dx0 = start_.vx[a] - start_.vx[b], dy0 = start_.vy_before[a] - start_.vy_before[b];
    const double dx1 = body[a].vx - body[b].vx, dy1 = body[a].vy - body[b].vy;
    rec.a = disks_.id[a];
    rec.b = disks_.id[b];
    rec.edge = -1;
    rec.point_m = {info.px, info.py};
    rec.normal = {g.nx, g.ny};
    rec.normal_impulse = sum.pn;
    rec.tangent_impulse = sum.pt;
    rec.vn_before = g.nx * dx0 + g.ny * dy0;
    rec.vn_after = g.nx * dx1 + g.ny * dy1;
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * start_.w[a] - c.beta * start_.w[b];
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * body[a].w - c.beta * body[b].w;
    const auto lo = static_cast<std::uint64_t>(std::min(rec.a, rec.b));
    const auto hi = static_cast<std::uint64_t>(std::max(rec.a, rec.b));
    rec.key = (lo << 32) | hi;
    account_contact(accounting_, rec, omega, false);
    // The rolling couple's dissipation (no field of its own in the record).
    const double rolling_loss = -sum.pr * 0.5 * ((start_.w[a] - start_.w[b]) + (body[a].w - body[b].w));
    accounting_.pp_tangent_J += rolling_loss;
    if (spectrum) {
      key.event_J += -sum.pn * 0.5 * (rec.vn_before + rec.vn_after) -
                      sum.pt * 0.5 * (rec.vt_before + rec.vt_after) + rolling_loss;
    }
  }
  for (std::size_t q = 0; q < contacts_.liner.size(); ++q) {
    const StepSum& sum = contacts_.liner.sum[q];
    if (sum.pn == 0.0 && sum.pt == 0.0 && sum.pr == 0.0) continue;
    const LinerGap& g = contacts_.liner.gap[q];
    const LinerRow& c = contacts_.liner.row[q];
    const ContactInfo& info = contacts_.liner.info[q];
    const auto a = static_cast<std::size_t>(g.a);
    if (!disks_.active[a]) continue;
    const double tx = -g.ny, ty = g.nx;
    const double dx0 = start_.vx[a] - g.vlx, dy0 = start_.vy_before[a] - g.vly;
    const double dx1 = body[a].vx - g.vlx, dy1 = body[a].vy - g.vly;
    rec.a = disks_.id[a];
    rec.b = -1;
    rec.edge = info.edge;
    rec.point_m = {info.px, info.py};
    rec.normal = {g.nx, g.ny};
    rec.normal_impulse = sum.pn;
    rec.tangent_impulse = sum.pt;
    rec.vn_before = g.nx * dx0 + g.ny * dy0;
    rec.vn_after = g.nx * dx1 + g.ny * dy1;
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * start_.w[a];
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * body[a].w;
    rec.key = (static_cast<std::uint64_t>(rec.a) << 32) | 0x80000000u | static_cast<std::uint32_t>(info.edge);
    account_contact(accounting_, rec, omega, liner_.edge_is_shell[static_cast<std::size_t>(info.edge)] != 0);
    // Rolling couple against the liner: the drive supplies it at the mill's speed.
    accounting_.pl_tangent_J += -sum.pr * (0.5 * (start_.w[a] + body[a].w) - omega);
    accounting_.torque_impulse_Nms += sum.pr;
    accounting_.drive_work_J += omega * sum.pr;
  }
}

void SoftEngine::check_inside_liner() {
  // A disk whose centre got deeper into the lifter metal than the liner contact reaches
  // (half a radius) has leaked through.
  const int rows = liner_.mill.rows;
  if (rows <= 0 || liner_.mill.units.empty()) return;
  const double pitch_angle = 2.0 * kPi / rows;
  const double inner_sq = (model_.mill_radius_m - liner_.band_m) * (model_.mill_radius_m - liner_.band_m);
  for (int i = 0; i < disks_.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!disks_.active[k]) continue;
    const Vec2 p{disks_.x[k], disks_.y[k]};
    if (length_sq(p) < inner_sq) continue;
    const Vec2 pm = rotated(p, -state_.mill_angle_rad);
    const double theta = std::atan2(pm.y, pm.x);
    int row = static_cast<int>(std::lround(theta / pitch_angle));
    row = ((row % rows) + rows) % rows;
    const Vec2 local = mill_to_local(pm, row, rows, model_.mill_radius_m);
    const Polyline& surf = liner_.mill.units[liner_.mill.units.size() == 1 ? 0 : static_cast<std::size_t>(row)].surface;
    for (std::size_t e = 0; e + 1 < surf.size(); ++e) {
      const Vec2 a = surf[e], b = surf[e + 1];
      if ((local.x - a.x) * (local.x - b.x) > 0.0 || a.x == b.x) continue;
      const double y_surface = a.y + (b.y - a.y) * (local.x - a.x) / (b.x - a.x);
      if (local.y < y_surface - 0.5 * disks_.radius[k]) {
        accounting_.escaped += 1;
        remove_disk(i, "leaked into the liner");
      }
      break;
    }
  }
}

void SoftEngine::finish() {
  const double g = kGravity;
  for (int i = 0; i < disks_.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!disks_.active[k]) continue;
    const auto id = static_cast<std::size_t>(disks_.id[k]);
    if (!std::isfinite(disks_.x[k]) || !std::isfinite(disks_.y[k]) || !std::isfinite(disks_.body[k].vx) ||
        !std::isfinite(disks_.body[k].vy) || !std::isfinite(disks_.body[k].w)) {
      accounting_.non_finite += 1;
      remove_disk(i, "went non-finite");
      continue;
    }
    // What the soft bias moved beyond x0 + dt v1 (the symplectic-Euler step with the final
    // velocity): its potential energy is the solver's share of the energy balance.
    const double corr_y = (disks_.y[k] - start_.y[k]) - model_.dt_s * disks_.body[k].vy;
    accounting_.solver_position_J -= disks_.mass[k] * g * corr_y;
    state_.position_m[id] = {disks_.x[k], disks_.y[k]};
    state_.velocity_m_s[id] = {disks_.body[k].vx, disks_.body[k].vy};
    state_.angle_rad[id] = disks_.angle[k];
    state_.spin_rad_s[id] = disks_.body[k].w;
    const double escape_r = liner_.max_r_m + 0.5 * disks_.radius[k];
    if (disks_.x[k] * disks_.x[k] + disks_.y[k] * disks_.y[k] > escape_r * escape_r) {
      accounting_.escaped += 1;
      remove_disk(i, "escaped through the shell");
    }
  }
}

void SoftEngine::step_once() {
  const auto t_start = Clock::now();

  contacts_.begin_step();
  const soft::StepBounds bounds = soft::update_margins(model_, disks_);
  if (soft::reorder_due(accounting_.steps, disks_))
    soft::reorder_by_cell(model_, liner_, bounds, broad_, disks_, contacts_);
  soft::record_step_start(model_, disks_, start_);
  soft::build_pair_grid(model_, bounds, disks_, broad_);
  const auto t_broad = Clock::now();
  timing_.broad_s += std::chrono::duration<double>(t_broad - t_start).count();

  // 3. Narrow phase.
  const double omega = state_.mill_speed_rad_s;
  soft::fit_liner_search(model_, liner_, bounds, omega, liner_search_);
  soft::find_pairs(model_, disks_, broad_.pair_grid, bounds, pair_search_, contacts_.pairs);
  soft::find_liner_contacts(model_, liner_, liner_search_, disks_, state_.mill_angle_rad, omega,
                            contacts_.liner);
  soft::match_warm_start(contacts_, accounting_);
  const auto t_narrow = Clock::now();
  timing_.collide_s += std::chrono::duration<double>(t_narrow - t_broad).count();

  // 4. Solve.
  solve();
  const auto t_solve = Clock::now();
  timing_.solve_s += std::chrono::duration<double>(t_solve - t_narrow).count();
  timing_.disk_steps += disks_.n;
  timing_.pair_rows += static_cast<std::int64_t>(contacts_.pairs.size());
  timing_.live_pair_rows += static_cast<std::int64_t>(live_rows_);
  timing_.liner_rows += static_cast<std::int64_t>(contacts_.liner.size());

  // 5. Finish.
  finish();
  account_contacts();
  state_.time_s += model_.dt_s;
  state_.mill_angle_rad += state_.mill_speed_rad_s * model_.dt_s;
  if (accounting_.steps % 16 == 0) check_inside_liner();
  account_step(accounting_, state_, model_.dt_s, model_.mill_radius_m, model_.shape_band_m + liner_.band_m, kGravity);
  timing_.account_s += seconds_since(t_solve);
}

}  // namespace

std::unique_ptr<Engine> make_soft_engine(const Scene& scene, const MillGeometry& mill,
                                         const ChargeState& initial,
                                         const AccountingOptions& opts) {
  return std::make_unique<SoftEngine>(scene, mill, initial, opts);
}

}  // namespace millwear
