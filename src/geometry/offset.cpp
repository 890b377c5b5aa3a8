// Re-smoothing by straight-skeleton offsets (CGAL stays in this file).
//
// Why the straight skeleton and not CGAL's exact arc offsets (offset_polygon_2 /
// approximated_offset_2): a skeleton offset moves every edge parallel to itself by exactly r
// and joins neighbours with a mitre, so
//   * the output is again a polygon with straight edges (no arcs to approximate, no growing
//     vertex count from rounded corners);
//   * inset r followed by outset r returns a convex polygon, or any polygon without
//     features narrower than 2r, to the same lines it started from: the opening and the
//     closing are idempotent there, so calling this after every wear stage does not make the
//     profile creep or round off lifter corners;
//   * only features that really vanish during the inset (spikes, ridges) or close during the
//     outset (notches) change.
// The skeleton uses Exact_predicates_inexact_constructions_kernel: the combinatorics are
// decided with exact predicates, the vertex positions are doubles.
#include "geometry/polyline.hpp"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/create_offset_polygons_2.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "common/errors.hpp"
#include "geometry/simplify.hpp"

namespace millwear {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CgalPolygon = CGAL::Polygon_2<Kernel>;

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

// Drop vertices within tol of the chain through their neighbours. Consecutive (nearly)
// collinear edges make simultaneous skeleton events, which CGAL 5.5's builder can crash on
// (MergeCoincidentNodes; CGAL issues 7203 and 7284, fixed in 5.6): a resampled worn liner
// has runs of them. Every skeleton input goes through this.
Polygon without_collinear(const Polygon& ring, double tol) {
  if (ring.size() <= 3) return ring;
  Polygon out;
  for (int i : simplify_ring(ring, tol)) out.push_back(ring[static_cast<std::size_t>(i)]);
  return out;
}

// Inset a CCW simple polygon by r; returns the largest piece (CCW), or empty if none survives.
Polygon inset_largest(const Polygon& ccw, double r) {
  const auto pieces = CGAL::create_interior_skeleton_and_offset_polygons_2(r, to_cgal(ccw));
  const CgalPolygon* best = nullptr;
  double best_area = 0.0;
  for (const auto& piece : pieces) {
    if (!piece) continue;
    const double a = CGAL::to_double(piece->area());
    // Interior offsets of a hole-free polygon are CCW outer contours; keep the largest.
    if (a > best_area) {
      best_area = a;
      best = piece.get();
    }
  }
  return best ? from_cgal(*best) : Polygon{};
}

// Outset a CCW simple polygon by r; returns the outer contour (CCW). CGAL computes the
// exterior offset inside a rectangular frame: the result holds the shrunk frame (CCW, the
// largest), the offset contour (CW, it is a hole of the frame) and, if the outset encloses
// a cavity, that cavity (CCW). The outer contour is the largest CW polygon; cavities are
// filled, which is what a closing wants.
Polygon outset_outer(const Polygon& ccw, double r) {
  const auto pieces = CGAL::create_exterior_skeleton_and_offset_polygons_2(r, to_cgal(ccw));
  const CgalPolygon* best = nullptr;
  double best_area = 0.0;
  for (const auto& piece : pieces) {
    if (!piece) continue;
    const double a = CGAL::to_double(piece->area());
    if (a < 0.0 && -a > best_area) {
      best_area = -a;
      best = piece.get();
    }
  }
  if (!best) throw RunError("smooth_by_offsets: the straight-skeleton outset failed");
  Polygon ring = from_cgal(*best);
  std::reverse(ring.begin(), ring.end());
  return ring;
}

}  // namespace

Polygon smooth_by_offsets(const Polygon& ring_in, double r) {
  Polygon ring = without_repeats(ring_in);
  if (!(r > 0.0)) return ring;  // radius 0: nothing to smooth
  if (!is_simple(ring))
    throw RunError("smooth_by_offsets: the polygon to smooth is not simple (" +
                   std::to_string(ring.size()) + " vertices)");
  const bool was_ccw = is_counter_clockwise(ring);
  if (!was_ccw) std::reverse(ring.begin(), ring.end());

  // Collinear within a ten-thousandth of the radius: far below any wear depth that matters.
  const double tol = 1e-4 * r;
  ring = without_collinear(ring, tol);
  // Opening: remove spikes and ridges narrower than 2r.
  Polygon opened = inset_largest(ring, r);
  if (opened.size() < 3) return {};
  opened = outset_outer(without_collinear(opened, tol), r);
  // Closing: fill notches narrower than 2r.
  Polygon closed = outset_outer(without_collinear(opened, tol), r);
  closed = inset_largest(without_collinear(closed, tol), r);
  if (closed.size() < 3) return {};

  if (!was_ccw) std::reverse(closed.begin(), closed.end());
  return closed;
}

}  // namespace millwear
