// Re-smoothing by morphological opening and closing with a disk (CGAL stays in this file).
//
// Why a disk and not a straight-skeleton offset: a skeleton offset moves
// each edge parallel to itself and joins neighbours with a mitre, so an inset followed by an
// outset brings back only the edges that survived the inset. A worn corner is a run of short
// edges bending round a radius smaller than r; the inset eats them, and the outset extends the
// two long edges either side until they meet in a sharp corner *outside* the worn surface:
// metal grew back where the charge had worn it (measured: 4 mm on a SAG 1x30's trailing
// corner after one 750 h stage), and a worn valley was cut sharp by the closing. Smoothing
// that sharpens every rounded feature feeds the wear noise back into the shape.
//
// With a disk D the opening (X erode D) dilate D is the union of every disk that fits in
// the metal: it rounds convex corners to radius r and removes ridges narrower than 2r, never
// adds metal, and is idempotent (smoothing again changes nothing). The closing is the same
// for the air side: it fills notches narrower than 2r and rounds concave corners. The disk is
// a regular kDiskSides-gon of circumradius r (symmetric, so erosion and dilation are dual),
// and the sums are CGAL's Minkowski sums in exact arithmetic (Epeck): the erosion is the
// hole left in a frame around the polygon when the frame's inside is dilated.
#include "common/units.hpp"
#include "geometry/polyline.hpp"

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>
#include <CGAL/minkowski_sum_2.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "common/errors.hpp"
#include "geometry/simplify.hpp"

namespace millwear {

namespace {

using Kernel = CGAL::Exact_predicates_exact_constructions_kernel;
using CgalPolygon = CGAL::Polygon_2<Kernel>;
using CgalPolygonWithHoles = CGAL::Polygon_with_holes_2<Kernel>;

// 32 sides: the polygon lies within 0.5% of r inside the circle (r (1 - cos(pi/32))), far
// below a wear step; each side turns 11.25 deg, over the 5 deg corner threshold the wear
// update resamples with (wear/reshape.cpp), so a rounded corner keeps its vertices.
constexpr int kDiskSides = 32;

CgalPolygon to_cgal(const Polygon& ring) {
  CgalPolygon p;
  for (const Vec2& v : ring) p.push_back(Kernel::Point_2(v.x, v.y));
  return p;
}

Polygon from_cgal(const CgalPolygon& p) {
  Polygon ring;
  ring.reserve(p.size());
  for (auto it = p.vertices_begin(); it != p.vertices_end(); ++it)
    ring.push_back({CGAL::to_double(it->x()), CGAL::to_double(it->y())});
  return ring;
}

// Drop repeated consecutive points (including last == first), which have no edge direction.
Polygon without_repeats(const Polygon& ring) {
  Polygon out;
  out.reserve(ring.size());
  for (const Vec2& p : ring)
    if (out.empty() || !(p == out.back())) out.push_back(p);
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
  return out;
}

// Drop vertices within tol of the chain through their neighbours: the sums' outputs carry
// runs of collinear vertices (a straight edge swept by a disk side), which only cost time.
Polygon without_collinear(const Polygon& ring, double tol) {
  if (ring.size() <= 3) return ring;
  Polygon out;
  for (int i : simplify_ring(ring, tol)) out.push_back(ring[static_cast<std::size_t>(i)]);
  return out;
}

CgalPolygon disk(double r) {
  CgalPolygon d;
  for (int i = 0; i < kDiskSides; ++i) {
    const double a = 2.0 * kPi * i / kDiskSides;
    d.push_back(Kernel::Point_2(r * std::cos(a), r * std::sin(a)));
  }
  return d;
}

// Dilation of a CCW simple polygon: the outer boundary of P + D (CCW). Cavities the sum
// encloses are filled, which is what a closing wants.
Polygon dilate(const Polygon& ccw, const CgalPolygon& d) {
  const CgalPolygonWithHoles sum = CGAL::minkowski_sum_2(to_cgal(ccw), d);
  return from_cgal(sum.outer_boundary());
}

// Erosion of a CCW simple polygon: what stays of P when everything within r of the outside
// is taken away, i.e. the holes of (frame with P cut out) + D. Returns the largest piece
// (CCW), or empty if none survives.
Polygon erode(const Polygon& ccw, const CgalPolygon& d, double r) {
  double x0 = ccw[0].x, x1 = x0, y0 = ccw[0].y, y1 = y0;
  for (const Vec2& p : ccw) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  const double m = 4.0 * r;
  CgalPolygon frame;
  frame.push_back(Kernel::Point_2(x0 - m, y0 - m));
  frame.push_back(Kernel::Point_2(x1 + m, y0 - m));
  frame.push_back(Kernel::Point_2(x1 + m, y1 + m));
  frame.push_back(Kernel::Point_2(x0 - m, y1 + m));
  CgalPolygon hole = to_cgal(ccw);
  hole.reverse_orientation();
  CgalPolygonWithHoles outside(frame);
  outside.add_hole(hole);
  const CgalPolygonWithHoles sum = CGAL::minkowski_sum_2(outside, d);
  const CgalPolygon* best = nullptr;
  double best_area = 0.0;
  for (auto h = sum.holes_begin(); h != sum.holes_end(); ++h) {
    const double a = -CGAL::to_double(h->area());  // holes are clockwise
    if (a > best_area) {
      best_area = a;
      best = &*h;
    }
  }
  if (!best) return {};
  Polygon ring = from_cgal(*best);
  std::reverse(ring.begin(), ring.end());
  return ring;
}

Polygon prepared_ccw(const Polygon& ring_in, bool& was_ccw, const char* who) {
  Polygon ring = without_repeats(ring_in);
  if (ring.size() < 3 || !is_simple(ring))
    throw RunError(std::string(who) + ": the polygon is not simple (" + std::to_string(ring.size()) + " vertices)");
  was_ccw = is_counter_clockwise(ring);
  if (!was_ccw) std::reverse(ring.begin(), ring.end());
  return ring;
}

}  // namespace

Polygon smooth_by_offsets(const Polygon& ring_in, double r) {
  if (!(r > 0.0)) return without_repeats(ring_in);  // radius 0: nothing to smooth
  bool was_ccw = true;
  Polygon ring = prepared_ccw(ring_in, was_ccw, "smooth_by_offsets");
  // Collinear within a ten-thousandth of the radius: far below any wear depth that matters.
  const double tol = 1e-4 * r;
  const CgalPolygon d = disk(r);
  // Opening: round convex corners, remove ridges narrower than 2r.
  Polygon opened = erode(without_collinear(ring, tol), d, r);
  if (opened.size() < 3) return {};
  opened = dilate(without_collinear(opened, tol), d);
  // Closing: round concave corners, fill notches narrower than 2r.
  Polygon closed = dilate(without_collinear(opened, tol), d);
  closed = erode(without_collinear(closed, tol), d, r);
  if (closed.size() < 3) return {};
  closed = without_collinear(closed, tol);
  if (!was_ccw) std::reverse(closed.begin(), closed.end());
  return closed;
}

Polygon intersect_largest(const Polygon& a_in, const Polygon& b_in) {
  bool a_ccw = true, b_ccw = true;
  const Polygon a = prepared_ccw(a_in, a_ccw, "intersect_largest");
  const Polygon b = prepared_ccw(b_in, b_ccw, "intersect_largest");
  std::vector<CgalPolygonWithHoles> pieces;
  CGAL::intersection(to_cgal(a), to_cgal(b), std::back_inserter(pieces));
  const CgalPolygon* best = nullptr;
  double best_area = 0.0;
  for (const auto& p : pieces) {
    const double s = CGAL::to_double(p.outer_boundary().area());
    if (s > best_area) {
      best_area = s;
      best = &p.outer_boundary();
    }
  }
  if (!best) return {};
  Polygon out = from_cgal(*best);
  if (!a_ccw) std::reverse(out.begin(), out.end());
  return out;
}

}  // namespace millwear
