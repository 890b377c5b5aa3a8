#pragma once
// Polylines and polygons as plain vectors of points, and the tools the wear loop needs:
// area, orientation, simplicity, resampling, and re-smoothing by polygon offsets (CGAL stays
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

double polyline_length(const Polyline& line);
// Cumulative arc length at each vertex (first is 0).
std::vector<double> cumulative_length(const Polyline& line);

// Resample an open polyline to edges of about target_length, keeping both end points and
// every vertex whose turning angle exceeds keep_corner_deg (lifter corners stay sharp).
Polyline resample(const Polyline& line, double target_length, double keep_corner_deg = 20.0);

// Point on a polyline at arc length s (clamped to the ends).
Vec2 point_at_length(const Polyline& line, double s);

// Shortest distance from p to the polyline (any segment).
double distance_to_polyline(Vec2 p, const Polyline& line);

// Morphological smoothing of a simple polygon by straight-skeleton offsets with radius r:
// an opening (inset r, outset r) removes spikes and ridges narrower than 2r, then a closing
// (outset r, inset r) fills notches narrower than 2r. Straight-skeleton offsets are mitred,
// so a convex polygon (or any polygon without features narrower than 2r) comes back
// unchanged up to rounding, and the result is again a simple polygon with straight edges
// (combinatorics from exact predicates, vertices in double): repeated calls in a wear loop
// do not creep. Returns the largest piece if the opening splits the polygon; cavities
// enclosed by the closing's outset are filled; returns an empty polygon if nothing
// survives. Input orientation is kept; r <= 0 returns the input. Throws RunError if the
// input is not simple. Cost grows about as n^2 (some 2 s for a 1800-vertex mill ring), so
// smooth the part that wore rather than the whole ring when that matters.
Polygon smooth_by_offsets(const Polygon& ring, double r);

}  // namespace millwear
