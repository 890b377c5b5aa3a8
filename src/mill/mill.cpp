// The mill's inner boundary from liner units, and lifter metrics against the shell circle.
#include "common/units.hpp"
#include "mill/mill.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "profiles/profile.hpp"

namespace millwear {

namespace {

// Edge-ownership slack: a vertical lifter face has its edge midpoints exactly at the foot
// x; 1 nm is far below any mesh edge and far above rounding of metre-scale coordinates.
constexpr double kOwnerTolM = 1e-9;

// A measured scan's points are kept at least this fraction of the lifter's edge length apart
// in the liner: finer than any mesh edge made from them, coarser than a gauge's step.
constexpr double kScanSpacingPerEdge = 1.0 / 8.0;

double row_angle(int row, int rows) { return 2.0 * kPi * row / rows; }

// Points of a straight run from a to b in n equal edges, n >= 1: b always, a when include_first.
void append_straight(Polyline& out, Vec2 a, Vec2 b, double target, bool include_first) {
  const int n = std::max(1, static_cast<int>(std::lround(length(b - a) / target)));
  if (include_first) out.push_back(a);
  for (int j = 1; j < n; ++j) out.push_back(a + (static_cast<double>(j) / n) * (b - a));
  out.push_back(b);
}

// The part of an open polyline inside x in [x0, x1], assuming x is monotone enough that the
// strip cuts it once at each side (true for a liner unit: shell, lifter, shell).
Polyline clip_polyline_x(const Polyline& line, double x0, double x1) {
  Polyline out;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    Vec2 a = line[i], b = line[i + 1];
    const double lo = std::min(a.x, b.x), hi = std::max(a.x, b.x);
    if (hi < x0 || lo > x1) continue;
    auto at_x = [&](double x) {
      const double t = (b.x == a.x) ? 0.0 : (x - a.x) / (b.x - a.x);
      return Vec2{x, a.y + t * (b.y - a.y)};
    };
    if (a.x < x0) a = at_x(x0);
    if (a.x > x1) a = at_x(x1);
    Vec2 bb = b;
    if (b.x < x0) bb = at_x(x0);
    if (b.x > x1) bb = at_x(x1);
    if (out.empty() || !(out.back() == a)) out.push_back(a);
    if (!(out.back() == bb)) out.push_back(bb);
  }
  return out;
}

// Trim the lifter's part of a (possibly worn) surface to its feet: walking in from each end,
// the foot is where the surface last leaves y <= 0 before the face reaches half the height
// (or the strip edge if it never touches the shell). measure_profile then measures the faces
// exactly as for a new profile.
Polyline trim_to_feet(const Polyline& c, double height) {
  const double y_half = 0.5 * height;
  std::size_t first_up = 0, last_up = c.size() - 1;
  while (first_up < c.size() && c[first_up].y < y_half) ++first_up;
  while (last_up > 0 && c[last_up].y < y_half) --last_up;
  if (first_up >= c.size() || last_up < first_up) return c;

  auto crossing = [](Vec2 a, Vec2 b) {  // point at y = 0 on [a, b], a.y <= 0 < b.y
    const double t = (0.0 - a.y) / (b.y - a.y);
    return Vec2{a.x + t * (b.x - a.x), 0.0};
  };
  Polyline out;
  std::size_t i0 = 0;
  for (std::size_t j = first_up; j-- > 0;) {
    if (c[j].y <= 0.0) {
      out.push_back(crossing(c[j], c[j + 1]));
      i0 = j + 1;
      break;
    }
  }
  if (out.empty()) out.push_back(c[0]), i0 = 1;
  std::size_t i1 = c.size() - 1;
  Vec2 right_foot = c.back();
  for (std::size_t j = last_up + 1; j < c.size(); ++j) {
    if (c[j].y <= 0.0) {
      right_foot = crossing(c[j], c[j - 1]);
      i1 = j;  // exclusive
      break;
    }
  }
  for (std::size_t j = i0; j < i1; ++j) out.push_back(c[j]);
  out.push_back(right_foot);
  return out;
}

}  // namespace

Vec2 local_to_mill(Vec2 local, int row, int rows, double radius_m) {
  const double theta = row_angle(row, rows) + local.x / radius_m;
  const double r = radius_m - local.y;
  return {r * std::cos(theta), r * std::sin(theta)};
}

Vec2 mill_to_local(Vec2 mill, int row, int rows, double radius_m) {
  double dtheta = std::atan2(mill.y, mill.x) - row_angle(row, rows);
  dtheta = std::remainder(dtheta, 2.0 * kPi);  // into [-pi, pi]
  return {radius_m * dtheta, radius_m - length(mill)};
}

bool deeper_than_liner_surface(const MillGeometry& mill, Vec2 p_mill, double depth_m) {
  const int rows = mill.rows;
  if (rows <= 0 || mill.units.empty()) return false;
  const double pitch_angle = 2.0 * kPi / rows;
  int row = static_cast<int>(std::lround(std::atan2(p_mill.y, p_mill.x) / pitch_angle));
  row = ((row % rows) + rows) % rows;
  const Vec2 local = mill_to_local(p_mill, row, rows, mill.radius_m);
  const Polyline& surf = mill.units[mill.unit_of_row(row)].surface;
  for (std::size_t e = 0; e + 1 < surf.size(); ++e) {
    const Vec2 a = surf[e], b = surf[e + 1];
    if ((local.x - a.x) * (local.x - b.x) > 0.0 || a.x == b.x) continue;
    const double y_surface = a.y + (b.y - a.y) * (local.x - a.x) / (b.x - a.x);
    return local.y < y_surface - depth_m;
  }
  return false;
}

namespace {

// A lifter half_extent either side of its centre and height tall must fit its row's pitch
// and stay under half the mill radius.
void check_lifter_fits(double half_extent, double height, double radius_m, int rows) {
  const double pitch = 2.0 * kPi * radius_m / rows;
  if (!(2.0 * half_extent < pitch))
    throw InputError("", "lifters.rows",
                     "expected lifters that fit the pitch: " + std::to_string(rows) + " rows give a pitch of " +
                         short_number(pitch * 1e3) + " mm along the shell, the lifter is " +
                         short_number(2.0 * half_extent * 1e3) + " mm wide");
  if (!(height < 0.5 * radius_m))
    throw InputError("", "lifters.profile",
                     "expected a lifter lower than half the mill radius (" + short_number(0.5 * radius_m * 1e3) +
                         " mm), got " + short_number(height * 1e3) + " mm");
}

void check_rows_and_radius(double radius_m, int rows) {
  if (rows < 1) throw InputError("", "lifters.rows", "expected at least 1 row of lifters");
  if (!(radius_m > 0.0)) throw InputError("", "mill.radius", "expected a radius > 0");
}

}  // namespace

LinerUnit make_liner_unit(const Polyline& lifter_local, double radius_m, int rows,
                          const MillMeshDef& mesh) {
  check_rows_and_radius(radius_m, rows);
  if (!(mesh.lifter_edge_m > 0.0) || !(mesh.shell_edge_m > 0.0))
    throw InputError("", "mesh", "expected positive target edge lengths");
  validate_lifter_polyline(lifter_local, "", "lifters.profile");

  // Centre the base on x = 0 so the lifter sits in the middle of its row and ownership by
  // |x| works for profiles drawn off-centre.
  Polyline lifter = lifter_local;
  const double shift = -0.5 * (lifter.front().x + lifter.back().x);
  double half_extent = 0.0, height = 0.0;
  for (Vec2& p : lifter) {
    p.x += shift;
    half_extent = std::max(half_extent, std::abs(p.x));
    height = std::max(height, p.y);
  }

  check_lifter_fits(half_extent, height, radius_m, rows);
  const double pitch = 2.0 * kPi * radius_m / rows;

  LinerUnit unit;
  unit.lifter_half_base_m = half_extent;
  const Polyline faces = resample(lifter, mesh.lifter_edge_m);
  append_straight(unit.surface, {-0.5 * pitch, 0.0}, faces.front(), mesh.shell_edge_m, true);
  unit.surface.insert(unit.surface.end(), faces.begin() + 1, faces.end());
  append_straight(unit.surface, faces.back(), {0.5 * pitch, 0.0}, mesh.shell_edge_m, false);
  return unit;
}

double measured_unit_shift_m(const Polyline& lifter_local, bool whole_unit) {
  if (!whole_unit || lifter_local.size() < 2) return 0.0;
  return -0.5 * (lifter_local.front().x + lifter_local.back().x);
}

LinerUnit make_measured_unit(const Polyline& surface, const Polyline& lifter_local, double radius_m, int rows,
                             const MillMeshDef& mesh, bool whole_unit) {
  check_rows_and_radius(radius_m, rows);
  validate_lifter_polyline(lifter_local, "", "lifters.profile");
  // A scan of one lifter is in the surveys' frame (x = 0 the lifter's centre line) and stays
  // there: the midpoint of a worn lifter's feet is not its centre (a worn face moves its foot),
  // and moving the scan would leave the surveys compared with its history off by the move. A
  // whole unit's scan places its lifter anywhere in the period: centred on its base.
  const double shift = measured_unit_shift_m(lifter_local, whole_unit);
  Polyline s = surface;
  double half_extent = 0.0, height = 0.0;
  for (Vec2& p : s) p.x += shift;
  for (const Vec2& p : lifter_local) {
    half_extent = std::max(half_extent, std::abs(p.x + shift));
    height = std::max(height, p.y);
  }
  const double pitch = 2.0 * kPi * radius_m / rows;
  const double half_pitch = 0.5 * pitch;
  if (whole_unit && s.size() >= 2) {
    // One period of the liner's surface, the lifter anywhere in it: the scan repeated a
    // period either side (its last point and the next copy's first are the same place; a
    // gauge's small mismatch between them becomes one short step), then cut to the unit.
    const double period = s.back().x - s.front().x;
    Polyline periodic;
    for (double shift_x : {-period, 0.0, period})
      for (const Vec2& p : s) {
        const Vec2 q{p.x + shift_x, p.y};
        if (periodic.empty() || length(q - periodic.back()) > 1e-9) periodic.push_back(q);
      }
    s = periodic;
  }
  // A scan of a whole unit is the pitch wide up to the gauge's accuracy: 1% of the pitch.
  const double slack = 0.01 * pitch;
  if (!whole_unit && (s.front().x < -half_pitch - slack || s.back().x > half_pitch + slack))
    throw InputError("", "lifters.rows",
                     "expected a measured profile no wider than the pitch, centred on its lifter: " +
                         std::to_string(rows) + " rows give a pitch of " + short_number(pitch * 1e3) +
                         " mm, the profile reaches from " + short_number(s.front().x * 1e3) + " to " +
                         short_number(s.back().x * 1e3) + " mm about its lifter's centre");
  check_lifter_fits(half_extent, height, radius_m, rows);
  // Within the pitch (a whole unit's scan may overrun it by the slack).
  s = clip_polyline_x(s, -half_pitch, half_pitch);
  // The unit's ends sit at one height so the rows join without a step: the mean of the
  // surface's ends. A scan that stops short of the pitch continues along the shell.
  const double y_end = 0.5 * (s.front().y + s.back().y);
  // A scan denser than the mesh can show (points closer than an eighth of the lifter's edge
  // length) is thinned to that spacing first: resampling keeps every turn of the gauge's
  // noise as a corner, and a million-point scan would make a million-edge liner. Where
  // dropping points makes a chord cross the line, the loop is cut out as the reader does.
  s = without_loops(thin_points(s, kScanSpacingPerEdge * mesh.lifter_edge_m));
  const Polyline fine = resample(s, mesh.lifter_edge_m, 5.0);
  LinerUnit unit;
  unit.lifter_half_base_m = half_extent;
  const Vec2 left{-half_pitch, y_end}, right{half_pitch, y_end};
  const double min_run = 1e-3 * mesh.shell_edge_m;
  if (fine.front().x - left.x > min_run) append_straight(unit.surface, left, fine.front(), mesh.shell_edge_m, true);
  else unit.surface.push_back(left);
  unit.surface.insert(unit.surface.end(), fine.begin() + 1, fine.end() - 1);
  if (right.x - fine.back().x > min_run) append_straight(unit.surface, fine.back(), right, mesh.shell_edge_m, true);
  else unit.surface.push_back(right);
  if (!is_simple_open(unit.surface))
    throw InputError("", "lifters.profile", "expected a measured surface that does not cross itself");
  return unit;
}

MillGeometry build_mill(double radius_m, int rows, std::vector<LinerUnit> units, int kinds) {
  if (rows < 1 || kinds < 1 || rows % kinds != 0 ||
      !(units.size() == static_cast<std::size_t>(kinds) || units.size() == static_cast<std::size_t>(rows)))
    throw InputError("", "lifters.rows", "expected one liner unit per kind of lifter, or one per row");
  MillGeometry g;
  g.radius_m = radius_m;
  g.rows = rows;
  g.kinds = kinds;
  g.units = std::move(units);

  // Ring: every unit's surface mapped into the mill frame, minus its last point (which is
  // the next unit's first point: both sit at the half-way angle between two lifters).
  for (int k = 0; k < rows; ++k) {
    const LinerUnit& u = g.units[g.unit_of_row(k)];
    const double hb = u.lifter_half_base_m + kOwnerTolM;
    for (std::size_t j = 0; j + 1 < u.surface.size(); ++j) {
      g.boundary.push_back(local_to_mill(u.surface[j], k, rows, radius_m));
      LinerEdgeInfo e;
      e.row = k;
      e.unit_edge = static_cast<int>(j);
      const double xm = 0.5 * (u.surface[j].x + u.surface[j + 1].x);
      if (std::abs(xm) <= hb) {
        e.owner = EdgeOwner::Lifter;
        e.owner_index = k;
      } else {
        // Shell segment k runs from lifter k to lifter k+1: the right half-gap of row k and
        // the left half-gap of row k+1.
        e.owner = EdgeOwner::Shell;
        e.owner_index = xm > 0.0 ? k : (k + rows - 1) % rows;
      }
      g.edges.push_back(e);
    }
  }

  const std::size_t n = g.boundary.size();
  g.normal_out.resize(n);
  g.edge_length_m.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 d = g.boundary[(i + 1) % n] - g.boundary[i];
    g.edge_length_m[i] = length(d);
    // Ring is CCW with the charge on the left, so the right side is the liner metal.
    g.normal_out[i] = normalized(right_perp(d));
  }

  // Local arc length: walk the ring from the start of some owner run (an edge whose owner
  // differs from its predecessor's) so that every run is seen from its first edge.
  auto same_owner = [&](std::size_t a, std::size_t b) {
    return g.edges[a].owner == g.edges[b].owner &&
           g.edges[a].owner_index == g.edges[b].owner_index;
  };
  std::size_t start = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!same_owner(i, (i + n - 1) % n)) {
      start = i;
      break;
    }
  }
  double s = 0.0;
  for (std::size_t m = 0; m < n; ++m) {
    const std::size_t i = (start + m) % n;
    if (m > 0 && !same_owner(i, (i + n - 1) % n)) s = 0.0;
    g.edges[i].s_local_m = s + 0.5 * g.edge_length_m[i];
    s += g.edge_length_m[i];
  }
  return g;
}

LifterMetrics measure_lifter(const LinerUnit& unit, double radius_m) {
  LifterMetrics m;
  const Polyline& surf = unit.surface;
  if (surf.size() < 2) return m;
  const double hb = unit.lifter_half_base_m;

  // Region below the surface, closed far beneath the shell, then clipped to the original
  // base span and to y >= 0: the metal above the original shell circle.
  Polygon region = region_above_zero(surf);
  region = clip_half_plane(region, [hb](Vec2 p) { return p.x + hb; });
  region = clip_half_plane(region, [hb](Vec2 p) { return hb - p.x; });
  if (region.size() < 3) return m;

  // Polar map: dA_mill = (R - y) dx dy / R, so A = A_flat - (1/R) * integral of y dA, both
  // exact for a polygon from its shoelace moments.
  double a2 = 0.0, my6 = 0.0;
  const std::size_t n = region.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 p = region[i], q = region[(i + 1) % n];
    const double c = cross(p, q);
    a2 += c;
    my6 += c * (p.y + q.y);
  }
  const double a_flat = 0.5 * a2, m_y = my6 / 6.0;
  m.area_m2 = std::abs(a_flat - m_y / radius_m);

  const Polyline lifter = clip_polyline_x(surf, -hb, hb);
  for (const Vec2& p : lifter) m.height_m = std::max(m.height_m, p.y);
  if (!(m.height_m > 0.0) || lifter.size() < 2) {
    m.height_m = std::max(m.height_m, 0.0);
    return m;  // worn flat: no faces to measure
  }
  const ProfileMetrics pm = measure_profile(trim_to_feet(lifter, m.height_m));
  m.leading_face_angle_rad = pm.leading_face_angle_rad;
  m.trailing_face_angle_rad = pm.trailing_face_angle_rad;
  return m;
}

}  // namespace millwear
