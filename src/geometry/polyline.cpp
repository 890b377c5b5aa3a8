// Plain polyline and polygon tools: shoelace moments, lengths, resampling, distances.
// The only CGAL use here is the simplicity test (exact predicates, so a ring that touches
// itself by rounding is caught); offsets live in offset.cpp to keep this unit small.
#include "common/units.hpp"
#include "geometry/edge_tree.hpp"
#include "geometry/polyline.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace millwear {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using KPoint = Kernel::Point_2;


// Segments [a,b] and [c,d] share a point (exact orientation predicates on double input).
bool segments_touch(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const Kernel::Segment_2 s1(KPoint(a.x, a.y), KPoint(b.x, b.y));
  const Kernel::Segment_2 s2(KPoint(c.x, c.y), KPoint(d.x, d.y));
  return CGAL::do_intersect(s1, s2);
}

// Whether segment [a,b] crosses [c,d] (in doubles; parallel segments do not), and where:
// a + t (b - a).
bool segments_cross_at(Vec2 a, Vec2 b, Vec2 c, Vec2 d, double& t) {
  const Vec2 r = b - a, q = d - c;
  const double den = cross(r, q);
  if (den == 0.0) return false;
  const double tt = cross(c - a, q) / den, u = cross(c - a, r) / den;
  if (!(tt >= 0.0 && tt <= 1.0 && u >= 0.0 && u <= 1.0)) return false;
  t = tt;
  return true;
}

// Closest point on segment [a,b] to p.
Vec2 closest_on_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double l2 = length_sq(ab);
  if (l2 <= 0.0) return a;
  const double t = std::clamp(dot(p - a, ab) / l2, 0.0, 1.0);
  return a + t * ab;
}

// Split the sub-chain line[i0..i1] (arc length L) into n equal-arc-length edges and append
// the interior points and the end point (the start point is already in out).
void append_run(const Polyline& line, std::size_t i0, std::size_t i1, double target_length,
                Polyline& out) {
  const Polyline run(line.begin() + static_cast<std::ptrdiff_t>(i0),
                     line.begin() + static_cast<std::ptrdiff_t>(i1) + 1);
  const double run_length = polyline_length(run);
  const int n = std::max(1, static_cast<int>(std::lround(run_length / target_length)));
  for (int j = 1; j < n; ++j) out.push_back(point_at_length(run, run_length * j / n));
  out.push_back(run.back());
}

}  // namespace

double signed_area(const Polygon& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return 0.0;
  double twice = 0.0;
  for (std::size_t i = 0; i < n; ++i) twice += cross(ring[i], ring[(i + 1) % n]);
  return 0.5 * twice;
}

double area(const Polygon& ring) { return std::abs(signed_area(ring)); }

bool is_counter_clockwise(const Polygon& ring) { return signed_area(ring) > 0.0; }

Vec2 centroid(const Polygon& ring) {
  const std::size_t n = ring.size();
  double twice_area = 0.0;
  Vec2 m{};
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % n];
    const double c = cross(a, b);
    twice_area += c;
    m += c * (a + b);
  }
  if (twice_area == 0.0) {
    // Degenerate ring: fall back to the vertex mean so callers get a finite point.
    Vec2 s{};
    for (const Vec2& p : ring) s += p;
    return n ? s / static_cast<double>(n) : s;
  }
  return m / (3.0 * twice_area);
}

bool is_simple(const Polygon& ring) {
  if (ring.size() < 3) return false;
  std::vector<KPoint> pts;
  pts.reserve(ring.size());
  for (const Vec2& p : ring) pts.emplace_back(p.x, p.y);
  // CGAL::is_simple_2 rejects repeated points and any touching of non-adjacent edges.
  return CGAL::is_simple_2(pts.begin(), pts.end(), Kernel());
}

Polygon region_above_zero(const Polyline& surface) {
  if (surface.empty()) return {};
  double ymin = 0.0;
  for (const Vec2& p : surface) ymin = std::min(ymin, p.y);
  Polygon region = surface;
  region.push_back({surface.back().x, ymin - 1.0});
  region.push_back({surface.front().x, ymin - 1.0});
  return clip_half_plane(region, [](Vec2 p) { return p.y; });
}

bool is_simple_open(const Polyline& line) {
  const std::size_t n = line.size();
  if (n < 2) return true;
  for (std::size_t i = 0; i + 1 < n; ++i)
    if (line[i] == line[i + 1]) return false;  // zero-length edge
  // Adjacent edges share line[i + 1]; they must not fold back onto each other.
  for (std::size_t i = 0; i + 2 < n; ++i) {
    const Vec2 u = line[i] - line[i + 1], v = line[i + 2] - line[i + 1];
    if (cross(u, v) == 0.0 && dot(u, v) > 0.0) return false;
  }
  // Any other two edges must not touch. Edges that touch have boxes that meet (the boxes of
  // double coordinates are exact), so only those are tested.
  const EdgeTree tree(line, 0.0);
  const std::size_t edges = tree.edge_count();
  for (std::size_t i = 0; i + 2 < edges; ++i) {
    const Vec2 a = line[i], b = line[i + 1];
    const auto touches = [&](std::size_t j) { return segments_touch(a, b, line[j], line[j + 1]); };
    if (tree.last_hit(box_of(a, b), i + 2, edges - 1, touches) != EdgeTree::kNone) return false;
  }
  return true;
}

Polyline without_loops(const Polyline& line, Polygon* largest) {
  if (largest) largest->clear();
  double largest_m2 = 0.0;
  Polyline out;
  out.reserve(line.size());
  const std::size_t n = line.size();
  if (n == 0) return out;
  out.push_back(line[0]);
  // The edges' boxes, grown by a millionth of the line's extent: an edge whose box misses the
  // current edge's by more than that cannot pass the crossing test below, whatever its
  // rounding, so only edges whose boxes meet are tested (the same edge is found as by
  // testing every one).
  double extent = 0.0;
  for (const Vec2& p : line) extent = std::max({extent, std::abs(p.x), std::abs(p.y)});
  const EdgeTree tree(line, 1e-6 * extent);
  // The current edge runs from out.back() to line[k]: after a cut it starts at the crossing,
  // and that remainder of the crossed edge is tested against the edges after it too.
  std::size_t k = 1;
  while (k < n) {
    const Vec2 a = out.back(), b = line[k];
    // The last edge j >= k + 1 that crosses the current edge: the loop between them goes.
    double t = 0.0;
    const auto crosses = [&](std::size_t j) { return segments_cross_at(a, b, line[j], line[j + 1], t); };
    std::size_t cut = k + 2 < n ? tree.last_hit(box_of(a, b), k + 1, n - 2, crosses) : EdgeTree::kNone;
    if (cut == EdgeTree::kNone) cut = n;
    const Vec2 at = a + t * (b - a);
    if (cut == n) {
      out.push_back(b);
      ++k;
      continue;
    }
    if (largest) {
      Polygon loop{at};
      loop.insert(loop.end(), line.begin() + static_cast<std::ptrdiff_t>(k),
                  line.begin() + static_cast<std::ptrdiff_t>(cut) + 1);
      const double area = std::abs(signed_area(loop));
      if (area > largest_m2) {
        largest_m2 = area;
        *largest = std::move(loop);
      }
    }
    if (!(at == out.back())) out.push_back(at);
    // Go on from the crossing along edge `cut` (past its end if the crossing is it).
    k = cut + 1;
    if (k < n && line[k] == out.back()) ++k;
  }
  return out;
}

Polyline thin_points(const Polyline& line, double min_spacing) {
  if (line.size() < 3) return line;
  Polyline out{line.front()};
  for (std::size_t i = 1; i + 1 < line.size(); ++i)
    if (length(line[i] - out.back()) >= min_spacing) out.push_back(line[i]);
  if (out.size() > 1 && length(line.back() - out.back()) < min_spacing) out.pop_back();
  out.push_back(line.back());
  return out;
}

double polyline_length(const Polyline& line) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) s += length(line[i + 1] - line[i]);
  return s;
}

Polyline resample(const Polyline& line, double target_length, double keep_corner_deg) {
  if (!(target_length > 0.0)) throw std::invalid_argument("resample: target_length must be > 0");
  // Drop zero-length edges first: they have no direction and would make a false corner.
  Polyline pts;
  pts.reserve(line.size());
  for (const Vec2& p : line)
    if (pts.empty() || !(p == pts.back())) pts.push_back(p);
  if (pts.size() < 2) return pts;

  // Kept vertices: both ends and every vertex where the direction turns by more than the
  // corner threshold (lifter feet and top corners stay sharp; gently curved runs are not).
  const double keep_rad = rad_from_deg(keep_corner_deg);
  std::vector<std::size_t> kept{0};
  for (std::size_t i = 1; i + 1 < pts.size(); ++i) {
    const Vec2 u = pts[i] - pts[i - 1], v = pts[i + 1] - pts[i];
    const double turn = std::atan2(std::abs(cross(u, v)), dot(u, v));
    if (turn > keep_rad) kept.push_back(i);
  }
  kept.push_back(pts.size() - 1);

  Polyline out{pts.front()};
  for (std::size_t k = 0; k + 1 < kept.size(); ++k)
    append_run(pts, kept[k], kept[k + 1], target_length, out);
  return out;
}

Vec2 point_at_length(const Polyline& line, double s) {
  if (line.empty()) return {};
  if (s <= 0.0) return line.front();
  double acc = 0.0;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const double l = length(line[i + 1] - line[i]);
    if (acc + l >= s && l > 0.0) return line[i] + ((s - acc) / l) * (line[i + 1] - line[i]);
    acc += l;
  }
  return line.back();
}

double distance_to_polyline(Vec2 p, const Polyline& line) {
  if (line.empty()) return INFINITY;
  if (line.size() == 1) return length(p - line[0]);
  double best = INFINITY;
  for (std::size_t i = 0; i + 1 < line.size(); ++i)
    best = std::min(best, length(p - closest_on_segment(p, line[i], line[i + 1])));
  return best;
}

}  // namespace millwear
