#include "engine/soft/finish.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/units.hpp"
#include "geometry/vec2.hpp"

namespace millwear::soft {

namespace {

// A liner face contact keeps working while a disk's centre is up to half a radius past the
// face line (liner_lookup.hpp): deeper than that, or as far past the farthest liner point,
// the disk is lost to the liner.
constexpr double kLostDepthRadii = 0.5;
// Liner contacts' accounting keys: the disk above, this bit and the edge below, so that
// they never meet a disk pair's key.
constexpr std::uint64_t kLinerKeyBit = 0x80000000u;

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
                          Disks& disks, Report report) {
  const double g = kGravity;
  ChargeState& charge = report.charge;
  Accounting& acc = report.accounting;
  for (int i = 0; i < disks.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!disks.active[k]) continue;
    const auto id = static_cast<std::size_t>(disks.id[k]);
    const double x = disks.x[k], y = disks.y[k];
    const Body& b = disks.body[k];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(b.vx) || !std::isfinite(b.vy) ||
        !std::isfinite(b.w)) {
      acc.non_finite += 1;
      remove_disk(disks, i, "went non-finite", report);
      continue;
    }
    // What the soft bias moved beyond x0 + dt v1 (the symplectic-Euler step with the final
    // velocity): its potential energy is the solver's share of the energy balance.
    const double corr_y = (y - start.y[k]) - model.dt_s * b.vy;
    acc.solver_position_J -= disks.mass[k] * g * corr_y;
    charge.position_m[id] = {x, y};
    charge.velocity_m_s[id] = {b.vx, b.vy};
    charge.angle_rad[id] = disks.angle[k];
    charge.spin_rad_s[id] = b.w;
    const double escape_r = liner.max_r_m + kLostDepthRadii * disks.radius[k];
    if (x * x + y * y > escape_r * escape_r) {
      acc.escaped += 1;
      remove_disk(disks, i, "escaped through the shell", report);
    }
  }
}

void account_contacts(const LinerModel& liner, const Disks& disks, const StepStart& start,
                      double mill_speed_rad_s, Contacts& contacts, Accounting& accounting) {
  const double omega = mill_speed_rad_s;
  const bool spectrum = accounting.options.collision_spectrum;
  const Body* body = disks.body.data();
  const double* vx0 = start.vx.data();
  const double* vy0 = start.vy_before.data();
  const double* w0 = start.w.data();
  ContactRecord rec;
  PairSet& pairs = contacts.pairs;
  for (std::size_t q = 0; q < pairs.size(); ++q) {
    const StepSum& sum = pairs.sum[q];
    ContactKey& key = pairs.key[q];
    // An unbuilt row never acted: its sums are zero.
    if (!(pairs.state[q] & kBuilt) || (sum.pn == 0.0 && sum.pt == 0.0 && sum.pr == 0.0)) {
      // Apart all step: a collision that was going on has ended.
      if (spectrum && key.event_J > 0.0) account_collision_event(accounting, key.event_J);
      key.event_J = 0.0;
      continue;
    }
    const ContactInfo& info = pairs.info[q];
    const PairGap& g = pairs.gap[q];
    const PairRow& c = pairs.row[q];
    const auto a = static_cast<std::size_t>(g.a), b = static_cast<std::size_t>(g.b);
    if (!disks.active[a] || !disks.active[b]) continue;
    const double tx = -g.ny, ty = g.nx;
    const double dx0 = vx0[a] - vx0[b], dy0 = vy0[a] - vy0[b];
    const double dx1 = body[a].vx - body[b].vx, dy1 = body[a].vy - body[b].vy;
    rec.a = disks.id[a];
    rec.b = disks.id[b];
    rec.edge = -1;
    rec.point_m = {info.px, info.py};
    rec.normal = {g.nx, g.ny};
    rec.normal_impulse = sum.pn;
    rec.tangent_impulse = sum.pt;
    rec.vn_before = g.nx * dx0 + g.ny * dy0;
    rec.vn_after = g.nx * dx1 + g.ny * dy1;
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * w0[a] - c.beta * w0[b];
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * body[a].w - c.beta * body[b].w;
    // The accounting's key is by the caller's ids, which the reordering does not change.
    rec.key = pair_key(std::min(rec.a, rec.b), std::max(rec.a, rec.b));
    account_contact(accounting, rec, omega, false);
    // The rolling couple's dissipation (no field of its own in the record).
    const double rolling_loss = -sum.pr * 0.5 * ((w0[a] - w0[b]) + (body[a].w - body[b].w));
    accounting.pp_tangent_J += rolling_loss;
    if (spectrum) {
      key.event_J += -sum.pn * 0.5 * (rec.vn_before + rec.vn_after) -
                     sum.pt * 0.5 * (rec.vt_before + rec.vt_after) + rolling_loss;
    }
  }
  const LinerSet& liner_contacts = contacts.liner;
  for (std::size_t q = 0; q < liner_contacts.size(); ++q) {
    const StepSum& sum = liner_contacts.sum[q];
    if (sum.pn == 0.0 && sum.pt == 0.0 && sum.pr == 0.0) continue;
    const LinerGap& g = liner_contacts.gap[q];
    const LinerRow& c = liner_contacts.row[q];
    const ContactInfo& info = liner_contacts.info[q];
    const auto a = static_cast<std::size_t>(g.a);
    if (!disks.active[a]) continue;
    const double tx = -g.ny, ty = g.nx;
    const double dx0 = vx0[a] - g.vlx, dy0 = vy0[a] - g.vly;
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
    rec.vt_before = tx * dx0 + ty * dy0 - c.alpha * w0[a];
    rec.vt_after = tx * dx1 + ty * dy1 - c.alpha * body[a].w;
    rec.key = (static_cast<std::uint64_t>(rec.a) << 32) | kLinerKeyBit |
              static_cast<std::uint32_t>(info.edge);
    account_contact(accounting, rec, omega,
                    liner.edge_is_shell[static_cast<std::size_t>(info.edge)] != 0);
    // Rolling couple against the liner: the drive supplies it at the mill's speed.
    accounting.pl_tangent_J += -sum.pr * (0.5 * (w0[a] + body[a].w) - omega);
    accounting.torque_impulse_Nms += sum.pr;
    accounting.drive_work_J += omega * sum.pr;
  }
}

void advance_clock(const Model& model, ChargeState& charge) {
  charge.time_s += model.dt_s;
  charge.mill_angle_rad += charge.mill_speed_rad_s * model.dt_s;
}

void check_inside_liner(const Model& model, const LinerModel& liner, Disks& disks,
                        Report report) {
  const MillGeometry& mill = liner.mill;
  const int rows = mill.rows;
  if (rows <= 0 || mill.units.empty()) return;
  const double radius = model.mill_radius_m;
  const double pitch_angle = 2.0 * kPi / rows;
  const double inner = radius - liner.band_m;
  const double inner_sq = inner * inner;
  for (int i = 0; i < disks.n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (!disks.active[k]) continue;
    const Vec2 p{disks.x[k], disks.y[k]};
    if (length_sq(p) < inner_sq) continue;
    const Vec2 pm = rotated(p, -report.charge.mill_angle_rad);
    const double theta = std::atan2(pm.y, pm.x);
    int row = static_cast<int>(std::lround(theta / pitch_angle));
    row = ((row % rows) + rows) % rows;
    const Vec2 local = mill_to_local(pm, row, rows, radius);
    const auto unit = mill.unit_of_row(row);
    const Polyline& surf = mill.units[unit].surface;
    for (std::size_t e = 0; e + 1 < surf.size(); ++e) {
      const Vec2 a = surf[e], b = surf[e + 1];
      if ((local.x - a.x) * (local.x - b.x) > 0.0 || a.x == b.x) continue;
      const double y_surface = a.y + (b.y - a.y) * (local.x - a.x) / (b.x - a.x);
      if (local.y < y_surface - kLostDepthRadii * disks.radius[k]) {
        report.accounting.escaped += 1;
        remove_disk(disks, i, "leaked into the liner", report);
      }
      break;
    }
  }
}

}  // namespace millwear::soft
