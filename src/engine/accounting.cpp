// Shared contact accounting. Energies come from impulse * mean velocity over the solve:
// for the velocity solve of one step, sum over contacts of P . (v_before + v_after)/2 is
// exactly the kinetic-energy change the impulses cause, so -P . v_rel_mean is the energy a
// contact dissipates, and P . v_liner is the work the drive does through it.
#include "common/units.hpp"
#include "engine/accounting.hpp"

#include <algorithm>
#include <cmath>

namespace millwear {

void reset_accounting(Accounting& acc, std::size_t edge_count) {
  AccountingOptions opts = acc.options;
  std::vector<ContactRecord> log = std::move(acc.contact_log);
  LinerStreaks streaks = std::move(acc.streaks);
  acc = Accounting{};
  acc.options = opts;
  acc.streaks = std::move(streaks);
  if (opts.contact_log) {
    log.clear();
    log.reserve(opts.contact_log_limit);
    acc.contact_log = std::move(log);
  }
  if (opts.per_edge) {
    acc.shear_work_J.assign(edge_count, 0.0);
    acc.impact_energy_J.assign(edge_count, 0.0);
    acc.contacts.assign(edge_count, 0u);
  }
}

namespace {

// Books disk id's liner contact at point_m (world) in this step into its streak; true when
// the disk has been in liner contact at every step for more than one revolution with the
// contact within 45 deg of where the run began, in the mill frame. A disk's first liner
// contact of a step counts one packed disk-step. The arrays grow only when a larger id
// first touches the liner.
bool liner_contact_packed(LinerStreaks& st, int id, Vec2 point_m, double mill_speed_rad_s,
                          std::int64_t& packed_disk_steps) {
  if (id < 0) return false;
  const auto k = static_cast<std::size_t>(id);
  if (k >= st.last_step.size()) {
    st.last_step.resize(k + 1, -2);
    st.since_s.resize(k + 1, 0.0);
    st.since_dir.resize(k + 1, Vec2{});
  }
  const bool first_this_step = st.last_step[k] != st.step;
  if (first_this_step) {
    // The contact's direction from the axis in the mill frame (cos/sin kept per step).
    const Vec2 dir = normalized({st.cos_mill * point_m.x + st.sin_mill * point_m.y,
                                 -st.sin_mill * point_m.x + st.cos_mill * point_m.y});
    constexpr double kCos45 = 0.70710678118654752;
    if (st.last_step[k] != st.step - 1 || dot(dir, st.since_dir[k]) < kCos45) {
      st.since_s[k] = st.clock_s;
      st.since_dir[k] = dir;
    }
    st.last_step[k] = st.step;
  }
  const double omega = std::fabs(mill_speed_rad_s);
  const bool packed = omega > 0.0 && (st.clock_s - st.since_s[k]) * omega > 2.0 * kPi;
  if (packed && first_this_step) packed_disk_steps += 1;
  return packed;
}

}  // namespace

void account_contact(Accounting& acc, const ContactRecord& c, double mill_speed_rad_s,
                     bool edge_is_shell) {
  const double vn_mean = 0.5 * (c.vn_before + c.vn_after);
  const double vt_mean = 0.5 * (c.vt_before + c.vt_after);
  const double normal_loss = -c.normal_impulse * vn_mean;
  const double tangent_loss = -c.tangent_impulse * vt_mean;
  if (c.b >= 0) {
    acc.pp_normal_J += normal_loss;
    acc.pp_tangent_J += tangent_loss;
    return;
  }
  acc.pl_normal_J += normal_loss;
  acc.pl_tangent_J += tangent_loss;
  const bool packed = liner_contact_packed(acc.streaks, c.a, c.point_m, mill_speed_rad_s, acc.packed_disk_steps);
  if (acc.options.contact_log) {
    if (acc.contact_log.size() < acc.options.contact_log_limit) {
      acc.contact_log.push_back(c);
      acc.contact_log.back().step = acc.steps;
    } else if (acc.contact_log_time_s == 0.0) {
      acc.contact_log_time_s = acc.time_s;
    }
  }
  // Impulse on the disk; the drive supplies the opposite torque to hold the mill's speed.
  const Vec2 tangent = left_perp(c.normal);
  const Vec2 impulse = c.normal_impulse * c.normal + c.tangent_impulse * tangent;
  const double torque_impulse = cross(c.point_m, impulse);
  acc.torque_impulse_Nms += torque_impulse;
  acc.drive_work_J += mill_speed_rad_s * torque_impulse;
  if (acc.options.per_edge && c.edge >= 0 && (acc.options.shell_work || !edge_is_shell)) {
    const auto e = static_cast<std::size_t>(c.edge);
    // Archard's dw: friction force times slip distance. Positions advance with the
    // post-solve velocity, so the distance slid in the step is vt_after * dt; a sticking
    // contact (vt_after = 0) does no shear work even though gravity moved it in between.
    const double shear = std::fabs(c.tangent_impulse * c.vt_after);
    if (packed) acc.packed_shear_work_J += shear;
    if (!packed || acc.options.packed_wear) acc.shear_work_J[e] += shear;
    acc.impact_energy_J[e] += normal_loss;
    acc.contacts[e] += 1u;
  }
}

int spectrum_bin(double energy_J) {
  if (!(energy_J > kSpectrumMinJ)) return 0;
  int bin = static_cast<int>(std::floor(std::log10(energy_J / kSpectrumMinJ) * kSpectrumBinsPerDecade));
  return std::clamp(bin, 0, kSpectrumBins - 1);
}

double spectrum_bin_lower_J(int bin) {
  return kSpectrumMinJ * std::pow(10.0, bin / kSpectrumBinsPerDecade);
}

CollisionEvent collision_event(double energy_J) {
  return {energy_J, energy_J > 0.0 ? spectrum_bin(energy_J) : -1};
}

void account_collision_event(Accounting& acc, const CollisionEvent& event) {
  if (event.bin < 0) return;
  const auto bin = static_cast<std::size_t>(event.bin);
  acc.spectrum_count[bin] += 1.0;
  acc.spectrum_energy_J[bin] += event.energy_J;
}

void account_collision_event(Accounting& acc, double energy_J) {
  account_collision_event(acc, collision_event(energy_J));
}

void shape_sample(const ChargeState& s, std::size_t i0, std::size_t i1, double dt_s, double radius_m, double band_m,
                  ShapeSample& out) {
  double mass = 0.0;
  Vec2 moment;
  const double band_inner = radius_m - band_m;
  const double band_inner_sq = band_inner * band_inner;
  const double bins_per_rad = kShapeAngleBins / (2.0 * kPi);
  out.occupancy.fill(0.0);
  for (std::size_t i = i0; i < i1; ++i) {
    if (!s.active[i]) continue;
    const double m = s.mass_kg[i];
    const Vec2 p = s.position_m[i];
    mass += m;
    moment += m * p;
    if (length_sq(p) > band_inner_sq) {
      // Angle from 6 o'clock, + counter-clockwise (toward +x at the bottom).
      double phi = std::atan2(p.x, -p.y);
      if (phi < 0) phi += 2.0 * kPi;
      int bin = static_cast<int>(phi * bins_per_rad);
      if (bin >= kShapeAngleBins) bin = kShapeAngleBins - 1;
      out.occupancy[static_cast<std::size_t>(bin)] += s.radius_m[i] * s.radius_m[i] * dt_s;
    }
  }
  out.mass_kg = mass;
  out.moment_kg_m = moment;
}

void account_step_samples(Accounting& acc, const ChargeState& s, double dt_s, const ShapeSample* samples,
                          std::size_t count) {
  acc.time_s += dt_s;
  acc.steps += 1;
  acc.streaks.step += 1;
  acc.streaks.clock_s += dt_s;
  // The engine has turned the mill for this step: the next step's contacts start here.
  acc.streaks.cos_mill = std::cos(s.mill_angle_rad);
  acc.streaks.sin_mill = std::sin(s.mill_angle_rad);
  if (!acc.options.charge_shape) return;
  double mass = 0.0;
  Vec2 moment;
  for (std::size_t r = 0; r < count; ++r) {
    mass += samples[r].mass_kg;
    moment += samples[r].moment_kg_m;
    for (int b = 0; b < kShapeAngleBins; ++b)
      acc.shell_band_occupancy[static_cast<std::size_t>(b)] += samples[r].occupancy[static_cast<std::size_t>(b)];
  }
  acc.mass_time_kg_s += mass * dt_s;
  acc.moment_time_kg_m_s += dt_s * moment;
  acc.shape_time_s += dt_s;
}

void account_step(Accounting& acc, const ChargeState& s, double dt_s, double radius_m,
                  double band_m) {
  ShapeSample sample;
  if (acc.options.charge_shape) shape_sample(s, 0, s.size(), dt_s, radius_m, band_m, sample);
  account_step_samples(acc, s, dt_s, &sample, 1);
}

}  // namespace millwear
