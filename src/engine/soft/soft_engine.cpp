// The soft backend: our own disk solver, derived from the method of Box2D v3 (soft step with
// substeps and relax, warm starting, restitution once per step) and specialised to a mill
// slice. No Box2D code is used; the method is written for disks from its description.
//
// One step (step_once) reads top to bottom:
//   1. margins     every disk gets a speculative margin that grows with its speed * dt;
//   2. broad phase a uniform grid built by counting sort; disks reordered by cell every
//                  kReorderInterval steps (deterministic), for cache locality;
//   3. narrow      disk pairs from the 3x3 cells, disk-liner contacts from the angle-bin
//                  lookup in the mill frame; both lists come out sorted by pair key and are
//                  matched against last step's to warm start;
//   4. solve       n substeps of {gravity, warm start, soft solve, integrate positions,
//                  relax}, then restitution once;
//   5. finish      write the state back, catch NaN and escaped disks, feed every contact to
//                  the shared accounting once with its impulses summed over the substeps.
//
// Units are SI throughout (doubles); every tolerance is a fraction of the particle size.
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
#include "engine/soft/soft_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>

#include "engine/soft/grid.hpp"
#include "engine/soft/liner_lookup.hpp"

namespace millwear {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kReorderInterval = 64;     // steps between reorderings of the disks by cell
constexpr int kMaxLinerHits = 8;         // liner contacts of one disk in one step
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// One contact, persisted across steps (warm starting), flat and plain.
struct Contact {
  std::uint64_t key = 0;   // (a << 32) | b for disk pairs (a < b), (a << 32) | edge for liner
  int a = 0, b = -1;       // internal disk indices; b = -1 for the liner
  int edge = -1;           // liner edge the contact's work goes to
  int owner = -1;          // liner edge that found it (its key)
  double nx = 0, ny = 0;   // unit normal from b (or the liner) toward a
  double alpha = 0, beta = 0;  // anchors: r_a = -alpha n, r_b = +beta n
  double px = 0, py = 0;   // contact point, world (liner contacts: for torque and velocity)
  double vlx = 0, vly = 0; // liner velocity at the contact point (0 for disk pairs)
  double s0 = 0;           // separation at the start of the step
  double mn = 0, mt = 0, mr = 0;  // effective masses: normal, tangent, rolling
  double mu = 0, e = 0, lever = 0;
  double vn0 = 0;          // normal relative velocity at the start of the step (restitution)
  double ln = 0, lt = 0, lr = 0;  // impulses of the current substep (warm start)
  double pn = 0, pt = 0, pr = 0;  // impulses summed over the step
  double event_J = 0;      // energy dissipated since this collision began (spectrum)
};

struct Softness {
  double bias_rate = 0, mass_scale = 1, impulse_scale = 0;
};

Softness make_softness(double hertz, double zeta, double h) {
  const double w = 2.0 * kPi * hertz;
  const double a1 = 2.0 * zeta + h * w;
  const double a2 = h * w * a1;
  const double a3 = 1.0 / (1.0 + a2);
  return {w / a1, a2 * a3, a3};
}

class SoftEngine final : public Engine {
 public:
  SoftEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
             const AccountingOptions& opts);

  void set_liner(const MillGeometry& mill) override;
  void set_mill_speed(double omega_rad_s) override { state_.mill_speed_rad_s = omega_rad_s; }
  void step(int n) override {
    for (int k = 0; k < n; ++k) step_once();
  }
  const ChargeState& state() const override { return state_; }
  double time_step_s() const override { return dt_; }
  const char* backend_name() const override { return "soft"; }

 private:
  void step_once();
  void reorder_by_cell();
  void find_pairs();
  void find_liner_contacts();
  void warm_start_match();
  void solve();
  template <bool kBias>
  void solve_pass(double elapsed_s, bool accumulate);
  void warm_start();
  void restitution();
  void finish();
  void account_contacts();
  void check_inside_liner();
  void remove_disk(int i, const std::string& why);
  Contact make_pair_contact(int i, int j) const;

  // Description (fixed).
  double dt_ = 1.0 / 600.0;
  int substeps_ = 4;
  double hertz_ = 0.0, zeta_ = 10.0, push_out_m_s_ = 1.0;
  double restitution_threshold_m_s_ = 0.1;
  double margin_base_m_ = 0.0;
  double r_min_ = 0.0, r_max_ = 0.0;
  double radius_m_ = 0.0, band_m_ = 0.0, shape_band_m_ = 0.0, max_r_m_ = 0.0;
  int species_count_ = 1;
  std::vector<double> mu_pair_, e_pair_, rr_pair_;   // species x species
  std::vector<double> mu_liner_, e_liner_, rr_;      // per species

  // Disk state, structure of arrays, in internal (cell) order; id_ maps to the caller's.
  int n_ = 0;
  std::vector<int> id_;
  std::vector<double> x_, y_, vx_, vy_, w_, ang_, im_, ii_, r_, mass_;
  std::vector<unsigned char> act_;
  std::vector<std::uint8_t> sp_;
  std::vector<double> dpx_, dpy_, x0_, y0_, vbx_, vby_, wb_, marg_;
  std::vector<double> scratch_d_;
  std::vector<int> scratch_i_, inverse_;
  std::vector<unsigned char> scratch_u_;

  // Contacts: current and last step's, each sorted by key.
  std::vector<Contact> pp_, pl_, pp_old_, pl_old_;
  soft::Grid grid_;
  soft::LinerLookup liner_;
  MillGeometry mill_;
  std::vector<std::uint8_t> edge_is_shell_;
  double liner_reach_need_ = 0.0;
  double margin_max_ = 0.0;

  ChargeState state_;
};

SoftEngine::SoftEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
                       const AccountingOptions& opts)
    : state_(initial) {
  accounting_.options = opts;
  dt_ = scene.solver.time_step_s;
  substeps_ = scene.solver.substeps;
  const double h = dt_ / substeps_;
  // Box2D v3 caps the contact frequency at an eighth of the substep rate; higher is not
  // resolved by one soft iteration per substep. Liner contacts get twice it (as static
  // contacts do in Box2D) and a quarter is the most we allow for them.
  hertz_ = scene.solver.contact_hertz > 0.0 ? std::min(scene.solver.contact_hertz, 0.125 / h)
                                            : 0.125 / h;
  zeta_ = scene.solver.damping_ratio;
  radius_m_ = mill.radius_m;

  n_ = static_cast<int>(state_.size());
  r_min_ = 0.0;
  r_max_ = 0.0;
  double mean_d = 0.0;
  for (int i = 0; i < n_; ++i) {
    const double r = state_.radius_m[static_cast<std::size_t>(i)];
    r_min_ = i == 0 ? r : std::min(r_min_, r);
    r_max_ = std::max(r_max_, r);
    mean_d += 2.0 * r / n_;
  }
  if (n_ == 0) r_min_ = r_max_ = 0.01 * radius_m_, mean_d = 2.0 * r_min_;
  push_out_m_s_ = scene.solver.push_out_radii_per_s * r_min_;
  // Restitution only for impacts faster than 1.67 mean diameters per second: the same
  // threshold as the Box2D backend (1 unit/s at its scaling), so both bounce alike.
  restitution_threshold_m_s_ = mean_d / 0.6;
  margin_base_m_ = 0.1 * r_min_;
  shape_band_m_ = 2.0 * r_max_;

  const auto& species = scene.charge.species;
  species_count_ = static_cast<int>(std::max<std::size_t>(species.size(), 1));
  mu_pair_.assign(static_cast<std::size_t>(species_count_ * species_count_), 0.5);
  e_pair_ = mu_pair_;
  rr_pair_.assign(mu_pair_.size(), 0.0);
  mu_liner_.assign(static_cast<std::size_t>(species_count_), 0.5);
  e_liner_.assign(mu_liner_.size(), 0.0);
  rr_.assign(mu_liner_.size(), 0.0);
  for (std::size_t a = 0; a < species.size(); ++a) {
    mu_liner_[a] = species[a].friction_liner;
    e_liner_[a] = species[a].restitution_liner;
    rr_[a] = species[a].rolling_resistance;
    for (std::size_t b = 0; b < species.size(); ++b) {
      const std::size_t k = a * species.size() + b;
      // Mixing as in Box2D: friction geometric mean, restitution the larger; rolling
      // resistance the larger coefficient (times the pair's reduced radius, below).
      mu_pair_[k] = std::sqrt(species[a].friction * species[b].friction);
      e_pair_[k] = std::max(species[a].restitution, species[b].restitution);
      rr_pair_[k] = std::max(species[a].rolling_resistance, species[b].rolling_resistance);
    }
  }

  const auto n = static_cast<std::size_t>(n_);
  id_.resize(n);
  x_.resize(n); y_.resize(n); vx_.resize(n); vy_.resize(n); w_.resize(n); ang_.resize(n);
  im_.resize(n); ii_.resize(n); r_.resize(n); mass_.resize(n); act_.resize(n); sp_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    id_[i] = static_cast<int>(i);
    x_[i] = state_.position_m[i].x;
    y_[i] = state_.position_m[i].y;
    vx_[i] = state_.velocity_m_s[i].x;
    vy_[i] = state_.velocity_m_s[i].y;
    w_[i] = state_.spin_rad_s[i];
    ang_[i] = state_.angle_rad[i];
    r_[i] = state_.radius_m[i];
    mass_[i] = state_.mass_kg[i];
    sp_[i] = state_.species[i];
    act_[i] = state_.active[i];
    // A disk's moment of inertia is m r^2 / 2.
    im_[i] = act_[i] ? 1.0 / mass_[i] : 0.0;
    ii_[i] = act_[i] ? 2.0 / (mass_[i] * r_[i] * r_[i]) : 0.0;
  }
  for (auto* v : {&dpx_, &dpy_, &x0_, &y0_, &vbx_, &vby_, &wb_, &marg_, &scratch_d_}) v->assign(n, 0.0);
  scratch_i_.assign(n, 0);
  inverse_.assign(n, 0);
  scratch_u_.assign(n, 0);
  const std::size_t expected_contacts = 4 * n + 16;
  for (auto* v : {&pp_, &pl_, &pp_old_, &pl_old_}) v->reserve(expected_contacts);
  set_liner(mill);
  reset_window();
}

void SoftEngine::set_liner(const MillGeometry& mill) {
  mill_ = mill;
  max_r_m_ = 0.0;
  double min_r = 1e300;
  for (const Vec2& p : mill.boundary) {
    max_r_m_ = std::max(max_r_m_, length(p));
    min_r = std::min(min_r, length(p));
  }
  band_m_ = max_r_m_ - min_r;
  liner_.build(mill, std::max(liner_reach_need_, 1.5 * (r_max_ + 2.0 * margin_base_m_)));
  const std::size_t n = mill.boundary.size();
  edge_is_shell_.resize(n);
  for (std::size_t e = 0; e < n; ++e)
    edge_is_shell_[e] = mill.edges[e].owner == EdgeOwner::Shell ? 1 : 0;
  // The grid covers the whole mill: a disk outside it has escaped (and is removed).
  grid_.side = 2.0 * (max_r_m_ + 2.0 * r_max_);
  grid_.origin = -0.5 * grid_.side;
  edge_count_ = n;
  reset_accounting(accounting_, n);
  // Edge ids changed: liner contacts start cold.
  pl_.clear();
  pl_old_.clear();
}

void SoftEngine::remove_disk(int i, const std::string& why) {
  const auto k = static_cast<std::size_t>(i);
  act_[k] = 0;
  im_[k] = 0.0;
  ii_[k] = 0.0;
  state_.active[static_cast<std::size_t>(id_[k])] = 0;
  events_.push_back({state_.time_s, "disk " + std::to_string(id_[k]) + " " + why});
}

// ---- 2. broad phase helpers -------------------------------------------------------------

// Permute every per-disk array into grid order (active disks by cell, then the inactive),
// and carry the contacts over to the new indices. Deterministic: the grid order is.
void SoftEngine::reorder_by_cell() {
  const auto n = static_cast<std::size_t>(n_);
  std::size_t k = 0;
  for (int c = 0; c < grid_.placed(); ++c) scratch_i_[k++] = grid_.order[static_cast<std::size_t>(c)];
  for (std::size_t i = 0; i < n; ++i)
    if (grid_.cell_of[i] < 0) scratch_i_[k++] = static_cast<int>(i);
  const std::vector<int>& perm = scratch_i_;  // new -> old
  for (std::size_t i = 0; i < n; ++i) inverse_[static_cast<std::size_t>(perm[i])] = static_cast<int>(i);
  auto permute_d = [&](std::vector<double>& v) {
    for (std::size_t i = 0; i < n; ++i) scratch_d_[i] = v[static_cast<std::size_t>(perm[i])];
    v.swap(scratch_d_);
  };
  for (auto* v : {&x_, &y_, &vx_, &vy_, &w_, &ang_, &im_, &ii_, &r_, &mass_, &marg_}) permute_d(*v);
  for (std::size_t i = 0; i < n; ++i) scratch_u_[i] = act_[static_cast<std::size_t>(perm[i])];
  act_.swap(scratch_u_);
  for (std::size_t i = 0; i < n; ++i) scratch_u_[i] = sp_[static_cast<std::size_t>(perm[i])];
  sp_.swap(scratch_u_);
  std::vector<int> ids(n);  // rare (every kReorderInterval steps): a small allocation is fine
  for (std::size_t i = 0; i < n; ++i) ids[i] = id_[static_cast<std::size_t>(perm[i])];
  id_.swap(ids);
  for (Contact& c : pp_) {
    int a = inverse_[static_cast<std::size_t>(c.a)], b = inverse_[static_cast<std::size_t>(c.b)];
    if (a > b) {
      // Swapping the roles flips the normal and tangent: the tangent impulse on the new a
      // keeps its sign, the rolling couple on it changes sign.
      std::swap(a, b);
      c.lr = -c.lr;
    }
    c.a = a;
    c.b = b;
    c.key = (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
  }
  for (Contact& c : pl_) {
    c.a = inverse_[static_cast<std::size_t>(c.a)];
    c.key = (static_cast<std::uint64_t>(c.a) << 32) | static_cast<std::uint32_t>(c.owner);
  }
  auto by_key = [](const Contact& p, const Contact& q) { return p.key < q.key; };
  std::sort(pp_.begin(), pp_.end(), by_key);
  std::sort(pl_.begin(), pl_.end(), by_key);
  grid_.build(x_.data(), y_.data(), act_.data(), n_, grid_.cell);
}

// ---- 3. narrow phase --------------------------------------------------------------------

Contact SoftEngine::make_pair_contact(int i, int j) const {
  const auto a = static_cast<std::size_t>(i), b = static_cast<std::size_t>(j);
  Contact c;
  c.a = i;
  c.b = j;
  c.key = (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
  const double dx = x_[a] - x_[b], dy = y_[a] - y_[b];
  const double dist = std::sqrt(dx * dx + dy * dy);
  if (dist > 0.0) {
    c.nx = dx / dist;
    c.ny = dy / dist;
  } else {
    c.nx = 0.0;
    c.ny = 1.0;
  }
  c.s0 = dist - r_[a] - r_[b];
  // The contact point is midway between the two surfaces.
  c.alpha = r_[a] + 0.5 * c.s0;
  c.beta = r_[b] + 0.5 * c.s0;
  c.px = x_[a] - c.alpha * c.nx;
  c.py = y_[a] - c.alpha * c.ny;
  const double im = im_[a] + im_[b];
  c.mn = im > 0.0 ? 1.0 / im : 0.0;
  const double it = im + ii_[a] * c.alpha * c.alpha + ii_[b] * c.beta * c.beta;
  c.mt = it > 0.0 ? 1.0 / it : 0.0;
  const double ir = ii_[a] + ii_[b];
  c.mr = ir > 0.0 ? 1.0 / ir : 0.0;
  const std::size_t pair = static_cast<std::size_t>(sp_[a]) * static_cast<std::size_t>(species_count_) + sp_[b];
  c.mu = mu_pair_[pair];
  c.e = e_pair_[pair];
  // Rolling resistance lever: the coefficient times the pair's reduced radius (the DEM
  // convention; a disk on a flat liner gets its own radius).
  c.lever = rr_pair_[pair] * r_[a] * r_[b] / (r_[a] + r_[b]);
  c.vn0 = (vx_[a] - vx_[b]) * c.nx + (vy_[a] - vy_[b]) * c.ny;
  return c;
}

// Pairs from the 3x3 cells around each disk, j > i only, in (i, j) order: sorted by key.
void SoftEngine::find_pairs() {
  pp_.clear();
  const int dim = grid_.dim;
  const int* order = grid_.order.data();
  const int* start = grid_.start.data();
  int cand[64];
  for (int i = 0; i < n_; ++i) {
    const int cell = grid_.cell_of[static_cast<std::size_t>(i)];
    if (cell < 0) continue;
    const int cx = cell % dim, cy = cell / dim;
    const double xi = x_[static_cast<std::size_t>(i)], yi = y_[static_cast<std::size_t>(i)];
    const double reach_i = r_[static_cast<std::size_t>(i)] + marg_[static_cast<std::size_t>(i)];
    int count = 0;
    for (int gy = std::max(cy - 1, 0); gy <= std::min(cy + 1, dim - 1); ++gy) {
      const int row = gy * dim;
      const int k0 = start[row + std::max(cx - 1, 0)];
      const int k1 = start[row + std::min(cx + 1, dim - 1) + 1];
      for (int k = k0; k < k1; ++k) {
        const int j = order[k];
        if (j <= i) continue;
        const auto jj = static_cast<std::size_t>(j);
        const double dx = xi - x_[jj], dy = yi - y_[jj];
        const double reach = reach_i + r_[jj] + marg_[jj];
        if (dx * dx + dy * dy < reach * reach && count < 64) cand[count++] = j;
      }
    }
    // A handful of candidates: insertion sort keeps the list in key order.
    for (int p = 1; p < count; ++p)
      for (int q = p; q > 0 && cand[q - 1] > cand[q]; --q) std::swap(cand[q - 1], cand[q]);
    for (int p = 0; p < count; ++p) pp_.push_back(make_pair_contact(i, cand[p]));
  }
}

// Disk-liner contacts through the mill-frame lookup; the liner's velocity at a contact is
// omega x r.
void SoftEngine::find_liner_contacts() {
  pl_.clear();
  const double omega = state_.mill_speed_rad_s;
  const double cs = std::cos(state_.mill_angle_rad), sn = std::sin(state_.mill_angle_rad);
  const double liner_travel = std::fabs(omega) * max_r_m_ * dt_;
  soft::LinerHit hits[kMaxLinerHits];
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!act_[k]) continue;
    const double margin = marg_[k] + liner_travel;
    // Into the mill frame (rotate by -theta).
    const Vec2 pm{cs * x_[k] + sn * y_[k], -sn * x_[k] + cs * y_[k]};
    if (!liner_.may_touch(pm, r_[k] + margin)) continue;
    const int count = liner_.query(pm, r_[k], margin, hits, kMaxLinerHits);
    for (int q = 0; q < count; ++q) {
      const soft::LinerHit& hit = hits[q];
      Contact c;
      c.a = i;
      c.b = -1;
      c.edge = hit.edge;
      c.owner = hit.owner;
      c.key = (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(hit.owner);
      c.nx = cs * hit.normal.x - sn * hit.normal.y;  // back to the world frame
      c.ny = sn * hit.normal.x + cs * hit.normal.y;
      c.s0 = hit.gap;
      c.alpha = r_[k] + 0.5 * c.s0;
      c.beta = 0.0;
      c.px = x_[k] - c.alpha * c.nx;
      c.py = y_[k] - c.alpha * c.ny;
      c.vlx = -omega * c.py;
      c.vly = omega * c.px;
      c.mn = im_[k] > 0.0 ? 1.0 / im_[k] : 0.0;
      const double it = im_[k] + ii_[k] * c.alpha * c.alpha;
      c.mt = it > 0.0 ? 1.0 / it : 0.0;
      c.mr = ii_[k] > 0.0 ? 1.0 / ii_[k] : 0.0;
      c.mu = mu_liner_[sp_[k]];
      c.e = e_liner_[sp_[k]];
      c.lever = rr_[sp_[k]] * r_[k];
      c.vn0 = (vx_[k] - c.vlx) * c.nx + (vy_[k] - c.vly) * c.ny;
      pl_.push_back(c);
    }
  }
}

// Carry last step's impulses to the contacts that persist (merge of two key-sorted lists).
// A disk-pair contact that ended closes its collision event for the spectrum.
void SoftEngine::warm_start_match() {
  const bool spectrum = accounting_.options.collision_spectrum;
  auto merge = [&](std::vector<Contact>& now, const std::vector<Contact>& old, bool events) {
    std::size_t p = 0;
    for (Contact& c : now) {
      while (p < old.size() && old[p].key < c.key) {
        if (events && old[p].event_J > 0.0) account_collision_event(accounting_, old[p].event_J);
        ++p;
      }
      if (p < old.size() && old[p].key == c.key) {
        c.ln = old[p].ln;
        c.lt = old[p].lt;
        c.lr = old[p].lr;
        c.event_J = old[p].event_J;
        ++p;
      }
    }
    for (; p < old.size(); ++p)
      if (events && old[p].event_J > 0.0) account_collision_event(accounting_, old[p].event_J);
  };
  merge(pp_, pp_old_, spectrum);
  merge(pl_, pl_old_, false);
}

// ---- 4. solve ---------------------------------------------------------------------------

void SoftEngine::warm_start() {
  double* vx = vx_.data();
  double* vy = vy_.data();
  double* w = w_.data();
  const double* im = im_.data();
  const double* ii = ii_.data();
  for (const Contact& c : pp_) {
    const double px = c.ln * c.nx - c.lt * c.ny, py = c.ln * c.ny + c.lt * c.nx;
    vx[c.a] += im[c.a] * px;
    vy[c.a] += im[c.a] * py;
    w[c.a] += ii[c.a] * (c.lr - c.alpha * c.lt);
    vx[c.b] -= im[c.b] * px;
    vy[c.b] -= im[c.b] * py;
    w[c.b] += ii[c.b] * (-c.lr - c.beta * c.lt);
  }
  for (const Contact& c : pl_) {
    const double px = c.ln * c.nx - c.lt * c.ny, py = c.ln * c.ny + c.lt * c.nx;
    vx[c.a] += im[c.a] * px;
    vy[c.a] += im[c.a] * py;
    w[c.a] += ii[c.a] * (c.lr - c.alpha * c.lt);
  }
}

// One Gauss-Seidel pass over the disk pairs, then the liner contacts (solved last, so they
// win: the liner must not be pushed through). kBias: the soft solve; otherwise the relax.
// Friction is bounded by mu times the normal impulse, rolling resistance by its lever times
// it (the tangent of a contact is left_perp(n); r_a = -alpha n gives r_a x t = -alpha).
template <bool kBias>
void SoftEngine::solve_pass(double elapsed_s, bool accumulate) {
  const double h = dt_ / substeps_;
  const double inv_h = 1.0 / h;
  const Softness soft = make_softness(hertz_, zeta_, h);
  const Softness soft_liner = make_softness(2.0 * hertz_, zeta_, h);
  const double push = push_out_m_s_;
  double* vx = vx_.data();
  double* vy = vy_.data();
  double* w = w_.data();
  const double* im = im_.data();
  const double* ii = ii_.data();
  const double* dpx = dpx_.data();
  const double* dpy = dpy_.data();

  auto normal_row = [&](Contact& c, double s, double vn, const Softness& sf) {
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

  for (Contact& c : pp_) {
    const int a = c.a, b = c.b;
    const double s = c.s0 + c.nx * (dpx[a] - dpx[b]) + c.ny * (dpy[a] - dpy[b]);
    const double vn = c.nx * (vx[a] - vx[b]) + c.ny * (vy[a] - vy[b]);
    const double dn = normal_row(c, s, vn, soft);
    vx[a] += im[a] * dn * c.nx;
    vy[a] += im[a] * dn * c.ny;
    vx[b] -= im[b] * dn * c.nx;
    vy[b] -= im[b] * dn * c.ny;
    // Friction.
    const double tx = -c.ny, ty = c.nx;
    const double vt = tx * (vx[a] - vx[b]) + ty * (vy[a] - vy[b]) - c.alpha * w[a] - c.beta * w[b];
    const double bound = c.mu * c.ln;
    const double lt = std::clamp(c.lt - c.mt * vt, -bound, bound);
    const double dt_imp = lt - c.lt;
    c.lt = lt;
    vx[a] += im[a] * dt_imp * tx;
    vy[a] += im[a] * dt_imp * ty;
    w[a] -= ii[a] * c.alpha * dt_imp;
    vx[b] -= im[b] * dt_imp * tx;
    vy[b] -= im[b] * dt_imp * ty;
    w[b] -= ii[b] * c.beta * dt_imp;
    // Rolling resistance.
    if (c.lever > 0.0) {
      const double rb = c.lever * c.ln;
      const double lr = std::clamp(c.lr - c.mr * (w[a] - w[b]), -rb, rb);
      const double dr = lr - c.lr;
      c.lr = lr;
      w[a] += ii[a] * dr;
      w[b] -= ii[b] * dr;
    }
    if (accumulate) {
      c.pn += c.ln;
      c.pt += c.lt;
      c.pr += c.lr;
    }
  }
  const double omega = state_.mill_speed_rad_s;
  for (Contact& c : pl_) {
    const int a = c.a;
    const double s = c.s0 + c.nx * (dpx[a] - c.vlx * elapsed_s) + c.ny * (dpy[a] - c.vly * elapsed_s);
    const double vn = c.nx * (vx[a] - c.vlx) + c.ny * (vy[a] - c.vly);
    const double dn = normal_row(c, s, vn, soft_liner);
    vx[a] += im[a] * dn * c.nx;
    vy[a] += im[a] * dn * c.ny;
    const double tx = -c.ny, ty = c.nx;
    const double vt = tx * (vx[a] - c.vlx) + ty * (vy[a] - c.vly) - c.alpha * w[a];
    const double bound = c.mu * c.ln;
    const double lt = std::clamp(c.lt - c.mt * vt, -bound, bound);
    const double dt_imp = lt - c.lt;
    c.lt = lt;
    vx[a] += im[a] * dt_imp * tx;
    vy[a] += im[a] * dt_imp * ty;
    w[a] -= ii[a] * c.alpha * dt_imp;
    if (c.lever > 0.0) {
      const double rb = c.lever * c.ln;
      const double lr = std::clamp(c.lr - c.mr * (w[a] - omega), -rb, rb);
      w[a] += ii[a] * (lr - c.lr);
      c.lr = lr;
    }
    if (accumulate) {
      c.pn += c.ln;
      c.pt += c.lt;
      c.pr += c.lr;
    }
  }
}

// Once per step, after the substeps: contacts that closed faster than the threshold and
// carried load get the restitution impulse that sends them apart at e times that speed.
void SoftEngine::restitution() {
  const double thr = -restitution_threshold_m_s_;
  double* vx = vx_.data();
  double* vy = vy_.data();
  const double* im = im_.data();
  for (Contact& c : pp_) {
    if (c.e == 0.0 || c.vn0 > thr || c.pn == 0.0) continue;
    const double vn = c.nx * (vx[c.a] - vx[c.b]) + c.ny * (vy[c.a] - vy[c.b]);
    const double next = std::max(c.ln - c.mn * (vn + c.e * c.vn0), 0.0);
    const double d = next - c.ln;
    c.ln = next;
    c.pn += d;
    vx[c.a] += im[c.a] * d * c.nx;
    vy[c.a] += im[c.a] * d * c.ny;
    vx[c.b] -= im[c.b] * d * c.nx;
    vy[c.b] -= im[c.b] * d * c.ny;
  }
  for (Contact& c : pl_) {
    if (c.e == 0.0 || c.vn0 > thr || c.pn == 0.0) continue;
    const double vn = c.nx * (vx[c.a] - c.vlx) + c.ny * (vy[c.a] - c.vly);
    const double next = std::max(c.ln - c.mn * (vn + c.e * c.vn0), 0.0);
    const double d = next - c.ln;
    c.ln = next;
    c.pn += d;
    vx[c.a] += im[c.a] * d * c.nx;
    vy[c.a] += im[c.a] * d * c.ny;
  }
}

void SoftEngine::solve() {
  const double h = dt_ / substeps_;
  const double gh = kGravity * h;
  for (int sub = 0; sub < substeps_; ++sub) {
    for (int i = 0; i < n_; ++i)
      if (im_[static_cast<std::size_t>(i)] > 0.0) vy_[static_cast<std::size_t>(i)] -= gh;
    warm_start();
    solve_pass<true>(sub * h, false);
    for (int i = 0; i < n_; ++i) {
      const auto k = static_cast<std::size_t>(i);
      if (!act_[k]) continue;
      const double ddx = h * vx_[k], ddy = h * vy_[k];
      x_[k] += ddx;
      y_[k] += ddy;
      dpx_[k] += ddx;
      dpy_[k] += ddy;
      ang_[k] += h * w_[k];
    }
    solve_pass<false>((sub + 1) * h, true);
  }
  restitution();
}

// ---- 5. finish: state, checks, accounting -----------------------------------------------

void SoftEngine::account_contacts() {
  const double omega = state_.mill_speed_rad_s;
  const bool spectrum = accounting_.options.collision_spectrum;
  ContactRecord rec;
  for (Contact& c : pp_) {
    if (c.pn == 0.0 && c.pt == 0.0 && c.pr == 0.0) {
      // Apart all step: a collision that was going on has ended.
      if (spectrum && c.event_J > 0.0) account_collision_event(accounting_, c.event_J);
      c.event_J = 0.0;
      continue;
    }
    const auto a = static_cast<std::size_t>(c.a), b = static_cast<std::size_t>(c.b);
    if (!act_[a] || !act_[b]) continue;
    const double tx = -c.ny, ty = c.nx;
    const double dx0 = vbx_[a] - vbx_[b], dy0 = vby_[a] - vby_[b];
    const double dx1 = vx_[a] - vx_[b], dy1 = vy_[a] - vy_[b];
    rec.a = id_[a];
    rec.b = id_[b];
    rec.edge = -1;
    rec.point_m = {c.px, c.py};
    rec.normal = {c.nx, c.ny};
    rec.normal_impulse = c.pn;
    rec.tangent_impulse = c.pt;
    rec.vn_before = c.nx * dx0 + c.ny * dy0;
    rec.vn_after = c.nx * dx1 + c.ny * dy1;
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * wb_[a] - c.beta * wb_[b];
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * w_[a] - c.beta * w_[b];
    const auto lo = static_cast<std::uint64_t>(std::min(rec.a, rec.b));
    const auto hi = static_cast<std::uint64_t>(std::max(rec.a, rec.b));
    rec.key = (lo << 32) | hi;
    account_contact(accounting_, rec, omega, false);
    // The rolling couple's dissipation (no field of its own in the record).
    const double rolling_loss = -c.pr * 0.5 * ((wb_[a] - wb_[b]) + (w_[a] - w_[b]));
    accounting_.pp_tangent_J += rolling_loss;
    if (spectrum) {
      c.event_J += -c.pn * 0.5 * (rec.vn_before + rec.vn_after) -
                   c.pt * 0.5 * (rec.vt_before + rec.vt_after) + rolling_loss;
    }
  }
  for (Contact& c : pl_) {
    if (c.pn == 0.0 && c.pt == 0.0 && c.pr == 0.0) continue;
    const auto a = static_cast<std::size_t>(c.a);
    if (!act_[a]) continue;
    const double tx = -c.ny, ty = c.nx;
    const double dx0 = vbx_[a] - c.vlx, dy0 = vby_[a] - c.vly;
    const double dx1 = vx_[a] - c.vlx, dy1 = vy_[a] - c.vly;
    rec.a = id_[a];
    rec.b = -1;
    rec.edge = c.edge;
    rec.point_m = {c.px, c.py};
    rec.normal = {c.nx, c.ny};
    rec.normal_impulse = c.pn;
    rec.tangent_impulse = c.pt;
    rec.vn_before = c.nx * dx0 + c.ny * dy0;
    rec.vn_after = c.nx * dx1 + c.ny * dy1;
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * wb_[a];
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * w_[a];
    rec.key = (static_cast<std::uint64_t>(rec.a) << 32) | 0x80000000u | static_cast<std::uint32_t>(c.edge);
    account_contact(accounting_, rec, omega, edge_is_shell_[static_cast<std::size_t>(c.edge)] != 0);
    // Rolling couple against the liner: the drive supplies it at the mill's speed.
    accounting_.pl_tangent_J += -c.pr * (0.5 * (wb_[a] + w_[a]) - omega);
    accounting_.torque_impulse_Nms += c.pr;
    accounting_.drive_work_J += omega * c.pr;
  }
}

void SoftEngine::check_inside_liner() {
  // A disk whose centre got deeper into the lifter metal than the liner contact reaches
  // (half a radius) has leaked through.
  const int rows = mill_.rows;
  if (rows <= 0 || mill_.units.empty()) return;
  const double pitch_angle = 2.0 * kPi / rows;
  const double inner_sq = (radius_m_ - band_m_) * (radius_m_ - band_m_);
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!act_[k]) continue;
    const Vec2 p{x_[k], y_[k]};
    if (length_sq(p) < inner_sq) continue;
    const Vec2 pm = rotated(p, -state_.mill_angle_rad);
    const double theta = std::atan2(pm.y, pm.x);
    int row = static_cast<int>(std::lround(theta / pitch_angle));
    row = ((row % rows) + rows) % rows;
    const Vec2 local = mill_to_local(pm, row, rows, radius_m_);
    const Polyline& surf = mill_.units[mill_.units.size() == 1 ? 0 : static_cast<std::size_t>(row)].surface;
    for (std::size_t e = 0; e + 1 < surf.size(); ++e) {
      const Vec2 a = surf[e], b = surf[e + 1];
      if ((local.x - a.x) * (local.x - b.x) > 0.0 || a.x == b.x) continue;
      const double y_surface = a.y + (b.y - a.y) * (local.x - a.x) / (b.x - a.x);
      if (local.y < y_surface - 0.5 * r_[k]) {
        accounting_.escaped += 1;
        remove_disk(i, "leaked into the liner");
      }
      break;
    }
  }
}

void SoftEngine::finish() {
  const double g = kGravity;
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!act_[k]) continue;
    const auto id = static_cast<std::size_t>(id_[k]);
    if (!std::isfinite(x_[k]) || !std::isfinite(y_[k]) || !std::isfinite(vx_[k]) ||
        !std::isfinite(vy_[k]) || !std::isfinite(w_[k])) {
      accounting_.non_finite += 1;
      remove_disk(i, "went non-finite");
      continue;
    }
    // What the soft bias moved beyond x0 + dt v1 (the symplectic-Euler step with the final
    // velocity): its potential energy is the solver's share of the energy balance.
    const double corr_y = (y_[k] - y0_[k]) - dt_ * vy_[k];
    accounting_.solver_position_J -= mass_[k] * g * corr_y;
    state_.position_m[id] = {x_[k], y_[k]};
    state_.velocity_m_s[id] = {vx_[k], vy_[k]};
    state_.angle_rad[id] = ang_[k];
    state_.spin_rad_s[id] = w_[k];
    const double escape_r = max_r_m_ + 0.5 * r_[k];
    if (x_[k] * x_[k] + y_[k] * y_[k] > escape_r * escape_r) {
      accounting_.escaped += 1;
      remove_disk(i, "escaped through the shell");
    }
  }
}

void SoftEngine::step_once() {
  const auto t_start = Clock::now();
  const double g = kGravity;
  // 1. Margins, and what the step starts from.
  margin_max_ = 0.0;
  for (int i = 0; i < n_; ++i) {
    const auto k = static_cast<std::size_t>(i);
    x0_[k] = x_[k];
    y0_[k] = y_[k];
    vbx_[k] = vx_[k];
    vby_[k] = act_[k] ? vy_[k] - g * dt_ : vy_[k];
    wb_[k] = w_[k];
    dpx_[k] = 0.0;
    dpy_[k] = 0.0;
    if (!act_[k]) continue;
    const double speed = std::sqrt(vx_[k] * vx_[k] + vy_[k] * vy_[k]);
    marg_[k] = margin_base_m_ + 1.5 * (speed + g * dt_) * dt_;
    margin_max_ = std::max(margin_max_, marg_[k]);
  }
  // 2. Broad phase: every candidate pair lies within the 3x3 cells.
  grid_.build(x_.data(), y_.data(), act_.data(), n_, 2.0 * (r_max_ + margin_max_));
  if (accounting_.steps % kReorderInterval == 0 && n_ > 0) {
    reorder_by_cell();
    // Reordering moved the before-step copies too: rebuild them.
    for (int i = 0; i < n_; ++i) {
      const auto k = static_cast<std::size_t>(i);
      x0_[k] = x_[k];
      y0_[k] = y_[k];
      vbx_[k] = vx_[k];
      vby_[k] = act_[k] ? vy_[k] - g * dt_ : vy_[k];
      wb_[k] = w_[k];
    }
  }
  const auto t_broad = Clock::now();
  timing_.broad_s += std::chrono::duration<double>(t_broad - t_start).count();

  // 3. Narrow phase. The liner lookup is rebuilt (rarely) when a fast disk needs more reach.
  const double reach = r_max_ + margin_max_ + std::fabs(state_.mill_speed_rad_s) * max_r_m_ * dt_;
  if (reach > liner_.reach_m()) {
    liner_reach_need_ = 1.5 * reach;
    liner_.build(mill_, liner_reach_need_);
  }
  pp_old_.swap(pp_);
  pl_old_.swap(pl_);
  find_pairs();
  find_liner_contacts();
  warm_start_match();
  const auto t_narrow = Clock::now();
  timing_.collide_s += std::chrono::duration<double>(t_narrow - t_broad).count();

  // 4. Solve.
  solve();
  const auto t_solve = Clock::now();
  timing_.solve_s += std::chrono::duration<double>(t_solve - t_narrow).count();
  timing_.disk_steps += n_;

  // 5. Finish.
  finish();
  account_contacts();
  state_.time_s += dt_;
  state_.mill_angle_rad += state_.mill_speed_rad_s * dt_;
  if (accounting_.steps % 16 == 0) check_inside_liner();
  account_step(accounting_, state_, dt_, radius_m_, shape_band_m_ + band_m_, kGravity);
  accounting_.kinetic_J_end = charge_kinetic_J(state_);
  accounting_.potential_J_end = charge_potential_J(state_, kGravity);
  timing_.account_s += seconds_since(t_solve);
}

}  // namespace

std::unique_ptr<Engine> make_soft_engine(const Scene& scene, const MillGeometry& mill,
                                         const ChargeState& initial,
                                         const AccountingOptions& opts) {
  return std::make_unique<SoftEngine>(scene, mill, initial, opts);
}

}  // namespace millwear
