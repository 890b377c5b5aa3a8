// Polyline tools: shoelace moments, simplicity, resampling, straight-skeleton re-smoothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "geometry/polyline.hpp"

using namespace millwear;

namespace {

constexpr double kPi = 3.14159265358979323846;

Polygon regular_polygon(int n, double radius) {
  Polygon p;
  for (int i = 0; i < n; ++i) {
    const double t = 2.0 * kPi * i / n;
    p.push_back({radius * std::cos(t), radius * std::sin(t)});
  }
  return p;
}

double max_y(const Polygon& p) {
  double y = -INFINITY;
  for (const Vec2& v : p) y = std::max(y, v.y);
  return y;
}

// CCW rectangle [0, w] x [0, h] with a spike of the given base width and height on top at
// x = w/2.
Polygon rectangle_with_spike(double w, double h, double spike_w, double spike_h) {
  return {{0, 0}, {w, 0}, {w, h}, {0.5 * w + 0.5 * spike_w, h}, {0.5 * w, h + spike_h},
          {0.5 * w - 0.5 * spike_w, h}, {0, h}};
}

}  // namespace

TEST(Geometry, SignedAreaIsPositiveForCounterClockwiseSquare) {
  const Polygon sq{{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  EXPECT_DOUBLE_EQ(signed_area(sq), 4.0);
  EXPECT_TRUE(is_counter_clockwise(sq));
  Polygon cw(sq.rbegin(), sq.rend());
  EXPECT_DOUBLE_EQ(signed_area(cw), -4.0);
  EXPECT_FALSE(is_counter_clockwise(cw));
  const Vec2 c = centroid(sq);
  EXPECT_DOUBLE_EQ(c.x, 1.0);
  EXPECT_DOUBLE_EQ(c.y, 1.0);
}

TEST(Geometry, BowTieIsNotSimple) {
  EXPECT_TRUE(is_simple({{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
  EXPECT_FALSE(is_simple({{0, 0}, {1, 1}, {1, 0}, {0, 1}}));
  EXPECT_FALSE(is_simple({{0, 0}, {1, 0}, {1, 0}, {0, 1}}));  // repeated point
  EXPECT_TRUE(is_simple_open({{0, 0}, {1, 0}, {1, 1}}));
  EXPECT_FALSE(is_simple_open({{0, 0}, {2, 0}, {2, 1}, {1, -1}}));
}

TEST(Geometry, ResampleKeepsEndsAndCornersWithEqualEdges) {
  // An L: 1.0 along x, then 0.5 up. The 90 deg corner must stay; each leg gets equal edges.
  const Polyline l{{0, 0}, {0.3, 0}, {1.0, 0}, {1.0, 0.5}};
  const Polyline r = resample(l, 0.1);
  ASSERT_EQ(r.size(), 16u);  // 10 edges + 5 edges
  EXPECT_EQ(r.front(), l.front());
  EXPECT_EQ(r.back(), l.back());
  EXPECT_EQ(r[10], (Vec2{1.0, 0.0}));  // the corner is a vertex, exactly
  for (std::size_t i = 0; i + 1 < r.size(); ++i)
    EXPECT_NEAR(length(r[i + 1] - r[i]), 0.1, 1e-12);  // rounding of 1.0/10 etc.
  EXPECT_NEAR(polyline_length(r), 1.5, 1e-12);
}

TEST(Geometry, ResampleDoesNotKeepGentleBends) {
  // A bend of 10 deg is below the 20 deg corner threshold: it is not kept as a vertex.
  const Polyline l{{0, 0}, {1, 0}, {1 + std::cos(0.1745), std::sin(0.1745)}};
  const Polyline r = resample(l, 0.4);  // 5 edges of 0.4: no point falls on the bend
  ASSERT_EQ(r.size(), 6u);
  for (const Vec2& p : r) EXPECT_FALSE(p == l[1]);
}

TEST(Geometry, PointAtLengthAndDistanceToPolyline) {
  const Polyline l{{0, 0}, {1, 0}, {1, 1}};
  const Vec2 p = point_at_length(l, 1.5);
  EXPECT_DOUBLE_EQ(p.x, 1.0);
  EXPECT_DOUBLE_EQ(p.y, 0.5);
  EXPECT_EQ(point_at_length(l, 9.0), l.back());  // clamped
  EXPECT_DOUBLE_EQ(distance_to_polyline({0.5, -2.0}, l), 2.0);
  EXPECT_DOUBLE_EQ(distance_to_polyline({3.0, 0.5}, l), 2.0);
  const auto s = cumulative_length(l);
  EXPECT_DOUBLE_EQ(s.back(), 2.0);
}

TEST(Geometry, ResmoothingSmoothConvexProfileChangesAreaBelowHalfPercent) {
  // A 200-gon of radius 0.3 m (a smooth convex profile) smoothed with r = 10 mm. The issue
  // asks for < 0.5 % area change; a mitred opening/closing of a convex polygon should in fact
  // return it unchanged, so we also bound the vertex displacement by 1 um (rounding only).
  const Polygon ring = regular_polygon(200, 0.3);
  const Polygon out = smooth_by_offsets(ring, 0.01);
  ASSERT_GE(out.size(), 3u);
  EXPECT_LT(std::abs(area(out) - area(ring)) / area(ring), 0.005);
  for (const Vec2& v : out) EXPECT_LT(distance_to_polyline(v, Polyline(ring.begin(), ring.end())), 1e-6);
}

TEST(Geometry, ResmoothingTwiceDoesNotCreep) {
  // The wear loop smooths after every stage: the second pass must not move the profile.
  // Tolerance 1e-9 relative: double rounding of the skeleton constructions.
  const Polygon once = smooth_by_offsets(regular_polygon(120, 1.0), 0.02);
  const Polygon twice = smooth_by_offsets(once, 0.02);
  EXPECT_NEAR(area(twice), area(once), 1e-9 * area(once));
}

TEST(Geometry, ResmoothingRemovesSpikeNarrowerThanRadius) {
  // Spike 5 mm wide, 100 mm tall on a 200 mm high block; r = 10 mm > spike width.
  const Polygon ring = rectangle_with_spike(1.0, 0.2, 0.005, 0.1);
  ASSERT_GT(max_y(ring), 0.29);
  const Polygon out = smooth_by_offsets(ring, 0.01);
  ASSERT_GE(out.size(), 3u);
  // The top edge comes back to exactly y = 0.2 up to rounding (1e-9 m).
  EXPECT_LT(max_y(out), 0.2 + 1e-9);
  EXPECT_NEAR(area(out), 0.2, 1e-9);
}

TEST(Geometry, ResmoothingKeepsFeatureWiderThanDiameter) {
  // A 100 mm wide step is wider than 2r = 20 mm: it must survive the opening.
  const Polygon ring = rectangle_with_spike(1.0, 0.2, 0.1, 0.05);
  const Polygon out = smooth_by_offsets(ring, 0.01);
  EXPECT_NEAR(max_y(out), 0.25, 1e-9);
}

TEST(Geometry, ResmoothingResultIsSimpleAndKeepsOrientation) {
  // A wavy ring with a narrow notch and a narrow spike; CW input must come back CW.
  Polygon ring;
  for (int i = 0; i < 180; ++i) {
    const double t = 2.0 * kPi * i / 180;
    double r = 1.0 + 0.05 * std::sin(7 * t);
    if (i == 40) r += 0.3;   // spike, one vertex wide (about 35 mm)
    if (i == 100) r -= 0.3;  // notch
    ring.push_back({r * std::cos(t), r * std::sin(t)});
  }
  ASSERT_TRUE(is_simple(ring));
  const Polygon ccw = smooth_by_offsets(ring, 0.05);
  EXPECT_TRUE(is_simple(ccw));
  EXPECT_TRUE(is_counter_clockwise(ccw));
  const Polygon cw = smooth_by_offsets(Polygon(ring.rbegin(), ring.rend()), 0.05);
  EXPECT_TRUE(is_simple(cw));
  EXPECT_FALSE(is_counter_clockwise(cw));
  // The spike tip (r = 1.3 at i = 40) is gone: nothing is left beyond r = 1.06.
  for (const Vec2& v : ccw) EXPECT_LT(length(v), 1.06);
}

TEST(Geometry, ResmoothingKeepsLargestPieceWhenOpeningSplits) {
  // Two 1 x 1 squares joined by a 10 mm neck; the right one is larger (1.2 wide).
  const Polygon ring{{0, 0}, {1, 0}, {1, 0.495}, {1.5, 0.495}, {1.5, 0}, {2.7, 0},
                     {2.7, 1}, {1.5, 1}, {1.5, 0.505}, {1, 0.505}, {1, 1}, {0, 1}};
  const Polygon out = smooth_by_offsets(ring, 0.05);
  ASSERT_GE(out.size(), 3u);
  EXPECT_NEAR(area(out), 1.2, 1e-9);
  for (const Vec2& v : out) EXPECT_GE(v.x, 1.5 - 1e-9);
}

TEST(Geometry, ResmoothingReturnsEmptyWhenNothingSurvives) {
  const Polygon thin{{0, 0}, {1, 0}, {1, 0.01}, {0, 0.01}};
  EXPECT_TRUE(smooth_by_offsets(thin, 0.05).empty());
}
