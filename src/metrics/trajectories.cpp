// Flights of the charge from its frames (see trajectories.hpp for the definitions).
#include "metrics/trajectories.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/units.hpp"

namespace millwear {

namespace {

double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double l2 = length_sq(ab);
  const double t = l2 > 0.0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return length(p - (a + t * ab));
}

// Angle bin of a mill-frame angle in [-pi, pi], `bins` bins from -pi.
int angle_bin(double t_rad, int bins) {
  const int k = static_cast<int>(std::floor((t_rad + kPi) / (2.0 * kPi) * bins));
  return ((k % bins) + bins) % bins;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

}  // namespace

double angle_from_bottom_deg(Vec2 world, double mill_speed_rad_s) {
  const double dir = mill_speed_rad_s < 0.0 ? -1.0 : 1.0;
  // Counter-clockwise from 6 o'clock is toward +x at the bottom.
  return dir * deg_from_rad(std::atan2(world.x, -world.y));
}

bool above_toe(double angle_deg, double toe_deg, double shoulder_deg) {
  return angle_deg < toe_deg || angle_deg > shoulder_deg;
}

FlightTracker::FlightTracker(const Polygon& liner, const ChargeState& first, const FlightOptions& options)
    : options_(options), liner_(liner) {
  const std::size_t n = first.size();
  double r_max = 0.0;
  for (std::size_t i = 0; i < n; ++i) r_max = std::max(r_max, first.radius_m[i]);
  reach_m_ = (1.0 + options_.touch_gap) * r_max;
  const std::size_t edges = liner_.size();
  inner_m_ = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < edges; ++k)
    inner_m_ = std::min(inner_m_, segment_distance({0.0, 0.0}, liner_[k], liner_[(k + 1) % edges]));
  // A point within reach of a liner point x (|x| >= inner, so the point's own radius is at
  // least inner - reach) lies within asin(reach / (inner - reach)) of its angle, so each edge
  // goes into every bin its angular span, widened by that, touches.
  // Bins about reach / inner wide keep a handful of edges each. A liner that is no ring round
  // the axis with room to spare (a test's box) gets one bin of every edge.
  const bool binned = edges >= 16 && inner_m_ > 2.0 * reach_m_ && reach_m_ > 0.0;
  bins_ = binned ? std::clamp(static_cast<int>(std::ceil(2.0 * kPi * inner_m_ / reach_m_)), 16, 100000) : 1;
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(bins_));
  const double spread = binned ? std::asin(std::min(1.0, reach_m_ / (inner_m_ - reach_m_))) : 0.0;
  for (std::size_t k = 0; k < edges; ++k) {
    if (!binned) {
      lists[0].push_back(static_cast<int>(k));
      continue;
    }
    const Vec2 a = liner_[k], b = liner_[(k + 1) % edges];
    double t0 = std::atan2(a.y, a.x);
    double t1 = t0 + std::remainder(std::atan2(b.y, b.x) - t0, 2.0 * kPi);
    if (t1 < t0) std::swap(t0, t1);
    // A slack of 1e-9 rad against bin borders (far above the rounding of the angles).
    const int lo = static_cast<int>(std::floor((t0 - spread - 1e-9 + kPi) / (2.0 * kPi) * bins_));
    const int hi = static_cast<int>(std::floor((t1 + spread + 1e-9 + kPi) / (2.0 * kPi) * bins_));
    for (int q = lo; q <= hi && q < lo + bins_; ++q)
      lists[static_cast<std::size_t>(((q % bins_) + bins_) % bins_)].push_back(static_cast<int>(k));
  }
  bin_start_.assign(static_cast<std::size_t>(bins_) + 1, 0);
  for (int q = 0; q < bins_; ++q) {
    const auto& l = lists[static_cast<std::size_t>(q)];
    bin_start_[static_cast<std::size_t>(q) + 1] = bin_start_[static_cast<std::size_t>(q)] + static_cast<int>(l.size());
    bin_edges_.insert(bin_edges_.end(), l.begin(), l.end());
  }

  phase_.assign(n, Phase::Unknown);
  prev_position_ = first.position_m;
  prev_velocity_ = first.velocity_m_s;
  prev_time_s_ = first.time_s;
  prev_mill_angle_rad_ = first.mill_angle_rad;
  prev_mill_speed_ = first.mill_speed_rad_s;
  launch_m_.assign(n, Vec2{});
  counted_.assign(n, 0);
  flying_path_.assign(n, FlightPath{});
  path_last_s_.assign(n, 0.0);
}

double FlightTracker::liner_distance(Vec2 q) const {
  const double r = length(q);
  if (bins_ > 1 && r < inner_m_ - reach_m_) return inner_m_ - r;  // no edge within reach
  const int bin = bins_ > 1 ? angle_bin(std::atan2(q.y, q.x), bins_) : 0;
  const std::size_t n = liner_.size();
  double d = std::numeric_limits<double>::infinity();
  for (int t = bin_start_[static_cast<std::size_t>(bin)]; t < bin_start_[static_cast<std::size_t>(bin) + 1]; ++t) {
    const auto k = static_cast<std::size_t>(bin_edges_[static_cast<std::size_t>(t)]);
    d = std::min(d, segment_distance(q, liner_[k], liner_[(k + 1) % n]));
  }
  return d;
}

bool FlightTracker::touches_liner(Vec2 world, double mill_angle_rad, double radius_m) const {
  return liner_distance(rotated(world, -mill_angle_rad)) <= (1.0 + options_.touch_gap) * radius_m;
}

void FlightTracker::observe(const ChargeState& frame) {
  const double dt = frame.time_s - prev_time_s_;
  if (!(dt > 0.0)) return;
  const double gdt = options_.gravity_m_s2 * dt;
  const double tol = options_.free_tolerance * gdt;
  const std::size_t n = std::min(frame.size(), phase_.size());
  for (std::size_t i = 0; i < n; ++i) {
    if (!frame.active[i]) {
      phase_[i] = Phase::Unknown;  // a lost disk's flight is dropped (the run reports the loss)
      flying_path_[i].points_m.clear();
      continue;
    }
    const Vec2 v = frame.velocity_m_s[i];
    const bool free = std::fabs(v.x - prev_velocity_[i].x) <= tol &&
                      std::fabs(v.y - prev_velocity_[i].y + gdt) <= tol;
    switch (phase_[i]) {
      case Phase::Unknown:
        phase_[i] = free ? Phase::Hop : Phase::Bound;
        break;
      case Phase::Bound:
        if (free) start_flight(i, frame);
        break;
      case Phase::Flying:
        if (free) {
          count_flight(i, frame.position_m[i], frame.radius_m[i]);
          FlightPath& path = flying_path_[i];
          if (!path.points_m.empty() && frame.time_s - path_last_s_[i] >= options_.path_interval_s) {
            path.points_m.push_back(frame.position_m[i]);
            path_last_s_[i] = frame.time_s;
          }
        } else {
          end_flight(i, frame);
        }
        break;
      case Phase::Hop:
        if (!free) phase_[i] = Phase::Bound;
        break;
    }
    prev_position_[i] = frame.position_m[i];
    prev_velocity_[i] = v;
  }
  prev_time_s_ = frame.time_s;
  prev_mill_angle_rad_ = frame.mill_angle_rad;
  prev_mill_speed_ = frame.mill_speed_rad_s;
}

// The disk was in contact up to the previous frame and flies since: a flight from the lifters
// if it left the liner there on the rising side.
void FlightTracker::start_flight(std::size_t i, const ChargeState& frame) {
  const Vec2 p0 = prev_position_[i];
  const double a0 = angle_from_bottom_deg(p0, prev_mill_speed_);
  if (!(a0 > 0.0 && a0 < 180.0) || !touches_liner(p0, prev_mill_angle_rad_, frame.radius_m[i])) {
    phase_[i] = Phase::Hop;
    return;
  }
  phase_[i] = Phase::Flying;
  counted_[i] = 0;
  launch_m_[i] = p0;
  FlightPath& path = flying_path_[i];
  path.points_m.clear();
  if (prev_time_s_ >= options_.path_from_s && prev_time_s_ <= options_.path_to_s &&
      paths_.size() < options_.max_paths) {
    path.disk = static_cast<int>(i);
    path.species = frame.species[i];
    path.landed = false;
    path.points_m = {p0, frame.position_m[i]};
    path_last_s_[i] = frame.time_s;
  }
  count_flight(i, frame.position_m[i], frame.radius_m[i]);
}

// A flight counts once the disk is a diameter away from where it left the liner.
void FlightTracker::count_flight(std::size_t i, Vec2 now, double radius_m) {
  if (counted_[i] || length(now - launch_m_[i]) < 2.0 * radius_m) return;
  counted_[i] = 1;
  ++launches_;
}

// The disk flew up to the previous frame and is in contact now: its first impact.
void FlightTracker::end_flight(std::size_t i, const ChargeState& frame) {
  phase_[i] = Phase::Bound;
  FlightPath& path = flying_path_[i];
  if (!counted_[i]) {  // chatter on the liner, not a flight
    path.points_m.clear();
    return;
  }
  Impact m;
  m.disk = static_cast<int>(i);
  m.species = frame.species[i];
  m.batch = batch_;
  m.launch_m = launch_m_[i];
  m.point_m = prev_position_[i];
  m.launch_deg = angle_from_bottom_deg(m.launch_m, prev_mill_speed_);
  m.angle_deg = angle_from_bottom_deg(m.point_m, prev_mill_speed_);
  // The mill frame's velocity at the point: omega x p.
  const Vec2 v_mill = prev_mill_speed_ * left_perp(m.point_m);
  m.energy_J = 0.5 * frame.mass_kg[i] * length_sq(prev_velocity_[i] - v_mill);
  m.on_liner = touches_liner(frame.position_m[i], frame.mill_angle_rad, frame.radius_m[i]);
  impacts_.push_back(m);
  if (!path.points_m.empty()) {
    if (!(path.points_m.back() == m.point_m)) path.points_m.push_back(m.point_m);
    path.landed = true;
    if (paths_.size() < options_.max_paths) paths_.push_back(std::move(path));
    path = FlightPath{};
  }
}

std::vector<FlightPath> FlightTracker::paths() const {
  std::vector<FlightPath> out = paths_;
  for (std::size_t i = 0; i < flying_path_.size(); ++i)
    if (phase_[i] == Phase::Flying && counted_[i] && !flying_path_[i].points_m.empty()) {
      out.push_back(flying_path_[i]);  // up to the disk where it is now
      if (!(out.back().points_m.back() == prev_position_[i])) out.back().points_m.push_back(prev_position_[i]);
    }
  return out;
}

ImpactDistribution bin_impacts(const std::vector<Impact>& impacts, int species_count) {
  ImpactDistribution d;
  const auto bins = static_cast<std::size_t>(kImpactBins);
  d.count.assign(bins, 0.0);
  d.energy_J.assign(bins, 0.0);
  d.liner_energy_J.assign(bins, 0.0);
  d.species_count.assign(static_cast<std::size_t>(std::max(species_count, 0)), std::vector<double>(bins, 0.0));
  d.species_energy_J = d.species_count;
  for (const Impact& m : impacts) {
    const auto k = static_cast<std::size_t>(
        std::clamp(static_cast<int>(std::floor((m.angle_deg + 180.0) / kImpactBinDeg)), 0, kImpactBins - 1));
    d.count[k] += 1.0;
    d.energy_J[k] += m.energy_J;
    if (m.on_liner) d.liner_energy_J[k] += m.energy_J;
    if (m.species >= 0 && m.species < species_count) {
      d.species_count[static_cast<std::size_t>(m.species)][k] += 1.0;
      d.species_energy_J[static_cast<std::size_t>(m.species)][k] += m.energy_J;
    }
  }
  return d;
}

ImpactShares impact_shares(const std::vector<Impact>& impacts, double toe_deg, double shoulder_deg,
                           bool centrifuged, int batch) {
  ImpactShares s;
  s.centrifuged = centrifuged;
  for (const Impact& m : impacts) {
    if (batch >= 0 && m.batch != batch) continue;
    ++s.impacts;
    s.energy_J += m.energy_J;
    if (centrifuged || !above_toe(m.angle_deg, toe_deg, shoulder_deg)) continue;
    s.above_toe_energy_J += m.energy_J;
    if (m.on_liner) s.liner_energy_J += m.energy_J;
  }
  // No toe or shoulder (nothing reached the shell band): nothing tells above the toe from in the bed.
  const bool defined = !centrifuged && std::isfinite(toe_deg) && std::isfinite(shoulder_deg) && s.energy_J > 0.0;
  s.liner_share = defined ? s.liner_energy_J / s.energy_J : kNaN;
  s.above_toe_share = defined ? s.above_toe_energy_J / s.energy_J : kNaN;
  return s;
}

ImpactSummary summarize_impacts(const std::vector<Impact>& impacts, int batches, double toe_deg,
                                double shoulder_deg, bool centrifuged) {
  ImpactSummary out;
  out.window = impact_shares(impacts, toe_deg, shoulder_deg, centrifuged);
  // A batch without a landed flight has no share; the error comes from those that have one.
  std::vector<double> liner, above;
  for (int b = 0; b < batches; ++b) {
    const ImpactShares s = impact_shares(impacts, toe_deg, shoulder_deg, centrifuged, b);
    if (std::isfinite(s.liner_share)) liner.push_back(s.liner_share);
    if (std::isfinite(s.above_toe_share)) above.push_back(s.above_toe_share);
  }
  out.liner_share = batch_means(liner);
  out.above_toe_share = batch_means(above);
  return out;
}

}  // namespace millwear
