// Reshape: apply Archard's depths to the liner units and re-smooth them.
#include "wear/reshape.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "geometry/polyline.hpp"
#include "scene/limits.hpp"
#include "wear/archard.hpp"

namespace millwear {

namespace {

// The unit's surface continued by its neighbours' copies (the liner repeats every pitch; the
// ends are at one height, so the copies join without a step) to `margin` beyond each end.
Polyline periodic_surface(const Polyline& unit, double pitch, double margin) {
  const int copies = static_cast<int>(std::ceil(margin / pitch));
  Polyline chain;
  for (int k = -copies; k <= copies; ++k)
    for (std::size_t i = (k == -copies ? 0 : 1); i < unit.size(); ++i) chain.push_back(unit[i] + Vec2{k * pitch, 0.0});
  // Cut where the chain first crosses x_left (x_right) going out from the unit itself: the
  // cut's vertical line then meets the chain once. (Cut from the outside in, a neighbour's
  // overhang reaching back over the line, a T-shaped lifter's wing, was kept and crossed by
  // the line down to the floor: no simple polygon.)
  const double x_left = unit.front().x - margin, x_right = unit.back().x + margin;
  const std::size_t unit_first = static_cast<std::size_t>(copies) * (unit.size() - 1);
  const std::size_t unit_last = unit_first + unit.size() - 1;
  std::size_t first = unit_first, last = unit_last;
  while (first > 0 && chain[first - 1].x > x_left) --first;
  if (first > 0) --first;  // chain[first] at or left of x_left, chain[first + 1] right of it
  while (last + 1 < chain.size() && chain[last + 1].x < x_right) ++last;
  if (last + 1 < chain.size()) ++last;  // chain[last] at or right of x_right
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

}  // namespace

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


double smoothing_radius(const Scene& scene) {
  return scene.wear.smoothing_radius_m > 0.0 ? scene.wear.smoothing_radius_m
                                             : scene.smallest_particle_radius_m();
}

LinerUnit starting_unit(const Scene& scene, int kind, double smoothing_m) {
  const LinerUnit unit = new_liner_unit(scene, kind);
  if (scene.mill.kind(kind).measured.empty()) return unit;
  try {
    return apply_wear(unit, std::vector<double>(unit.surface.size() - 1, 0.0), scene.radius_m(), smoothing_m,
                      scene.mill.mesh);
  } catch (const RunError& e) {
    throw InputError(scene.mill.kind(kind).source_file, "x_mm,y_mm",
                     std::string("a measured surface that survives re-smoothing at ") +
                         std::to_string(in_mm(smoothing_m)) + " mm (wear.smoothing_radius): " + e.what());
  }
}

SmoothingLoss smoothing_loss(const Scene& scene, double smoothing_m, int kind) {
  const double R = scene.radius_m();
  SmoothingLoss loss;
  LinerUnit unit;
  try {
    unit = starting_unit(scene, kind, smoothing_m);
  } catch (const InputError& e) {
    loss.area_fraction = loss.height_fraction = 1.0;  // the unit did not survive it
    loss.failure = e.expected;
    return loss;
  }
  const LifterMetrics before = measure_lifter(unit, R);
  try {
    const LinerUnit after = apply_wear(unit, std::vector<double>(unit.surface.size() - 1, 0.0), R, smoothing_m,
                                       scene.mill.mesh);
    const LifterMetrics m = measure_lifter(after, R);
    loss.area_fraction = 1.0 - m.area_m2 / before.area_m2;
    loss.height_fraction = 1.0 - m.height_m / before.height_m;
  } catch (const RunError& e) {
    loss.area_fraction = loss.height_fraction = 1.0;  // the unit did not survive it
    loss.failure = e.what();
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
  for (int kind = 0; kind < scene.mill.kind_count(); ++kind) check_smoothing_radius(scene, file, kind);
}

void check_scene(const Scene& scene, const std::string& file) {
  check_run_limits(scene, file);
  check_smoothing_radius(scene, file);
}

// A measured profile's lifter once re-smoothed: most of the scan's metal left (the first pass
// takes the gauge's noise, a few per cent; a scan of a fin thinner than the particles would
// start as a sliver, which the bounds on later passes cannot see), and no part thinner than
// the smallest particle radius (scene/limits.cpp checks a drawn profile as read).
void check_measured_features(const Scene& scene, const std::string& file, int kind) {
  const LifterProfile& p = scene.mill.kind(kind);
  const double needed = scene.smallest_particle_radius_m();
  if (p.measured.empty() || !(needed > 0.0)) return;
  const double r = smoothing_radius(scene);
  const LinerUnit unit = starting_unit(scene, kind, r);
  const double scan_m2 = measure_lifter(new_liner_unit(scene, kind), scene.radius_m()).area_m2;
  const double start_m2 = measure_lifter(unit, scene.radius_m()).area_m2;
  if (!(start_m2 >= (1.0 - kMaxScanSmoothingLoss) * scan_m2)) {
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "a measured lifter the particles can see: re-smoothing the scan at %.3g mm (wear.smoothing_radius) "
                  "takes %.0f%% of its lifter's area (%.4g of %.4g mm^2, leaving %.4g; gauge noise takes a few per "
                  "cent), so most of it is thinner than the particles",
                  in_mm(r), 100.0 * (1.0 - start_m2 / scan_m2), in_mm2(scan_m2 - start_m2), in_mm2(scan_m2),
                  in_mm2(start_m2));
    throw InputError(p.source_file, "x_mm,y_mm", buf);
  }
  const double thinnest = thinnest_part(lifter_of_surface(unit.surface, p.source_file, "x_mm,y_mm"), 0.25 * needed);
  if (thinnest < needed) refuse_thin_lifter(scene, file, kind, needed, thinnest, true);
  // The history starts from the re-smoothed lifter, a little lower than the scan's highest
  // point (which the scene reader compares with): a replacement height between the two would
  // give a life that ended before the history began.
  const double start_height_m = measure_lifter(unit, scene.radius_m()).height_m;
  if (!(scene.wear.replacement_height_m < start_height_m)) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "expected a height below the measured lifter's as the history starts from it, %.4g mm (%s "
                  "re-smoothed at "
                  "%.3g mm, wear.smoothing_radius), got %.4g mm",
                  in_mm(start_height_m), p.source_file.c_str(), r * 1e3, in_mm(scene.wear.replacement_height_m));
    throw InputError(file, "wear.replacement_height", buf);
  }
}

void check_smoothing_radius(const Scene& scene, const std::string& file, int kind) {
  check_measured_features(scene, file, kind);
  const double r = smoothing_radius(scene);
  auto too_much = [&](double radius) {
    const SmoothingLoss l = smoothing_loss(scene, radius, kind);
    return l.area_fraction > kMaxSmoothingAreaLoss || l.height_fraction > kMaxSmoothingHeightLoss;
  };
  if (r <= 0.0 || !too_much(r)) return;
  // Bisect for the largest radius within the bounds (to 1% of r; 0 when even a tiny one is not).
  double lo = 0.0, hi = r;
  for (int i = 0; i < 12 && hi - lo > 0.01 * r; ++i) {
    const double mid = 0.5 * (lo + hi);
    (too_much(mid) ? hi : lo) = mid;
  }
  const SmoothingLoss l = smoothing_loss(scene, r, kind);
  const LifterProfile& profile = scene.mill.kind(kind);
  const std::string measured =
      profile.measured.empty() ? "" : " (measured profile " + profile.source_file + ")";
  char buf[640];
  if (lo <= 0.0) {
    // Not a radius problem: the lifter as meshed does not survive any re-smoothing.
    const SmoothingLoss at_hi = smoothing_loss(scene, hi, kind);
    if (!at_hi.failure.empty())
      std::snprintf(buf, sizeof buf,
                    "a lifter that survives re-smoothing: even at %.2g mm it leaves no valid surface%s (%.300s); "
                    "look at the profile and at lifters.lifter_edge",
                    hi * 1e3, measured.c_str(), at_hi.failure.c_str());
    else
      std::snprintf(buf, sizeof buf,
                    "a lifter that survives re-smoothing: even at %.2g mm it removes over %.0f%% of the new lifter%s "
                    "(at %.3g mm: %.0f%% of its area, %.0f%% of its height); look at the profile and at "
                    "lifters.lifter_edge",
                    hi * 1e3, 100.0 * kMaxSmoothingAreaLoss, measured.c_str(), r * 1e3, 100.0 * l.area_fraction,
                    100.0 * l.height_fraction);
    throw InputError(file, "wear.smoothing_radius", buf);
  }
  if (!l.failure.empty()) {
    // Not a share removed: the re-smoothed surface is no lifter surface at all (an overhang
    // the offset closes over, say); say why, not that the radius is too wide.
    std::snprintf(buf, sizeof buf,
                  "a smoothing radius of at most %.3g mm for this lifter%s: re-smoothing the new lifter at %.3g mm "
                  "leaves no valid surface (%.300s)",
                  lo * 1e3, measured.c_str(), r * 1e3, l.failure.c_str());
    throw InputError(file, "wear.smoothing_radius", buf);
  }
  std::snprintf(buf, sizeof buf,
                "a smoothing radius of at most %.3g mm for this lifter%s: re-smoothing the new lifter at %.3g mm "
                "removes %.0f%% of its area and %.0f%% of its height before any wear (the radius is wider than half "
                "its narrowest part; bounds %.0f%% and %.0f%%)%s",
                lo * 1e3, measured.c_str(), r * 1e3, 100.0 * l.area_fraction, 100.0 * l.height_fraction, 100.0 * kMaxSmoothingAreaLoss,
                100.0 * kMaxSmoothingHeightLoss,
                scene.wear.smoothing_radius_m > 0.0 ? "" : "; the default is the smallest particle radius: set "
                                                           "wear.smoothing_radius");
  throw InputError(file, "wear.smoothing_radius", buf);
}

std::vector<LinerUnit> reshape(const std::vector<LinerUnit>& units, const std::vector<std::vector<double>>& depths,
                               double radius_m, double smoothing_m, const MillMeshDef& mesh, double new_area_m2,
                               int stage) {
  const std::string at = "stage " + std::to_string(stage) + ": ";
  for (const auto& unit_depths : depths)
    for (double d : unit_depths)
      if (!std::isfinite(d)) throw NumericalError(at + "a wear depth is not finite (the shear work went non-finite)");
  std::vector<LinerUnit> worn(units.size());
  for (std::size_t u = 0; u < units.size(); ++u) {
    try {
      worn[u] = apply_wear(units[u], depths[u], radius_m, smoothing_m, mesh);
    } catch (const RunError& e) {
      throw NumericalError(at + e.what() + " (a numerical failure of the wear update, not wear-out; a finer mesh or "
                     "a smaller wear.max_depth_step may avoid it)");
    }
    // A smoothing radius wider than a feature the worn lifter grew (a thin ridge left
    // between two wear grooves) takes it without any shear work. Stop with the limit
    // rather than report it as wear. (The update never adds metal or raises the lifter:
    // apply_wear cuts everything back to the surface before it.)
    const double lost = resmoothing_loss_m2(units[u], worn[u], depths[u], radius_m);
    if (lost > kMaxSmoothingAreaLoss * new_area_m2) {
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "stage %d: re-smoothing at wear.smoothing_radius %.3g mm removed %.1f%% of the new lifter's "
                    "area beyond the wear itself (bound %.0f%%): the worn lifter has a feature narrower than "
                    "twice the radius; lower wear.smoothing_radius",
                    stage, in_mm(smoothing_m), 100.0 * lost / new_area_m2, 100.0 * kMaxSmoothingAreaLoss);
      throw NumericalError(buf);
    }
  }
  return worn;
}

}  // namespace millwear
