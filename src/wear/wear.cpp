// Archard's law per liner edge and the wear loops.
//
// Staged (quasi-static) mode: with the geometry frozen, a window of revolutions gives the
// shear power on every edge; the real operating time then advances by the step that keeps
// the largest depth increment under the scene's bound, the liner is worn and re-smoothed,
// and the next window measures the new geometry. Statistics (rule 2) and geometry change
// (rule 1) are separate knobs.
// Continuous mode (the paper's): the mill keeps turning and every update_interval of
// simulated time the accumulated work wears the liner with C_model = factor * C, so one
// simulated second stands for `factor` seconds of operation.
//
// Stage 0 settles a fresh charge; every later stage starts a fresh engine from the charge
// as the previous stage's wear ended (kept in its record), so a stage depends only on its
// record: resuming from a saved stage gives the same results as an uninterrupted run.
#include "wear/wear.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "common/errors.hpp"
#include "geometry/polyline.hpp"

namespace millwear {

namespace {

constexpr double kSecondsPerHour = 3600.0;
using Clock = std::chrono::steady_clock;

double unit_edge_mid_x(const LinerUnit& u, int j) { return 0.5 * (u.surface[j].x + u.surface[j + 1].x); }

bool is_lifter_edge(const LinerUnit& u, int j) {
  return std::fabs(unit_edge_mid_x(u, j)) <= u.lifter_half_base_m + 1e-9;
}

// Direction of rotation at an operating time: +1 forward (counter-clockwise), -1 reverse.
double direction_at(const Scene& scene, double hours) {
  switch (scene.mill.direction) {
    case Direction::Forward: return 1.0;
    case Direction::Reverse: return -1.0;
    case Direction::Bidirectional: {
      const long period = static_cast<long>(std::floor(hours / scene.mill.reverse_every_hours + 1e-9));
      return period % 2 == 0 ? 1.0 : -1.0;
    }
  }
  return 1.0;
}

// Turns the mill at the direction's speed; after a reversal the charge turns round for half
// a revolution before anything is measured.
void set_direction(Engine& engine, const Scene& scene, double dir, bool reversed) {
  engine.set_mill_speed(dir * scene.angular_speed_rad_s());
  if (reversed) engine.step(steps_for(0.5 * scene.revolution_time_s(), engine.time_step_s()));
  engine.reset_window();
}

// Operating hours of the next reversal after `hours` (infinity for one-way mills).
double next_reversal(const Scene& scene, double hours) {
  if (scene.mill.direction != Direction::Bidirectional) return INFINITY;
  const double p = scene.mill.reverse_every_hours;
  return (std::floor(hours / p + 1e-9) + 1.0) * p;
}

// Shear power per unit edge (W, averaged over rows or per row) over a window, with the
// lifter area-loss-rate batch statistics for rule 2.
struct WindowResult {
  std::vector<double> edge_power_W;                 // per mill edge
  std::vector<std::vector<double>> unit_power_W;    // per unit (1 or rows), per unit edge
  Accounting accounting;                            // whole window
  double lifter_power_mean_W = 0.0;                 // per row, summed over lifter edges
  double lifter_power_rel_sem = 0.0;
  double simulated_s = 0.0;
};

double lifter_power(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power) {
  double sum = 0.0;
  for (std::size_t u = 0; u < unit_power.size(); ++u)
    for (std::size_t j = 0; j < unit_power[u].size(); ++j)
      if (is_lifter_edge(mill.units[u], static_cast<int>(j))) sum += unit_power[u][j];
  return sum / static_cast<double>(unit_power.size());
}

void add_into(Accounting& total, const Accounting& part) {
  if (total.shear_work_J.empty()) { total = part; return; }
  for (std::size_t e = 0; e < total.shear_work_J.size(); ++e) {
    total.shear_work_J[e] += part.shear_work_J[e];
    total.impact_energy_J[e] += part.impact_energy_J[e];
    total.contacts[e] += part.contacts[e];
  }
  total.time_s += part.time_s;
  total.steps += part.steps;
  total.drive_work_J += part.drive_work_J;
  total.torque_impulse_Nms += part.torque_impulse_Nms;
  total.pp_normal_J += part.pp_normal_J;
  total.pp_tangent_J += part.pp_tangent_J;
  total.pl_normal_J += part.pl_normal_J;
  total.pl_tangent_J += part.pl_tangent_J;
  total.solver_position_J += part.solver_position_J;
  total.kinetic_J_end = part.kinetic_J_end;
  total.potential_J_end = part.potential_J_end;
  for (int k = 0; k < kSpectrumBins; ++k) {
    total.spectrum_count[k] += part.spectrum_count[k];
    total.spectrum_energy_J[k] += part.spectrum_energy_J[k];
  }
  total.mass_time_kg_s += part.mass_time_kg_s;
  total.moment_time_kg_m_s += part.moment_time_kg_m_s;
  for (int k = 0; k < kShapeAngleBins; ++k) total.shell_band_occupancy[k] += part.shell_band_occupancy[k];
  total.shape_samples += part.shape_samples;
  total.packed_shear_work_J += part.packed_shear_work_J;
  total.packed_disk_steps += part.packed_disk_steps;
  total.escaped += part.escaped;
  total.non_finite += part.non_finite;
}

// simulate_window -> accumulate_work: run the window in batches (batch means for rule 2),
// extending it while the lifter's shear power is less certain than the scene's target.
WindowResult simulate_window(Engine& engine, const Scene& scene, const MillGeometry& mill,
                             const std::function<void()>& check_stop) {
  constexpr int kBatches = 4;
  constexpr int kMaxBatches = 16;
  const double batch_s = scene.wear.window_revolutions * scene.revolution_time_s() / kBatches;
  const int batch_steps = std::max(1, steps_for(batch_s, engine.time_step_s()));
  WindowResult w;
  std::vector<double> batch_power;
  for (int b = 0; b < kMaxBatches; ++b) {
    check_stop();
    engine.reset_window();
    engine.step(batch_steps);
    const Accounting& acc = engine.accounting();
    std::vector<double> p(acc.shear_work_J.size());
    for (std::size_t e = 0; e < p.size(); ++e) p[e] = acc.shear_work_J[e] / acc.time_s;
    batch_power.push_back(lifter_power(mill, unit_edge_work(mill, p, scene.wear.average_rows)));
    add_into(w.accounting, acc);
    const int n = static_cast<int>(batch_power.size());
    if (n < kBatches) continue;
    const double mean = std::accumulate(batch_power.begin(), batch_power.end(), 0.0) / n;
    double var = 0.0;
    for (double x : batch_power) var += (x - mean) * (x - mean);
    var /= (n - 1);
    w.lifter_power_rel_sem = mean > 0.0 ? std::sqrt(var / n) / mean : 0.0;
    if (scene.wear.target_rel_uncertainty <= 0.0 || w.lifter_power_rel_sem <= scene.wear.target_rel_uncertainty)
      break;
  }
  w.simulated_s = w.accounting.time_s;
  w.edge_power_W.resize(w.accounting.shear_work_J.size());
  for (std::size_t e = 0; e < w.edge_power_W.size(); ++e)
    w.edge_power_W[e] = w.accounting.shear_work_J[e] / w.accounting.time_s;
  w.unit_power_W = unit_edge_work(mill, w.edge_power_W, scene.wear.average_rows);
  w.lifter_power_mean_W = lifter_power(mill, w.unit_power_W);
  return w;
}

// Unit edge lengths in the mill frame (true lengths; rows are identical copies).
std::vector<double> unit_edge_lengths(const LinerUnit& u, double radius_m) {
  std::vector<double> len(u.surface.size() - 1);
  for (std::size_t j = 0; j + 1 < u.surface.size(); ++j)
    len[j] = length(local_to_mill(u.surface[j + 1], 0, 1, radius_m) - local_to_mill(u.surface[j], 0, 1, radius_m));
  return len;
}

// archard_depths: depth rate (m per operating second) per unit edge for real C.
// Archard's depth per unit edge, read at the mesh's resolution: an edge shorter than
// min_length_m (a cut's sliver, a step of a rounded corner) takes the depth of the run of
// edges around it that is min_length_m long, as one contact's work divided by a sliver's
// length would be all noise. Longer edges keep their own. Shell edges are zero unless the
// shell wears.
std::vector<double> unit_depths(const LinerUnit& unit, const std::vector<double>& work_J,
                                const std::vector<double>& len_m, double min_length_m, double thickness_m,
                                double rate_m3_per_J, bool shell_wear) {
  const std::size_t n = len_m.size();
  std::vector<double> depth(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    if (!shell_wear && !is_lifter_edge(unit, static_cast<int>(j))) continue;
    double work = work_J[j], len = len_m[j];
    for (std::size_t a = j, b = j; len < min_length_m && (a > 0 || b + 1 < n);) {
      if (a > 0) { --a; work += work_J[a]; len += len_m[a]; }
      if (len < min_length_m && b + 1 < n) { ++b; work += work_J[b]; len += len_m[b]; }
    }
    depth[j] = archard_depth_m(work, len, thickness_m, rate_m3_per_J);
  }
  return depth;
}

std::vector<std::vector<double>> depth_rates(const Scene& scene, const MillGeometry& mill,
                                             const WindowResult& w, double c_real) {
  std::vector<std::vector<double>> rates(w.unit_power_W.size());
  const double t = scene.slice_thickness();
  for (std::size_t u = 0; u < rates.size(); ++u) {
    rates[u] = unit_depths(mill.units[u], w.unit_power_W[u], unit_edge_lengths(mill.units[u], mill.radius_m),
                           0.5 * scene.mill.mesh.lifter_edge_m, t, c_real, scene.wear.shell_wear);
  }
  return rates;
}

double max_of(const std::vector<std::vector<double>>& v) {
  double m = 0.0;
  for (const auto& a : v) for (double x : a) m = std::max(m, x);
  return m;
}

double smoothing_radius(const Scene& scene) {
  return scene.wear.smoothing_radius_m > 0.0 ? scene.wear.smoothing_radius_m
                                             : scene.smallest_particle_radius_m();
}

bool lifter_worn_out(const LifterMetrics& m, const LifterMetrics& new_m) {
  // Worn to the shell: under 1% of its new height or area left.
  return m.height_m < 0.01 * new_m.height_m || m.area_m2 < 0.01 * new_m.area_m2;
}

}  // namespace

std::vector<std::vector<double>> unit_edge_work(const MillGeometry& mill,
                                                const std::vector<double>& edge_work,
                                                bool average_rows) {
  const bool shared = average_rows || mill.units.size() == 1;
  const std::size_t n_units = shared ? 1 : static_cast<std::size_t>(mill.rows);
  std::vector<std::vector<double>> out(n_units);
  for (std::size_t u = 0; u < n_units; ++u)
    out[u].assign(static_cast<std::size_t>(mill.unit_edge_count(static_cast<int>(u))), 0.0);
  const double scale = shared ? 1.0 / mill.rows : 1.0;
  for (std::size_t e = 0; e < edge_work.size(); ++e) {
    const LinerEdgeInfo& info = mill.edges[e];
    const std::size_t u = shared ? 0 : static_cast<std::size_t>(info.row);
    out[u][static_cast<std::size_t>(info.unit_edge)] += scale * edge_work[e];
  }
  return out;
}

double real_wear_rate(const Scene& scene, const MillGeometry& mill,
                      const std::vector<double>& shear_power_W) {
  const WearDef& w = scene.wear;
  if (w.rate_source == WearRateSource::Given) return w.wear_rate_m3_per_J;
  const auto unit_power = unit_edge_work(mill, shear_power_W, true);
  const LinerUnit& unit = mill.units[0];
  const double t = scene.slice_thickness();
  if (w.rate_source == WearRateSource::AreaLossRate) {
    // Area loss rate of the lifter = C * sum(P_e) / t over lifter edges.
    double p = 0.0;
    for (std::size_t j = 0; j < unit_power[0].size(); ++j)
      if (is_lifter_edge(unit, static_cast<int>(j))) p += unit_power[0][j];
    const double target_m2_per_s = w.calibration_value * 1e-6 / (1000.0 * kSecondsPerHour);
    if (!(p > 0.0)) throw RunError("cannot calibrate the wear rate: no shear work on the lifter");
    return target_m2_per_s * t / p;
  }
  // Height loss rate: depth rate at the lifter's top edges (within 10% of its height).
  const LifterMetrics m = measure_lifter(unit, mill.radius_m);
  const auto len = unit_edge_lengths(unit, mill.radius_m);
  double sum = 0.0, count = 0.0;
  for (std::size_t j = 0; j < len.size(); ++j) {
    const double y = 0.5 * (unit.surface[j].y + unit.surface[j + 1].y);
    if (!is_lifter_edge(unit, static_cast<int>(j)) || y < 0.9 * m.height_m) continue;
    sum += unit_power[0][j] / (len[j] * t);
    count += 1.0;
  }
  if (!(sum > 0.0)) throw RunError("cannot calibrate the wear rate: no shear work on the lifter top");
  const double target_m_per_s = w.calibration_value * 1e-3 / kSecondsPerHour;
  return target_m_per_s / (sum / count);
}

// The unit's surface continued by its neighbours' copies (the liner repeats every pitch; the
// ends are at one height, so the copies join without a step) to `margin` beyond each end.
Polyline periodic_surface(const Polyline& unit, double pitch, double margin) {
  const int copies = static_cast<int>(std::ceil(margin / pitch));
  Polyline chain;
  for (int k = -copies; k <= copies; ++k)
    for (std::size_t i = (k == -copies ? 0 : 1); i < unit.size(); ++i) chain.push_back(unit[i] + Vec2{k * pitch, 0.0});
  // Cut where the chain first (last) crosses x_left (x_right), from the outside in.
  const double x_left = unit.front().x - margin, x_right = unit.back().x + margin;
  std::size_t first = 0, last = chain.size() - 1;
  while (first + 1 < chain.size() && chain[first + 1].x <= x_left) ++first;
  while (last > first + 1 && chain[last - 1].x >= x_right) --last;
  auto at_x = [](Vec2 a, Vec2 b, double x) {
    return a.x == b.x ? a : Vec2{x, a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)};
  };
  Polyline out{at_x(chain[first], chain[first + 1], x_left)};
  for (std::size_t i = first + 1; i < last; ++i) out.push_back(chain[i]);
  out.push_back(at_x(chain[last - 1], chain[last], x_right));
  return out;
}

// The metal region below an open surface running left to right: the surface, then down to
// y_floor and back along it (counter-clockwise).
Polygon metal_below(const Polyline& surface, double y_floor) {
  Polygon metal(surface.rbegin(), surface.rend());  // right to left along the top...
  metal.push_back({surface.front().x, y_floor});     // ...then down and along the floor
  metal.push_back({surface.back().x, y_floor});
  if (signed_area(metal) < 0.0) std::reverse(metal.begin(), metal.end());
  return metal;
}

// The top of a counter-clockwise metal region between x_left and x_right, left to right: from
// the highest crossing of the boundary with x = x_left to the highest with x = x_right.
Polyline top_chain_between(const Polygon& ccw, double x_left, double x_right) {
  const std::size_t n = ccw.size();
  auto highest_crossing = [&](double x, std::size_t& edge, Vec2& at) {
    bool found = false;
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = ccw[i], b = ccw[(i + 1) % n];
      if (a.x == b.x || (a.x - x) * (b.x - x) > 0.0) continue;
      const Vec2 p{x, a.y + (b.y - a.y) * (x - a.x) / (b.x - a.x)};
      if (!found || p.y > at.y) {
        found = true;
        edge = i;
        at = p;
      }
    }
    return found;
  };
  std::size_t e_right = 0, e_left = 0;
  Vec2 p_right, p_left;
  if (!highest_crossing(x_right, e_right, p_right) || !highest_crossing(x_left, e_left, p_left)) return {};
  // Counter-clockwise, the top runs from right to left.
  Polyline top{p_right};
  if (e_left != e_right)  // else both crossings lie on one edge: nothing between them
    for (std::size_t i = (e_right + 1) % n;; i = (i + 1) % n) {
      if (!(ccw[i] == top.back())) top.push_back(ccw[i]);
      if (i == e_left || top.size() > n + 1) break;
    }
  if (!(p_left == top.back())) top.push_back(p_left);
  std::reverse(top.begin(), top.end());
  // The two ends are one height up to rounding: make it exact, so rows join without a step.
  const double y = 0.5 * (top.front().y + top.back().y);
  top.front().y = top.back().y = y;
  return top;
}

LinerUnit apply_wear(const LinerUnit& unit, const std::vector<double>& edge_depth_m,
                     double radius_m, double smoothing_m, const MillMeshDef& mesh) {
  const Polyline& s = unit.surface;
  const std::size_t n = s.size();
  if (edge_depth_m.size() + 1 != n) throw RunError("apply_wear: one depth per unit edge expected");
  // Edge depths -> vertex displacements into the metal along the vertex normals. Both are
  // the neighbouring edges' weighted by length, so a short edge (where a cut met a vertex)
  // neither turns its vertices nor moves them by its own noisy depth.
  Polyline moved = s;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e_prev = i > 0 ? s[i] - s[i - 1] : Vec2{};
    const Vec2 e_next = i + 1 < n ? s[i + 1] - s[i] : Vec2{};
    const double l_prev = length(e_prev), l_next = length(e_next);
    const double d_prev = i > 0 ? edge_depth_m[i - 1] : 0.0;
    const double d_next = i + 1 < n ? edge_depth_m[i] : 0.0;
    // into the metal: right of the surface's direction (+x); right_perp keeps the length
    const Vec2 normal = normalized(right_perp(e_prev) + right_perp(e_next));
    moved[i] = s[i] + ((l_prev * d_prev + l_next * d_next) / (l_prev + l_next)) * normal;
  }
  // The unit's ends stay at +-pitch/2 and at one height, so rows join without a step.
  const double half_pitch = 0.5 * (s.back().x - s.front().x);
  const double y_end = 0.5 * (moved.front().y + moved.back().y);
  moved.front() = {-half_pitch, y_end};
  moved.back() = {half_pitch, y_end};
  // A rounded corner worn deeper than its radius folds over itself: cut the fold out.
  moved = without_loops(moved);

  // The liner repeats every pitch, so the unit is smoothed and cut with its neighbours'
  // copies either side: its ends then see the same metal as its middle does.
  const double pitch = 2.0 * half_pitch;
  // The opening and closing reach 2r: 3r of the neighbours (and a bit, for r = 0) is plenty.
  const double margin = 3.0 * smoothing_m + 0.1 * pitch;
  double y_min = y_end;
  for (const Vec2& p : moved) y_min = std::min(y_min, p.y);
  for (const Vec2& p : s) y_min = std::min(y_min, p.y);
  const double y_floor = y_min - 4.0 * smoothing_m - 0.05 * half_pitch;
  auto metal_of = [&](const Polyline& surface) { return metal_below(periodic_surface(surface, pitch, margin), y_floor); };
  // The unit's top between its ends. Cutting leaves slivers where a chord crosses the old
  // surface near one of its vertices: clusters of points micrometres apart, edges with no
  // direction to wear along and a depth that is all noise. Points closer than a hundredth of
  // a lifter edge to the last one kept go (what that can leave outside the old surface is
  // below a hundredth of an edge).
  const double too_short = kSliverEdgeFraction * mesh.lifter_edge_m;
  auto unit_top = [&](const Polygon& metal) {
    const Polyline top = top_chain_between(metal, -half_pitch, half_pitch);
    if (top.size() < 2) throw RunError("the worn liner unit lost its ends when re-smoothed");
    Polyline kept{top.front()};
    for (std::size_t i = 1; i + 1 < top.size(); ++i)
      if (length(top[i] - kept.back()) > too_short && length(top.back() - top[i]) > too_short) kept.push_back(top[i]);
    kept.push_back(top.back());
    return kept;
  };

  // Re-smooth: open and close the metal with a disk of radius smoothing_m.
  Polyline top = moved;
  if (smoothing_m > 0.0) {
    const Polygon smooth = smooth_by_offsets(metal_of(moved), smoothing_m);
    if (smooth.size() < 4) throw RunError("the worn liner unit vanished when re-smoothed");
    top = unit_top(smooth);
  }

  // Resample: lifter-size edges over the lifter, shell-size edges elsewhere.
  LinerUnit out;
  out.lifter_half_base_m = unit.lifter_half_base_m;
  // Bends over 5 deg stay vertices: a corner the smoothing rounded is a run of the disk
  // polygon's 11.25 deg turns, and chords across it would wear it (convex) or grow it
  // (concave) by L^2 / 8r at every update.
  const Polyline fine = resample(top, mesh.lifter_edge_m, 5.0);
  out.surface.reserve(fine.size());
  const double keep_zone = unit.lifter_half_base_m + mesh.shell_edge_m;
  double last_x = -INFINITY;
  for (std::size_t i = 0; i < fine.size(); ++i) {
    const Vec2 p = fine[i];
    const bool end = i == 0 || i + 1 == fine.size();
    if (end || std::fabs(p.x) <= keep_zone || p.x - last_x >= mesh.shell_edge_m * 0.999) {
      out.surface.push_back(p);
      last_x = p.x;
    }
  }
  if (out.surface.size() >= 2 && out.surface[out.surface.size() - 2].x > half_pitch - 1e-3 * mesh.shell_edge_m)
    out.surface.erase(out.surface.end() - 2);
  // Wear never adds metal: what the closing filled (a notch, a concave corner's fillet) and
  // what a chord of the resampling spans over a hollow are cut back to the surface before
  // this update.
  out.surface = unit_top(intersect_largest(metal_of(out.surface), metal_of(s)));
  if (!is_simple_open(out.surface)) throw RunError("the worn liner surface crosses itself");
  (void)radius_m;
  return out;
}

SmoothingLoss smoothing_loss(const Scene& scene, double smoothing_m) {
  const double R = scene.radius_m();
  const LinerUnit unit = make_liner_unit(scene.mill.lifter.points, R, scene.mill.rows, scene.mill.mesh);
  const LifterMetrics before = measure_lifter(unit, R);
  SmoothingLoss loss;
  try {
    const LinerUnit after = apply_wear(unit, std::vector<double>(unit.surface.size() - 1, 0.0), R, smoothing_m,
                                       scene.mill.mesh);
    const LifterMetrics m = measure_lifter(after, R);
    loss.area_fraction = 1.0 - m.area_m2 / before.area_m2;
    loss.height_fraction = 1.0 - m.height_m / before.height_m;
  } catch (const RunError&) {
    loss.area_fraction = loss.height_fraction = 1.0;  // the unit did not survive it
  }
  return loss;
}

double resmoothing_loss_m2(const LinerUnit& before, const LinerUnit& after, const std::vector<double>& edge_depth_m,
                           double radius_m) {
  const std::vector<double> len = unit_edge_lengths(before, radius_m);
  double worn = 0.0;  // what Archard's depths remove from the lifter
  for (std::size_t j = 0; j < len.size() && j < edge_depth_m.size(); ++j)
    if (is_lifter_edge(before, static_cast<int>(j))) worn += edge_depth_m[j] * len[j];
  return measure_lifter(before, radius_m).area_m2 - measure_lifter(after, radius_m).area_m2 - worn;
}

void check_smoothing_radius(const Scene& scene, const std::string& file) {
  const double r = smoothing_radius(scene);
  auto too_much = [&](double radius) {
    const SmoothingLoss l = smoothing_loss(scene, radius);
    return l.area_fraction > kMaxSmoothingAreaLoss || l.height_fraction > kMaxSmoothingHeightLoss;
  };
  if (r <= 0.0 || !too_much(r)) return;
  // Bisect for the largest radius within the bounds (to 1% of r; 0 when even a tiny one is not).
  double lo = 0.0, hi = r;
  for (int i = 0; i < 12 && hi - lo > 0.01 * r; ++i) {
    const double mid = 0.5 * (lo + hi);
    (too_much(mid) ? hi : lo) = mid;
  }
  const SmoothingLoss l = smoothing_loss(scene, r);
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "a smoothing radius of at most %.3g mm for this lifter: re-smoothing the new lifter at %.3g mm "
                "removes %.0f%% of its area and %.0f%% of its height before any wear (the radius is wider than half "
                "its narrowest part; bounds %.0f%% and %.0f%%)%s",
                lo * 1e3, r * 1e3, 100.0 * l.area_fraction, 100.0 * l.height_fraction, 100.0 * kMaxSmoothingAreaLoss,
                100.0 * kMaxSmoothingHeightLoss,
                scene.wear.smoothing_radius_m > 0.0 ? "" : "; the default is the smallest particle radius: set "
                                                           "wear.smoothing_radius");
  throw InputError(file, "wear.smoothing_radius", buf);
}

LinerUnit wear_under_load_field(const LinerUnit& unit, double radius_m,
                                const std::function<double(Vec2)>& shear_power_W_per_m2,
                                double c_model_m3_per_J, double sim_time_s, int updates,
                                double smoothing_m, const MillMeshDef& mesh) {
  LinerUnit u = unit;
  const double dt = sim_time_s / updates;
  for (int k = 0; k < updates; ++k) {
    std::vector<double> depth(u.surface.size() - 1);
    for (std::size_t j = 0; j + 1 < u.surface.size(); ++j) {
      const Vec2 mid = 0.5 * (u.surface[j] + u.surface[j + 1]);
      // Work per area = power per area * dt; the depth is C_model times that (A dh = C dw).
      depth[j] = c_model_m3_per_J * shear_power_W_per_m2(mid) * dt;
    }
    u = apply_wear(u, depth, radius_m, smoothing_m, mesh);
  }
  return u;
}

void compute_life(WearHistory& h, double replacement_height_m) {
  h.life_h = 0.0;
  h.life_extrapolated = false;
  const auto& st = h.stages;
  if (st.empty()) return;
  for (std::size_t k = 1; k < st.size(); ++k) {
    const double h0 = st[k - 1].lifter.height_m, h1 = st[k].lifter.height_m;
    if (h1 <= replacement_height_m && h0 > replacement_height_m) {
      const double f = (h0 - replacement_height_m) / (h0 - h1);
      h.life_h = st[k - 1].hours + f * (st[k].hours - st[k - 1].hours);
      return;
    }
  }
  if (st.front().lifter.height_m <= replacement_height_m) return;
  // Beyond the simulated stages: extrapolate the height trend of the last stages.
  h.life_extrapolated = true;
  if (st.size() < 2) { h.life_h = INFINITY; return; }
  const std::size_t a = st.size() >= 3 ? st.size() - 3 : 0, b = st.size() - 1;
  const double rate = (st[a].lifter.height_m - st[b].lifter.height_m) / (st[b].hours - st[a].hours);
  h.life_h = rate > 0.0 ? st[b].hours + (st[b].lifter.height_m - replacement_height_m) / rate : INFINITY;
}

WearHistory run_wear_history(const Scene& scene, const WearCallbacks& cb,
                             const std::vector<StageRecord>& resume_from) {
  check_smoothing_radius(scene, scene.source_file);
  WearHistory history;
  const double R = scene.radius_m();
  const int rows = scene.mill.rows;
  const LinerUnit new_unit = make_liner_unit(scene.mill.lifter.points, R, rows, scene.mill.mesh);
  const LifterMetrics new_metrics = measure_lifter(new_unit, R);
  const double smoothing_m = smoothing_radius(scene);
  const double stage_h = scene.wear.stage_hours;
  const bool staged = scene.wear.mode == WearMode::Staged;

  std::vector<LinerUnit> units{new_unit};
  if (!scene.wear.average_rows) units.assign(static_cast<std::size_t>(rows), new_unit);
  int first_stage = 0;
  if (!resume_from.empty()) {
    history.stages = resume_from;
    units = resume_from.back().units;
    first_stage = resume_from.back().stage;
  }
  double c_real = scene.wear.rate_source == WearRateSource::Given ? scene.wear.wear_rate_m3_per_J : 0.0;
  if (!resume_from.empty() && (first_stage >= scene.wear.stages || resume_from.back().worn_out)) {
    // Everything was finished already: nothing to simulate.
    history.wear_rate_m3_per_J = c_real;
    compute_life(history, scene.wear.replacement_height_m);
    return history;
  }
  auto check_stop = [&cb] {
    if (cb.should_stop && cb.should_stop()) throw RunError("interrupted");
  };

  // Progress after every window: stage being worn, operating hours, simulated seconds.
  auto report_progress = [&cb](int stage, double hours, double simulated, std::int64_t disk_steps,
                               Clock::time_point since) {
    if (!cb.on_progress) return;
    WearProgress p;
    p.stage = stage;
    p.hours = hours;
    p.simulated_s = simulated;
    const double wall = std::chrono::duration<double>(Clock::now() - since).count();
    p.disk_steps_per_s = wall > 0 ? disk_steps / wall : 0.0;
    cb.on_progress(p);
  };

  // The charge as the last stage's wear ended (a resumed run: the one its stage started from).
  ChargeState carry = resume_from.empty() ? ChargeState{} : resume_from.back().start_charge;
  for (int k = first_stage; k <= scene.wear.stages; ++k) {
    const auto t0 = Clock::now();
    double hours = k * stage_h;
    MillGeometry mill = build_mill(R, rows, units);
    check_stop();
    double dir = direction_at(scene, hours);
    const ChargeState start = std::move(carry);
    carry = ChargeState{};
    std::unique_ptr<Engine> engine;
    if (start.size() == 0) {
      // The first stage: a fresh charge, settled on the new liner.
      engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
      settle_and_spin_up(*engine, scene, dir);
    } else {
      engine = make_engine(scene, mill, start, accounting_options_for(scene));
      set_direction(*engine, scene, dir, start.mill_speed_rad_s * dir < 0.0);
    }
    WindowResult w = simulate_window(*engine, scene, mill, check_stop);
    double simulated = w.simulated_s;
    std::int64_t disk_steps = w.accounting.steps * static_cast<std::int64_t>(engine->state().size());
    if (c_real <= 0.0) {
      // Calibration is against the new liner: it needs stage 0's window.
      if (k != 0 && resume_from.empty()) throw RunError("wear-rate calibration needs stage 0");
      c_real = real_wear_rate(scene, k == 0 ? mill : build_mill(R, rows, {new_unit}), w.edge_power_W);
    }
    history.wear_rate_m3_per_J = c_real;

    const bool resumed_stage = k == first_stage && !resume_from.empty();
    if (!resumed_stage) {
      StageRecord rec;
      rec.stage = k;
      rec.hours = hours;
      rec.units = units;
      rec.lifter = measure_lifter(units[0], R);
      rec.charge = charge_figures(w.accounting, scene, dir * scene.angular_speed_rad_s());
      const double t = scene.slice_thickness();
      rec.area_loss_rate_mm2_per_h = c_real * w.lifter_power_mean_W / t * kSecondsPerHour * 1e6;
      rec.area_loss_rate_rel_sem = w.lifter_power_rel_sem;
      rec.spectrum_count_per_s.resize(kSpectrumBins);
      rec.spectrum_energy_W.resize(kSpectrumBins);
      for (int b = 0; b < kSpectrumBins; ++b) {
        rec.spectrum_count_per_s[b] = w.accounting.spectrum_count[b] / w.accounting.time_s;
        rec.spectrum_energy_W[b] = w.accounting.spectrum_energy_J[b] / w.accounting.time_s;
      }
      rec.edge_wear_rate_m_per_h.resize(mill.boundary.size());
      for (std::size_t e = 0; e < mill.boundary.size(); ++e) {
        const bool shell = mill.edges[e].owner == EdgeOwner::Shell;
        rec.edge_wear_rate_m_per_h[e] = (shell && !scene.wear.shell_wear) ? 0.0
            : archard_depth_m(w.edge_power_W[e], mill.edge_length_m[e], t, c_real) * kSecondsPerHour;
      }
      rec.snapshot = engine->state();
      rec.mill_angle_rad = engine->state().mill_angle_rad;
      rec.start_charge = start;
      rec.worn_out = lifter_worn_out(rec.lifter, new_metrics);
      for (const auto& e : engine->events())
        history.events.push_back("stage " + std::to_string(k) + ": " + e.what);
      if (k == scene.wear.stages || rec.worn_out) {
        rec.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
        rec.simulated_s = simulated;
        rec.disk_steps = disk_steps;
        history.stages.push_back(rec);
        if (cb.on_stage) cb.on_stage(history.stages.back());
        if (rec.worn_out) history.events.push_back("stage " + std::to_string(k) + ": the lifter is worn to the shell");
        break;
      }
      history.stages.push_back(rec);
    }

    // Wear through stage k+1.
    const double target_h = (k + 1) * stage_h;
    bool worn_out = false;
    while (hours < target_h - 1e-9 && !worn_out) {
      check_stop();
      const auto rates = depth_rates(scene, mill, w, c_real);  // m per operating second
      const double reversal = next_reversal(scene, hours);
      double dt_h = std::min(target_h, reversal) - hours;
      std::vector<std::vector<double>> depths(rates.size());
      if (staged) {
        const double max_rate_h = max_of(rates) * kSecondsPerHour;
        if (max_rate_h > 0.0) dt_h = std::min(dt_h, scene.wear.max_depth_step_m / max_rate_h);
        for (std::size_t u = 0; u < rates.size(); ++u) {
          depths[u].resize(rates[u].size());
          for (std::size_t j = 0; j < rates[u].size(); ++j) depths[u][j] = rates[u][j] * dt_h * kSecondsPerHour;
        }
      } else {
        // Continuous: the charge turns for update_interval of simulated time, which stands
        // for factor times as much operation; wear uses that interval's own work.
        const double sim_s = std::min(scene.wear.update_interval_s,
                                      dt_h * kSecondsPerHour / scene.wear.factor);
        engine->reset_window();
        engine->step(std::max(1, steps_for(sim_s, engine->time_step_s())));
        simulated += engine->accounting().time_s;
        disk_steps += engine->accounting().steps * static_cast<std::int64_t>(engine->state().size());
        dt_h = engine->accounting().time_s * scene.wear.factor / kSecondsPerHour;
        const auto work = unit_edge_work(mill, engine->accounting().shear_work_J, scene.wear.average_rows);
        const double t = scene.slice_thickness();
        const double c_model = scene.wear.factor * c_real;
        for (std::size_t u = 0; u < work.size(); ++u)
          depths[u] = unit_depths(units[u], work[u], unit_edge_lengths(units[u], R), 0.5 * scene.mill.mesh.lifter_edge_m,
                                  t, c_model, scene.wear.shell_wear);
        const double worst = max_of(depths);
        if (worst > 0.25 * new_metrics.height_m) {
          history.events.push_back("stage " + std::to_string(k + 1) + ": wear.factor " +
                                   std::to_string(scene.wear.factor) + " wore " +
                                   std::to_string(worst * 1e3) + " mm in one update (over a quarter of the lifter): "
                                   "C_model is too large for rule 1; lower wear.factor");
          compute_life(history, scene.wear.replacement_height_m);
          return history;
        }
      }
      // apply_wear -> resmooth (inside) for every unit.
      std::string smoothing_error;
      try {
        for (std::size_t u = 0; u < units.size(); ++u) {
          LinerUnit worn = apply_wear(units[u], depths[u], R, smoothing_m, scene.mill.mesh);
          // A smoothing radius wider than a feature the worn lifter grew (a thin ridge left
          // between two wear grooves) takes it without any shear work. Stop with the limit
          // rather than report it as wear. (The update never adds metal or raises the
          // lifter: apply_wear cuts everything back to the surface before it.)
          const double lost = resmoothing_loss_m2(units[u], worn, depths[u], R);
          if (lost > kMaxSmoothingAreaLoss * new_metrics.area_m2) {
            char buf[400];
            std::snprintf(buf, sizeof buf,
                          "stage %d: re-smoothing at wear.smoothing_radius %.3g mm removed %.1f%% of the new lifter's "
                          "area beyond the wear itself (bound %.0f%%): the worn lifter has a feature narrower than "
                          "twice the radius; lower wear.smoothing_radius",
                          k + 1, smoothing_m * 1e3, 100.0 * lost / new_metrics.area_m2, 100.0 * kMaxSmoothingAreaLoss);
            smoothing_error = buf;
            break;
          }
          units[u] = std::move(worn);
        }
      } catch (const RunError& e) {
        history.events.push_back("stage " + std::to_string(k + 1) + ": " + e.what());
        worn_out = true;
        break;
      }
      if (!smoothing_error.empty()) throw RunError(smoothing_error);
      hours += dt_h;
      if (lifter_worn_out(measure_lifter(units[0], R), new_metrics)) { worn_out = true; break; }
      if (hours >= target_h - 1e-9) break;
      mill = build_mill(R, rows, units);
      engine->set_liner(mill);
      const double new_dir = direction_at(scene, hours);
      if (new_dir != dir) {
        dir = new_dir;
        set_direction(*engine, scene, dir, true);
      }
      if (staged) {
        w = simulate_window(*engine, scene, mill, check_stop);
        simulated += w.simulated_s;
        disk_steps += w.accounting.steps * static_cast<std::int64_t>(engine->state().size());
      }
      report_progress(k + 1, hours, simulated, disk_steps, t0);
    }
    if (!worn_out) carry = engine->state();
    if (!resumed_stage && !history.stages.empty() && history.stages.back().stage == k) {
      history.stages.back().wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
      history.stages.back().simulated_s = simulated;
      history.stages.back().disk_steps = disk_steps;
      if (cb.on_stage) cb.on_stage(history.stages.back());
    }
    report_progress(k + 1, hours, simulated, disk_steps, t0);
    if (worn_out) {
      // Record the worn-out geometry as the last stage, then stop cleanly.
      StageRecord rec;
      rec.stage = k + 1;
      rec.hours = hours;
      rec.units = units;
      rec.lifter = measure_lifter(units[0], R);
      rec.worn_out = true;
      rec.charge = history.stages.empty() ? ChargeFigures{} : history.stages.back().charge;
      history.stages.push_back(rec);
      history.events.push_back("stage " + std::to_string(k + 1) + ": the lifter is worn to the shell at " +
                               std::to_string(hours) + " h");
      if (cb.on_stage) cb.on_stage(history.stages.back());
      break;
    }
  }
  compute_life(history, scene.wear.replacement_height_m);
  return history;
}

}  // namespace millwear

namespace millwear {

Rule1Report rule1_check(const Scene& scene, std::vector<double> factors, double tolerance_pct_height) {
  std::sort(factors.begin(), factors.end());
  Rule1Report report;
  report.tolerance_pct_height = tolerance_pct_height;
  const double height = measure_lifter(
      make_liner_unit(scene.mill.lifter.points, scene.radius_m(), scene.mill.rows, scene.mill.mesh),
      scene.radius_m()).height_m;
  for (double f : factors) {
    Scene s = scene;
    s.wear.mode = WearMode::Continuous;
    s.wear.factor = f;
    const auto t0 = Clock::now();
    const WearHistory h = run_wear_history(s);
    Rule1Row row;
    row.factor = f;
    row.wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
    for (const auto& st : h.stages) row.simulated_s += st.simulated_s;
    row.profile = h.stages.back().units[0].surface;
    row.events = h.events;
    if (!report.rows.empty()) {
      const Polyline& prev = report.rows.back().profile;
      double d = 0.0;
      for (const Vec2& p : row.profile) d = std::max(d, distance_to_polyline(p, prev));
      for (const Vec2& p : prev) d = std::max(d, distance_to_polyline(p, row.profile));
      row.deviation_m = d;
      row.deviation_pct_height = 100.0 * d / height;
    }
    report.rows.push_back(row);
  }
  // Largest factor that agrees with every smaller one within tolerance (a run that hit the
  // rule-1 bound or another event never qualifies).
  if (!report.rows.empty() && report.rows.front().events.empty())
    report.recommended_factor = report.rows.front().factor;
  for (std::size_t k = 1; k < report.rows.size(); ++k) {
    if (report.rows[k].deviation_pct_height > tolerance_pct_height || !report.rows[k].events.empty()) break;
    report.recommended_factor = report.rows[k].factor;
  }
  return report;
}

}  // namespace millwear
