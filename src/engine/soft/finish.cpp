#include "engine/soft/finish.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "geometry/vec2.hpp"

namespace millwear::soft {

namespace {

void remove_disk(Disks& disks, int i, const std::string& why, Report& report) {
  const auto k = static_cast<std::size_t>(i);
  disks.active[k] = 0;
  disks.body[k].im = 0.0;
  disks.body[k].ii = 0.0;
  report.charge.active[static_cast<std::size_t>(disks.id[k])] = 0;
  report.events.push_back(
      {report.charge.time_s, "disk " + std::to_string(disks.id[k]) + " " + why});
}

}  // namespace

void write_back_and_check(const Model& model, const LinerModel& liner, const StepStart& start,
                          Disks& disks, Report report, FinishScratch& scratch,
                          Workers& workers) {
  constexpr std::size_t kPerRange = 1024;
  const double g = kGravity;
  ChargeState& charge = report.charge;
  Accounting& acc = report.accounting;
  const auto n = static_cast<std::size_t>(disks.n);
  const int ranges = range_count(n, kPerRange);
  scratch.position_J.resize(static_cast<std::size_t>(ranges));
  scratch.flagged.resize(static_cast<std::size_t>(ranges));
  scratch.verdict.resize(n);
  workers.run(ranges, [&](int r) {
    const std::size_t i0 = static_cast<std::size_t>(r) * kPerRange, i1 = std::min(n, i0 + kPerRange);
    double position_J = 0.0;
    std::uint8_t flagged = 0;
    for (std::size_t k = i0; k < i1; ++k) {
      scratch.verdict[k] = 0;
      if (!disks.active[k]) continue;
      const double x = disks.x[k], y = disks.y[k];
      const Body& b = disks.body[k];
      if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(b.vx) ||
          !std::isfinite(b.vy) || !std::isfinite(b.w)) {
        scratch.verdict[k] = 1;
        flagged = 1;
        continue;
      }
      // What the soft bias moved beyond x0 + dt v1 (the symplectic-Euler step with the
      // final velocity): its potential energy is the solver's share of the energy balance.
      const double corr_y = (y - start.y[k]) - model.dt_s * b.vy;
      position_J -= disks.mass[k] * g * corr_y;
      const double escape_r = liner.max_r_m + kLostDepthRadii * disks.radius[k];
      if (x * x + y * y > escape_r * escape_r) {
        scratch.verdict[k] = 2;
        flagged = 1;
      }
    }
    scratch.position_J[static_cast<std::size_t>(r)] = position_J;
    scratch.flagged[static_cast<std::size_t>(r)] = flagged;
  });
  // The state by id, in ranges of ids: each range writes a contiguous run of the charge's
  // arrays (written in the solver's order, the ranges would share cache lines at random).
  workers.run(ranges, [&](int r) {
    const std::size_t j0 = static_cast<std::size_t>(r) * kPerRange, j1 = std::min(n, j0 + kPerRange);
    for (std::size_t j = j0; j < j1; ++j) {
      const auto k = static_cast<std::size_t>(disks.slot[j]);
      if (!disks.active[k] || scratch.verdict[k] == 1) continue;
      const Body& b = disks.body[k];
      charge.position_m[j] = {disks.x[k], disks.y[k]};
      charge.velocity_m_s[j] = {b.vx, b.vy};
      charge.angle_rad[j] = disks.angle[k];
      charge.spin_rad_s[j] = b.w;
    }
  });
  for (int r = 0; r < ranges; ++r) {
    acc.solver_position_J += scratch.position_J[static_cast<std::size_t>(r)];
    if (!scratch.flagged[static_cast<std::size_t>(r)]) continue;
    const std::size_t i0 = static_cast<std::size_t>(r) * kPerRange, i1 = std::min(n, i0 + kPerRange);
    for (std::size_t k = i0; k < i1; ++k) {
      if (scratch.verdict[k] == 1) {
        acc.non_finite += 1;
        remove_disk(disks, static_cast<int>(k), "went non-finite", report);
      } else if (scratch.verdict[k] == 2) {
        acc.escaped += 1;
        remove_disk(disks, static_cast<int>(k), "escaped through the shell", report);
      }
    }
  }
}

void account_contacts(const LinerModel& liner, const Disks& disks, const StepStart& start,
                      double mill_speed_rad_s, Contacts& contacts, Accounting& accounting,
                      FinishScratch& scratch, Workers& workers) {
  constexpr std::size_t kPerRange = 2048;
  const double omega = mill_speed_rad_s;
  const bool spectrum = accounting.options.collision_spectrum;
  const Body* body = disks.body.data();
  const StartVelocity* v0 = start.v.data();
  PairSet& pairs = contacts.pairs;
  const int ranges = range_count(pairs.size(), kPerRange);
  if (scratch.pairs.size() < static_cast<std::size_t>(ranges))
    scratch.pairs.resize(static_cast<std::size_t>(ranges));
  workers.run(ranges, [&](int r) {
    FinishScratch::PairSums& part = scratch.pairs[static_cast<std::size_t>(r)];
    part.normal_J = part.tangent_J = 0.0;
    part.ended = 0;
    auto end_event = [&](double energy_J) {
      if (part.ended == part.ended_events.size()) part.ended_events.resize(2 * part.ended + 16);
      part.ended_events[part.ended++] = collision_event(energy_J);
    };
    const std::size_t q0 = static_cast<std::size_t>(r) * kPerRange;
    const std::size_t q1 = std::min(pairs.size(), q0 + kPerRange);
    // The rows that acted and those that did not, listed first: every row written to both
    // lists and counted in one (a third of the rows act, in no pattern a branch predictor
    // learns). An unbuilt row never acted (its sums are stale: zeroed when a row is built).
    if (part.acted.size() < kPerRange) {
      part.acted.resize(kPerRange);
      part.idle.resize(kPerRange);
    }
    std::uint32_t* acted = part.acted.data();
    std::uint32_t* idle = part.idle.data();
    std::size_t acted_n = 0, idle_n = 0;
    for (std::size_t q = q0; q < q1; ++q) {
      const StepSum& sum = pairs.sum[q];
      const bool nonzero = (sum.pn != 0.0) | (sum.pt != 0.0) | (sum.pr != 0.0);
      const std::size_t act = static_cast<std::size_t>((pairs.state[q] & kBuilt) != 0) & static_cast<std::size_t>(nonzero);
      acted[acted_n] = idle[idle_n] = static_cast<std::uint32_t>(q);
      acted_n += act;
      idle_n += act ^ 1;
    }
    // A collision's energy lives in its key only when the spectrum is asked for (it stays
    // zero otherwise, and the keys are not written here). A row apart all step ends the
    // collision that was going on.
    if (spectrum) {
      for (std::size_t t = 0; t < idle_n; ++t) {
        ContactKey& key = pairs.key[idle[t]];
        if (key.event_J > 0.0) end_event(key.event_J);
        key.event_J = 0.0;
      }
    }
    for (std::size_t t = 0; t < acted_n; ++t) {
      const std::size_t q = acted[t];
      const StepSum& sum = pairs.sum[q];
      ContactKey& key = pairs.key[q];
      const PairGap& g = pairs.gap[q];
      const auto a = static_cast<std::size_t>(g.a), b = static_cast<std::size_t>(g.b);
      if (!disks.active[a] || !disks.active[b]) continue;
      // The row's anchors, as build_pair_row computed them, from the bodies read here anyway
      // (the row itself stays unread).
      const double alpha = body[a].radius + 0.5 * g.s0, beta = body[b].radius + 0.5 * g.s0;
      const double tx = -g.ny, ty = g.nx;
      const double dx0 = v0[a].vx - v0[b].vx, dy0 = v0[a].vy - v0[b].vy;
      const double dx1 = body[a].vx - body[b].vx, dy1 = body[a].vy - body[b].vy;
      const double vn_before = g.nx * dx0 + g.ny * dy0;
      const double vn_after = g.nx * dx1 + g.ny * dy1;
      const double vt_before = tx * dx0 + ty * dy0 - alpha * v0[a].w - beta * v0[b].w;
      const double vt_after = tx * dx1 + ty * dy1 - alpha * body[a].w - beta * body[b].w;
      // What account_contact books for a disk pair (dissipation only), and the rolling
      // couple's dissipation (no field of its own in the record).
      const double normal_loss = -sum.pn * (0.5 * (vn_before + vn_after));
      const double tangent_loss = -sum.pt * (0.5 * (vt_before + vt_after));
      const double rolling_loss = -sum.pr * 0.5 * ((v0[a].w - v0[b].w) + (body[a].w - body[b].w));
      part.normal_J += normal_loss;
      part.tangent_J += tangent_loss;
      part.tangent_J += rolling_loss;
      if (spectrum) key.event_J += normal_loss + tangent_loss + rolling_loss;
    }
  });
  for (int r = 0; r < ranges; ++r) {
    const FinishScratch::PairSums& part = scratch.pairs[static_cast<std::size_t>(r)];
    accounting.pp_normal_J += part.normal_J;
    accounting.pp_tangent_J += part.tangent_J;
    for (std::size_t e = 0; e < part.ended; ++e) account_collision_event(accounting, part.ended_events[e]);
  }
  ContactRecord rec;
  const LinerSet& liner_contacts = contacts.liner;
  for (std::size_t q = 0; q < liner_contacts.size(); ++q) {
    const StepSum& sum = liner_contacts.sum[q];
    if (sum.pn == 0.0 && sum.pt == 0.0 && sum.pr == 0.0) continue;
    const LinerGap& g = liner_contacts.gap[q];
    const LinerRow& c = liner_contacts.row[q];
    const LinerInfo& info = liner_contacts.info[q];
    const auto a = static_cast<std::size_t>(g.a);
    if (!disks.active[a]) continue;
    const double tx = -g.ny, ty = g.nx;
    const double dx0 = v0[a].vx - g.vlx, dy0 = v0[a].vy - g.vly;
    const double dx1 = body[a].vx - g.vlx, dy1 = body[a].vy - g.vly;
    rec.a = disks.id[a];
    rec.b = -1;
    rec.edge = info.edge;
    rec.point_m = {info.px, info.py};
    rec.normal = {g.nx, g.ny};
    rec.normal_impulse = sum.pn;
    rec.tangent_impulse = sum.pt;
    rec.vn_before = g.nx * dx0 + g.ny * dy0;
    rec.vn_after = g.nx * dx1 + g.ny * dy1;
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * v0[a].w;
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * body[a].w;
    account_contact(accounting, rec, omega,
                    liner.edge_is_shell[static_cast<std::size_t>(info.edge)] != 0);
    // Rolling couple against the liner: the drive supplies it at the mill's speed.
    accounting.pl_tangent_J += -sum.pr * (0.5 * (v0[a].w + body[a].w) - omega);
    accounting.torque_impulse_Nms += sum.pr;
    accounting.drive_work_J += omega * sum.pr;
  }
}

void advance_clock(const Model& model, ChargeState& charge) {
  charge.time_s += model.dt_s;
  charge.mill_angle_rad += charge.mill_speed_rad_s * model.dt_s;
}

void check_inside_liner(const Model& model, const LinerModel& liner, Disks& disks,
                        Report report, FinishScratch& scratch, Workers& workers) {
  constexpr std::size_t kPerRange = 1024;
  const double inner = model.mill_radius_m - liner.band_m;
  const double inner_sq = inner * inner;
  const auto n = static_cast<std::size_t>(disks.n);
  const int ranges = range_count(n, kPerRange);
  scratch.flagged.resize(static_cast<std::size_t>(ranges));
  scratch.verdict.resize(n);
  // Which disks leaked, by ranges at once; then their removal in index order.
  workers.run(ranges, [&](int r) {
    const std::size_t i0 = static_cast<std::size_t>(r) * kPerRange, i1 = std::min(n, i0 + kPerRange);
    std::uint8_t flagged = 0;
    for (std::size_t k = i0; k < i1; ++k) {
      scratch.verdict[k] = 0;
      if (!disks.active[k]) continue;
      const Vec2 p{disks.x[k], disks.y[k]};
      if (length_sq(p) < inner_sq) continue;
      const Vec2 pm = rotated(p, -report.charge.mill_angle_rad);
      if (deeper_than_liner_surface(liner.mill, pm, kLostDepthRadii * disks.radius[k])) {
        scratch.verdict[k] = 1;
        flagged = 1;
      }
    }
    scratch.flagged[static_cast<std::size_t>(r)] = flagged;
  });
  for (int r = 0; r < ranges; ++r) {
    if (!scratch.flagged[static_cast<std::size_t>(r)]) continue;
    const std::size_t i0 = static_cast<std::size_t>(r) * kPerRange, i1 = std::min(n, i0 + kPerRange);
    for (std::size_t k = i0; k < i1; ++k) {
      if (!scratch.verdict[k]) continue;
      report.accounting.escaped += 1;
      remove_disk(disks, static_cast<int>(k), "leaked into the liner", report);
    }
  }
}

}  // namespace millwear::soft
