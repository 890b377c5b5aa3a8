// The soft backend: our own disk solver, derived from the method of Box2D v3 (soft step with
// substeps and relax, warm starting, restitution once per step) and specialised to a mill
// slice. No Box2D code is used; the method is written for disks from its description.
//
// The engine holds a model (model.hpp: the constants derived from the scene, the mill and
// the charge's sizes, built once; the liner, replaced by set_liner) and the data of one run
// (the disks in the solver's order, this and last step's contacts, the scratch of each
// stage). A step is the sequence of named stages in step_once, each in its own file:
//   broad_phase     margins, the reordering of the disks by cell, the pair-search grid;
//   narrow_phase    disk pairs, disk-liner contacts, the match against last step's;
//   contact_solver  per substep: gravity, warm start, soft solve and positions, relax
//                   (and the next substep's gravity); then restitution once (colour_solve:
//                   the live disk pairs in vector lanes);
//   finish          the state written back and checked, every contact accounted.
// Units are SI throughout (doubles); every tolerance is a fraction of the particle size.
#include "engine/soft/soft_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <vector>

#include "engine/soft/broad_phase.hpp"
#include "engine/soft/contact_set.hpp"
#include "engine/soft/contact_solver.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/finish.hpp"
#include "engine/soft/model.hpp"
#include "engine/soft/narrow_phase.hpp"
#include "engine/soft/workers.hpp"

namespace millwear::soft {

namespace {

// Wall-clock laps for the Timing of the benchmarks; read between stages, never inside one.
class Stopwatch {
 public:
  double lap() {
    const auto now = Clock::now();
    const double s = std::chrono::duration<double>(now - last_).count();
    last_ = now;
    return s;
  }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point last_ = Clock::now();
};

class SoftEngine final : public Engine {
 public:
  SoftEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
             const AccountingOptions& opts);

  void set_liner(const MillGeometry& mill) override;
  void set_mill_speed(double omega_rad_s) override { charge_.mill_speed_rad_s = omega_rad_s; }
  void step(int n) override;
  const ChargeState& state() const override { return charge_; }
  double time_step_s() const override { return model_.dt_s; }
  const char* backend_name() const override { return "soft"; }

 private:
  void step_once();
  void count_rows();
  void account_shape();
  Report report() { return {charge_, accounting_, events_}; }

  // Model: fixed for the engine's life, and the liner (set_liner).
  const Model model_;
  LinerModel liner_;
  // Data of the run.
  ChargeState charge_;  // by the caller's ids: what state() hands out, written every step
  Disks disks_;         // the solver's copy, in cell order
  StepStart start_;
  Contacts contacts_;
  // Scratch of the stages.
  BroadPhase broad_;
  PairSearch pair_search_;
  LinerSearch liner_search_;
  SolverRows rows_;
  MatchScratch match_;
  FinishScratch finish_;
  std::vector<ShapeSample> shape_;  // per disk range of the shape sample
  Workers workers_;
};

SoftEngine::SoftEngine(const Scene& scene, const MillGeometry& mill, const ChargeState& initial,
                       const AccountingOptions& opts)
    : model_(build_model(scene, mill, initial)),
      charge_(initial),
      disks_(load_disks(initial)),
      start_(make_step_start(disks_.n)),
      workers_(step_thread_count(scene.solver, initial.size())) {
  accounting_.options = opts;
  broad_.reserve(disks_.n);
  contacts_.reserve(disks_.n);
  pair_search_.reserve(disks_.n);
  set_liner(mill);
  reset_window();
}

void SoftEngine::set_liner(const MillGeometry& mill) {
  liner_ = build_liner_model(mill);
  build_liner_search(model_, liner_, liner_search_);
  edge_count_ = mill.boundary.size();
  reset_accounting(accounting_, edge_count_);
  // Edge ids changed: liner contacts start cold.
  contacts_.liner.clear();
  contacts_.liner_old.clear();
}

void SoftEngine::step(int n) {
  if (n <= 0) return;
  for (int k = 0; k < n; ++k) step_once();
  // The window's end energies: only the last step's count, so they are taken once here
  // rather than after every step (two passes over the charge saved per step).
  Stopwatch watch;
  accounting_.kinetic_J_end = charge_kinetic_J(charge_);
  accounting_.potential_J_end = charge_potential_J(charge_, kGravity);
  timing_.account_s += watch.lap();
}

void SoftEngine::step_once() {
  const double omega = charge_.mill_speed_rad_s;
  Stopwatch watch;

  contacts_.begin_step();
  const StepBounds bounds = update_margins(model_, disks_, broad_, workers_);
  if (reorder_due(accounting_.steps, disks_))
    reorder_by_cell(model_, liner_, bounds, broad_, disks_, contacts_);
  record_step_start(disks_, start_, workers_);
  build_pair_grid(model_, bounds, disks_, broad_, workers_);
  timing_.broad_s += watch.lap();

  fit_liner_search(model_, liner_, bounds, omega, liner_search_);
  find_pairs(model_, disks_, broad_.pair_grid, bounds, pair_search_, contacts_.pairs, workers_);
  find_liner_contacts(model_, liner_, liner_search_, disks_, charge_.mill_angle_rad, omega,
                      contacts_.liner, workers_);
  match_warm_start(contacts_, accounting_, match_, workers_);
  timing_.collide_s += watch.lap();

  const double h = model_.substep_s;
  colour_live_rows(model_, disks_, start_, broad_.block_disks, contacts_, rows_, workers_);
  integrate_velocities(model_, disks_, workers_);
  for (int sub = 0; sub < model_.substeps; ++sub) {
    const bool gravity_next = sub + 1 < model_.substeps;
    warm_start(contacts_, rows_, disks_, workers_);
    solve_and_integrate_positions(model_, start_, sub * h, omega, contacts_, rows_, disks_, workers_);
    relax(model_, start_, (sub + 1) * h, omega, gravity_next, contacts_, rows_, disks_, workers_);
  }
  store_lanes(rows_, contacts_.pairs, workers_);
  apply_restitution(model_, contacts_, rows_, disks_, workers_);
  timing_.solve_s += watch.lap();
  count_rows();

  write_back_and_check(model_, liner_, start_, disks_, report(), finish_, workers_);
  account_contacts(liner_, disks_, start_, omega, contacts_, accounting_, finish_, workers_);
  advance_clock(model_, charge_);
  if (inside_liner_check_due(accounting_.steps))
    check_inside_liner(model_, liner_, disks_, report(), finish_, workers_);
  account_shape();
  timing_.account_s += watch.lap();
}

// The step's clock and charge-shape sample, by disk ranges at once (added in range order).
void SoftEngine::account_shape() {
  const std::size_t n = charge_.size();
  const int ranges = accounting_.options.charge_shape ? std::max(1, range_count(n, kDisksPerRange)) : 0;
  shape_.resize(static_cast<std::size_t>(ranges));
  const double band_m = model_.shape_band_m + liner_.band_m;
  workers_.run(ranges, [&](int r) {
    const std::size_t i0 = static_cast<std::size_t>(r) * kDisksPerRange;
    shape_sample(charge_, i0, std::min(n, i0 + kDisksPerRange), model_.dt_s, model_.mill_radius_m, band_m,
                 shape_[static_cast<std::size_t>(r)]);
  });
  account_step_samples(accounting_, charge_, model_.dt_s, shape_.data(), shape_.size());
}

// Rows per disk-step for the benchmarks: whether a cost per disk-step grows with the work.
void SoftEngine::count_rows() {
  timing_.disk_steps += disks_.n;
  timing_.pair_rows += static_cast<std::int64_t>(contacts_.pairs.size());
  timing_.live_pair_rows += static_cast<std::int64_t>(rows_.live_n);
  timing_.liner_rows += static_cast<std::int64_t>(contacts_.liner.size());
}

}  // namespace

}  // namespace millwear::soft

namespace millwear {

std::unique_ptr<Engine> make_soft_engine(const Scene& scene, const MillGeometry& mill,
                                         const ChargeState& initial,
                                         const AccountingOptions& opts) {
  return std::make_unique<soft::SoftEngine>(scene, mill, initial, opts);
}

}  // namespace millwear
