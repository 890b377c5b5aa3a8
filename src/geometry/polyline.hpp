#pragma once
// Polylines and polygons as plain vectors of points, and the tools the wear loop needs:
// area, orientation, simplicity, resampling, and re-smoothing by opening and closing with a disk (CGAL stays
// inside polyline.cpp and offset.cpp).
#include <vector>

#include "geometry/vec2.hpp"

namespace millwear {

using Polyline = std::vector<Vec2>;  // open chain of points
using Polygon = std::vector<Vec2>;   // closed ring, last point not repeated

// Signed area (shoelace): positive for counter-clockwise rings.
double signed_area(const Polygon& ring);
double area(const Polygon& ring);
bool is_counter_clockwise(const Polygon& ring);
// Centroid of the region enclosed by the ring.
Vec2 centroid(const Polygon& ring);
// Simple: no two non-adjacent edges touch, no repeated points (CGAL::is_simple_2).
bool is_simple(const Polygon& ring);
// An open polyline does not cross itself.
bool is_simple_open(const Polyline& line);

// The polyline with every loop cut out: where an edge crosses a later one, the part between
// the two goes and the line runs on from the crossing. What moving a surface into the metal
// by more than a convex corner's radius leaves (a swallowtail) is such a loop. With
// `largest`, the loop of largest area cut (its ring, crossing point first; empty if none).
Polyline without_loops(const Polyline& line, Polygon* largest = nullptr);

// The line's points at least min_spacing apart: a point closer than that to the last one
// kept is dropped; both ends are kept (the one before the last end goes if it is too close).
Polyline thin_points(const Polyline& line, double min_spacing);

double polyline_length(const Polyline& line);

// Resample an open polyline to edges of about target_length, keeping both end points and
// every vertex whose turning angle exceeds keep_corner_deg (lifter corners stay sharp).
Polyline resample(const Polyline& line, double target_length, double keep_corner_deg = 20.0);

// Point on a polyline at arc length s (clamped to the ends).
Vec2 point_at_length(const Polyline& line, double s);

// Shortest distance from p to the polyline (any segment).
double distance_to_polyline(Vec2 p, const Polyline& line);

// The thinnest part of the metal under an open surface (a lifter profile running left to
// right over a flat shell: the metal is the region between the surface and the straight line
// joining its ends). Found on points `spacing` apart along the surface: the smallest distance
// between two of them that face each other across the metal, i.e. whose straight join runs
// through the metal while the surface between them runs more than twice as far (a ridge,
// tooth or spike, as opposed to the two sides of a corner). Infinity if the metal has no such
// part. Accurate to about `spacing`; at most 4000 points are used.
double thinnest_part(const Polyline& surface, double spacing);

// Whether p lies inside a polygon (even-odd rule; a point on the boundary may go either way).
bool contains(const Polygon& ring, Vec2 p);

// Sutherland-Hodgman clip of a ring against the half-plane keep(p) >= 0, with keep linear.
// For a convex clip window the signed area and moments of the output are exactly those of the
// clipped region (any zero-width bridges contribute nothing).
template <class F>
Polygon clip_half_plane(const Polygon& ring, F keep) {
  Polygon out;
  const std::size_t n = ring.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = ring[i], b = ring[(i + 1) % n];
    const double fa = keep(a), fb = keep(b);
    if (fa >= 0.0) out.push_back(a);
    if ((fa >= 0.0) != (fb >= 0.0)) out.push_back(a + (fa / (fa - fb)) * (b - a));
  }
  return out;
}

// The region between a surface (a polyline along x) and the line y = 0 below it: the surface
// closed far under its lowest point, then clipped to y >= 0, so what of the surface lies
// under y = 0 adds nothing. A lifter's metal above the shell line; callers clip it in x.
Polygon region_above_zero(const Polyline& surface);

// Morphological smoothing of a simple polygon with a disk of radius r (a regular 32-gon,
// exact Minkowski sums): an opening (erode r, dilate r) rounds convex corners to radius r and
// removes ridges narrower than 2r, never adding metal; then a closing (dilate r, erode r)
// rounds concave corners and fills notches narrower than 2r. Both are idempotent: a polygon
// smoothed once comes back unchanged (up to the removal of collinear vertices). Returns the
// largest piece if the opening splits the polygon; cavities enclosed by the closing are
// filled; returns an empty polygon if nothing survives. Input orientation is kept; r <= 0
// returns the input without repeated points. Throws RunError if the input is not simple.
Polygon smooth_by_offsets(const Polygon& ring, double r);

// The largest piece of the intersection of two simple polygons (exact Boolean operation), in
// the first one's orientation; empty if they do not overlap. Throws RunError if either is not
// simple.
Polygon intersect_largest(const Polygon& a, const Polygon& b);

}  // namespace millwear
