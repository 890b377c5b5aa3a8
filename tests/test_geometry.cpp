// Polyline tools: shoelace moments, simplicity, resampling, re-smoothing with a disk.
#include <gtest/gtest.h>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "common/units.hpp"
#include "geometry/polyline.hpp"

using namespace millwear;

namespace {


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

// The crossing tests against every pair of edges, as a reference for the ones that test only
// the edges whose boxes meet: the same answers and the same cut line, point for point.
bool is_simple_open_every_pair(const Polyline& line) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  const std::size_t n = line.size();
  for (std::size_t i = 0; i + 1 < n; ++i)
    if (line[i] == line[i + 1]) return false;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    for (std::size_t j = i + 1; j + 1 < n; ++j) {
      if (j == i + 1) {
        const Vec2 u = line[i] - line[j], v = line[j + 1] - line[j];
        if (cross(u, v) == 0.0 && dot(u, v) > 0.0) return false;
        continue;
      }
      const K::Segment_2 s1({line[i].x, line[i].y}, {line[i + 1].x, line[i + 1].y});
      const K::Segment_2 s2({line[j].x, line[j].y}, {line[j + 1].x, line[j + 1].y});
      if (CGAL::do_intersect(s1, s2)) return false;
    }
  }
  return true;
}

Polyline without_loops_every_edge(const Polyline& line, Polygon* largest) {
  largest->clear();
  double largest_m2 = 0.0;
  const std::size_t n = line.size();
  Polyline out{line[0]};
  std::size_t k = 1;
  while (k < n) {
    const Vec2 a = out.back(), b = line[k];
    std::size_t cut = n;
    Vec2 at;
    for (std::size_t j = n - 1; j-- > k + 1;) {
      const Vec2 c = line[j], d = line[j + 1];
      const Vec2 r = b - a, q = d - c;
      const double den = cross(r, q);
      if (den == 0.0) continue;
      const double t = cross(c - a, q) / den, u = cross(c - a, r) / den;
      if (t >= 0.0 && t <= 1.0 && u >= 0.0 && u <= 1.0) {
        cut = j;
        at = a + t * r;
        break;
      }
    }
    if (cut == n) {
      out.push_back(b);
      ++k;
      continue;
    }
    Polygon loop{at};
    loop.insert(loop.end(), line.begin() + static_cast<std::ptrdiff_t>(k),
                line.begin() + static_cast<std::ptrdiff_t>(cut) + 1);
    if (std::abs(signed_area(loop)) > largest_m2) {
      largest_m2 = std::abs(signed_area(loop));
      *largest = loop;
    }
    if (!(at == out.back())) out.push_back(at);
    k = cut + 1;
    if (k < n && line[k] == out.back()) ++k;
  }
  return out;
}

// A gauge's scan of a lifter, in metres: 2,000 points up a face, across the top and down,
// each moved by noise of about the point spacing, so that it steps back over the points before
// it, in loops of every size.
Polyline noisy_scan(unsigned seed, double noise_m) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  const Polyline path{{-0.06, 0.0}, {-0.02, 0.0}, {-0.01, 0.02}, {0.01, 0.02}, {0.02, 0.0}, {0.06, 0.0}};
  const double total = polyline_length(path);
  Polyline line;
  for (int i = 0; i < 2000; ++i) {
    const Vec2 p = point_at_length(path, total * i / 1999.0);
    line.push_back({p.x + noise(rng), p.y + noise(rng)});
  }
  return line;
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

TEST(Geometry, WithoutLoopsCutsTheFoldOutAndKeepsASimpleLine) {
  // Along x, up and back down across the first edge, then on: the loop between the crossing
  // at (1, 0) goes.
  const Polyline folded{{0, 0}, {2, 0}, {1, 1}, {1, -1}, {3, -1}};
  EXPECT_FALSE(is_simple_open(folded));
  const Polyline cut = without_loops(folded);
  const Polyline expected{{0, 0}, {1, 0}, {1, -1}, {3, -1}};
  ASSERT_EQ(cut.size(), expected.size());
  for (std::size_t i = 0; i < cut.size(); ++i) EXPECT_NEAR(length(cut[i] - expected[i]), 0.0, 1e-15) << i;
  // A simple line comes back as it was.
  const Polyline l{{0, 0}, {1, 0}, {1, 1}, {2, 1}};
  EXPECT_EQ(without_loops(l), l);
}

// After a cut the line goes on from the crossing along the crossed edge; that remainder can
// cross a later edge too (a gauge's back-step near a loop), and is cut as well.
TEST(Geometry, WithoutLoopsAlsoCutsWhereTheRestOfACrossedEdgeCrossesOn) {
  const Polyline steps{{-20, -1}, {-19, -1}, {-18.6, -0.8}, {-18.8, -0.8}, {-18.8, -1.2},
                       {-18.9, -1.2}, {-16.5, 0}, {-5, 20}, {5, 20}, {16.5, 0}, {20, -1}};
  EXPECT_FALSE(is_simple_open(steps));
  const Polyline cut = without_loops(steps);
  EXPECT_TRUE(is_simple_open(cut));
  EXPECT_EQ(cut.front(), steps.front());
  EXPECT_EQ(cut.back(), steps.back());
}

TEST(Geometry, CrossingTestsFindWhatTestingEveryEdgeFinds) {
  int with_loops = 0, simple_after = 0;
  for (unsigned seed = 1; seed <= 6; ++seed) {
    for (const double noise_m : {2e-5, 1e-4, 1e-3}) {  // a fifth of the spacing to 15 spacings
      const Polyline line = noisy_scan(seed, noise_m);
      Polygon loop, loop_ref;
      const Polyline cut = without_loops(line, &loop);
      const Polyline cut_ref = without_loops_every_edge(line, &loop_ref);
      ASSERT_EQ(cut.size(), cut_ref.size()) << "seed " << seed << " noise " << noise_m;
      for (std::size_t i = 0; i < cut.size(); ++i) ASSERT_EQ(cut[i], cut_ref[i]) << i;
      ASSERT_EQ(loop.size(), loop_ref.size());
      for (std::size_t i = 0; i < loop.size(); ++i) ASSERT_EQ(loop[i], loop_ref[i]) << i;
      const bool simple = is_simple_open(line);
      EXPECT_EQ(simple, is_simple_open_every_pair(line));
      with_loops += !simple;
      const bool cut_simple = is_simple_open(cut);
      EXPECT_EQ(cut_simple, is_simple_open_every_pair(cut));
      simple_after += cut_simple;
    }
  }
  // Both answers are compared: some lines cross themselves and some do not, and cut lines
  // come out simple (or, where the noise is wilder than any gauge's, as the reference finds).
  EXPECT_GT(with_loops, 0);
  EXPECT_LT(with_loops, 18);
  EXPECT_GT(simple_after, 0);
}

TEST(Geometry, ThinPointsKeepsTheEndsAndTheSpacing) {
  Polyline line;
  for (int i = 0; i <= 1000; ++i) line.push_back({0.001 * i, 0.0});  // 1 m, a point a millimetre
  const Polyline thin = thin_points(line, 0.0095);
  EXPECT_EQ(thin.front(), line.front());
  EXPECT_EQ(thin.back(), line.back());
  ASSERT_EQ(thin.size(), 101u);  // every tenth point: 0.010 apart (0.009 is too close)
  for (std::size_t i = 0; i + 1 < thin.size(); ++i) EXPECT_GE(length(thin[i + 1] - thin[i]), 0.0095) << i;
  // A line already that sparse comes back as it was; the point before the end goes if too close.
  EXPECT_EQ(thin_points(thin, 0.0095), thin);
  const Polyline near_end{{0, 0}, {1, 0}, {2, 0}, {2.5, 0}};
  const Polyline cut = thin_points(near_end, 0.9);
  ASSERT_EQ(cut.size(), 3u);
  EXPECT_EQ(cut[1], (Vec2{1, 0}));
  EXPECT_EQ(cut[2], (Vec2{2.5, 0}));
}

TEST(Geometry, PointAtLengthAndDistanceToPolyline) {
  const Polyline l{{0, 0}, {1, 0}, {1, 1}};
  const Vec2 p = point_at_length(l, 1.5);
  EXPECT_DOUBLE_EQ(p.x, 1.0);
  EXPECT_DOUBLE_EQ(p.y, 0.5);
  EXPECT_EQ(point_at_length(l, 9.0), l.back());  // clamped
  EXPECT_DOUBLE_EQ(distance_to_polyline({0.5, -2.0}, l), 2.0);
  EXPECT_DOUBLE_EQ(distance_to_polyline({3.0, 0.5}, l), 2.0);
  EXPECT_DOUBLE_EQ(polyline_length(l), 2.0);
}

// The smoothing is an opening and a closing with a disk of radius r, drawn as a regular
// 32-gon of circumradius r: it lies within r (1 - cos(pi/32)) = 0.0048 r of the circle, the
// tolerance every analytic figure below is held to (kDiskError).
constexpr double kDiskError = 0.005;

// Metal an opening takes from a convex corner whose edges turn by phi (and a closing adds
// to a concave one): the region between the corner and a tangent circle of radius r.
double corner_fillet(double r, double phi) { return r * r * (std::tan(0.5 * phi) - 0.5 * phi); }
// ...and what the disk polygon's error can change in four right-angle fillets, over r^2.
constexpr double kCornersError = 4.0 * 0.5 * kPi * kDiskError;

TEST(Geometry, ResmoothingSmoothConvexProfileChangesAreaBelowHalfPercent) {
  // A 200-gon of radius 0.3 m (a smooth convex profile, curvature radius 30 r) smoothed with
  // r = 10 mm: every disk fits, so nothing moves beyond the disk polygon's own error.
  const Polygon ring = regular_polygon(200, 0.3);
  const Polygon out = smooth_by_offsets(ring, 0.01);
  ASSERT_GE(out.size(), 3u);
  EXPECT_LT(std::abs(area(out) - area(ring)) / area(ring), 0.005);
  for (const Vec2& v : out)
    EXPECT_LT(distance_to_polyline(v, Polyline(ring.begin(), ring.end())), kDiskError * 0.01);
}

TEST(Geometry, ResmoothingTwiceDoesNotCreep) {
  // The wear loop smooths after every update: opening and closing are idempotent, so the
  // second pass must not move the profile (a square: its corners round at the first pass).
  const Polygon square{{0, 0}, {0.2, 0}, {0.2, 0.2}, {0, 0.2}};
  const Polygon once = smooth_by_offsets(square, 0.02);
  const Polygon twice = smooth_by_offsets(once, 0.02);
  EXPECT_NEAR(area(twice), area(once), 1e-9 * area(once));
}

TEST(Geometry, ResmoothingRoundsConvexCornersAndNeverGrowsThem) {
  // A square whose corners were worn round to 20 mm (ten edges each), smoothed with r = 50
  // mm. The opening rounds each corner to 50 mm: it takes (1 - pi/4) (R^2 - rho^2) per corner
  // and nothing of the square lies outside the input. (The straight-skeleton version of
  // this smoothing re-sharpened such a corner, growing 8 mm of metal beyond the worn one.)
  const double side = 0.4, rho = 0.02, r = 0.05;
  Polygon ring;
  const double cx[4] = {side - rho, side - rho, rho, rho}, cy[4] = {rho, side - rho, side - rho, rho};
  for (int c = 0; c < 4; ++c)
    for (int i = 0; i <= 10; ++i) {
      const double t = kPi * (c - 1) / 2.0 + 0.5 * kPi * i / 10.0;
      ring.push_back({cx[c] + rho * std::cos(t), cy[c] + rho * std::sin(t)});
    }
  ASSERT_TRUE(is_simple(ring));
  const Polygon out = smooth_by_offsets(ring, r);
  const Polyline in_line(ring.begin(), ring.end());
  for (const Vec2& v : out) {
    const bool inside = v.x > -1e-12 && v.x < side + 1e-12 && v.y > -1e-12 && v.y < side + 1e-12;
    EXPECT_TRUE(inside) << v.x << " " << v.y;
    // Near a corner the output must lie inside the worn arc too (no growth).
    for (int c = 0; c < 4; ++c) {
      const double dx = v.x - cx[c], dy = v.y - cy[c];
      const bool beyond = (c == 0 || c == 1 ? dx > 0 : dx < 0) && (c == 1 || c == 2 ? dy > 0 : dy < 0);
      if (beyond) {
        EXPECT_LE(std::hypot(dx, dy), rho + 1e-9) << "corner " << c;
      }
    }
  }
  // Rounded at r, the worn square is side^2 less four fillets of a right angle. The disk
  // polygon's error along a quarter circle bounds the difference: (pi/2) r * kDiskError r.
  const double expected = side * side - 4.0 * corner_fillet(r, 0.5 * kPi);
  EXPECT_NEAR(area(out), expected, kCornersError * r * r)
      << "area " << area(out) << " expected " << expected;
}

TEST(Geometry, ResmoothingRemovesSpikeNarrowerThanRadius) {
  // Spike 5 mm wide, 100 mm tall on a 1 x 0.2 m block; r = 10 mm > spike width. What stays
  // above the block is the cap of the disks that still reach into the spike's base, as high
  // as a circle of radius r is wide over the spike (r - sqrt(r^2 - (w/2)^2) = 0.32 mm); the
  // block's four corners round off, the spike's feet fill.
  const double r = 0.01, w = 0.005;
  const Polygon ring = rectangle_with_spike(1.0, 0.2, w, 0.1);
  ASSERT_GT(max_y(ring), 0.29);
  const Polygon out = smooth_by_offsets(ring, r);
  ASSERT_GE(out.size(), 3u);
  const double cap = r - std::sqrt(r * r - 0.25 * w * w);
  EXPECT_LT(max_y(out), 0.2 + cap + kDiskError * r);
  EXPECT_NEAR(area(out), 0.2 - 4.0 * corner_fillet(r, 0.5 * kPi), kCornersError * r * r + 2.0 * cap * w);
}

TEST(Geometry, ResmoothingKeepsFeatureWiderThanDiameter) {
  // A 100 mm wide, 50 mm high ridge (a right angle at its apex) is wider than 2r = 20 mm: it
  // survives the opening with its apex rounded to r, r (sqrt 2 - 1) lower.
  const double r = 0.01;
  const Polygon ring = rectangle_with_spike(1.0, 0.2, 0.1, 0.05);
  const Polygon out = smooth_by_offsets(ring, r);
  EXPECT_NEAR(max_y(out), 0.25 - r * (std::sqrt(2.0) - 1.0), kDiskError * r);
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
  const double r = 0.05, neck = 0.01;
  const Polygon out = smooth_by_offsets(ring, r);
  ASSERT_GE(out.size(), 3u);
  // The right square with its four corners rounded; at the neck's root a cap of the disks
  // that still reach into it stays, r - sqrt(r^2 - (neck/2)^2) = 0.25 mm proud.
  const double cap = r - std::sqrt(r * r - 0.25 * neck * neck);
  EXPECT_NEAR(area(out), 1.2 - 4.0 * corner_fillet(r, 0.5 * kPi), kCornersError * r * r + 2.0 * cap * neck);
  for (const Vec2& v : out) EXPECT_GE(v.x, 1.5 - cap - kDiskError * r);
}

TEST(Geometry, ResmoothingReturnsEmptyWhenNothingSurvives) {
  const Polygon thin{{0, 0}, {1, 0}, {1, 0.01}, {0, 0.01}};
  EXPECT_TRUE(smooth_by_offsets(thin, 0.05).empty());
}
