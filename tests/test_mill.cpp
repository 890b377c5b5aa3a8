// Mill geometry: polar map, the closed boundary, edge ownership, lifter metrics.
#include <gtest/gtest.h>

#include <cmath>

#include "common/units.hpp"
#include "common/errors.hpp"
#include "mill/mill.hpp"
#include "profiles/profile.hpp"

using namespace millwear;

namespace {

// The mesh these checks were written for.
const MillMeshDef kMesh{0.04, 0.02};

constexpr double kDeg = kPi / 180.0;
constexpr double kR = 5.0;   // 10 m mill
constexpr int kRows = 48;

Polyline lifter_2x30() { return trapezoid_points({0.2, 0.1, 30 * kDeg, 30 * kDeg}); }

MillGeometry mill_2x30() {
  return build_mill(kR, kRows, {make_liner_unit(lifter_2x30(), kR, kRows, kMesh)}, 1);
}

}  // namespace

TEST(Mill, LocalToMillRoundTrips) {
  const Vec2 local{0.12, 0.15};
  for (int row : {0, 7, 47}) {
    const Vec2 back = mill_to_local(local_to_mill(local, row, kRows, kR), row, kRows, kR);
    // Rounding of atan2/hypot on metre-scale values: 1e-12 m.
    EXPECT_NEAR(back.x, local.x, 1e-12);
    EXPECT_NEAR(back.y, local.y, 1e-12);
  }
}

TEST(Mill, ShellLineMapsToShellCircleAndXIsCounterClockwiseArc) {
  const Vec2 a = local_to_mill({0.0, 0.0}, 0, kRows, kR);
  const Vec2 b = local_to_mill({0.5, 0.0}, 0, kRows, kR);
  EXPECT_NEAR(length(b), kR, 1e-12);
  EXPECT_NEAR(a.x, kR, 1e-12);
  EXPECT_NEAR(std::atan2(b.y, b.x), 0.5 / kR, 1e-12);  // +x is CCW, x is arc length
  EXPECT_NEAR(length(local_to_mill({0.0, 0.2}, 3, kRows, kR)), kR - 0.2, 1e-12);
}

TEST(Mill, BoundaryIsClosedSimpleAndCounterClockwise) {
  const MillGeometry g = mill_2x30();
  const std::size_t n = g.boundary.size();
  ASSERT_GT(n, static_cast<std::size_t>(kRows) * 10);
  EXPECT_EQ(g.edges.size(), n);
  EXPECT_EQ(g.normal_out.size(), n);
  EXPECT_EQ(g.edge_length_m.size(), n);
  EXPECT_TRUE(is_simple(g.boundary));
  EXPECT_TRUE(is_counter_clockwise(g.boundary));
  // Closed: the closing edge is an ordinary shell edge (no gap, no duplicate joint point),
  // and every edge is shorter than the coarsest target (40 mm) plus rounding.
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_GT(g.edge_length_m[i], 1e-3);
    EXPECT_LT(g.edge_length_m[i], 0.04 * 1.5);
  }
  EXPECT_EQ(g.edges.back().owner, EdgeOwner::Shell);
  // Area: disk minus 48 lifters of their true (polar) area. The boundary is made of chords,
  // each losing about c^3 / (12 R) against its arc (1e-6 m^2 for c = 40 mm, R = 5 m); some
  // 1700 edges bound the difference by 2e-3 m^2.
  const double lifter = measure_lifter(g.units[0], kR).area_m2;
  EXPECT_NEAR(area(g.boundary), kPi * kR * kR - kRows * lifter, 2e-3);
}

TEST(Mill, EdgeOwnersAndLocalCoordinatesAtLifterFeet) {
  const MillGeometry g = mill_2x30();
  const LinerUnit& u = g.units[0];
  const Polyline lifter = lifter_2x30();
  const int edges_per_row = g.unit_edge_count(0);
  // Index of the unit vertex at the trailing foot and at the leading foot.
  int trail = -1, lead = -1;
  for (int j = 0; j <= edges_per_row; ++j) {
    if (u.surface[j] == lifter.front()) trail = j;
    if (u.surface[j] == lifter.back()) lead = j;
  }
  ASSERT_GE(trail, 1);
  ASSERT_GT(lead, trail);

  // Total shell segment length: right half-gap of row k plus left half-gap of row k+1.
  double shell_len = 0.0;
  for (int j = 0; j < trail; ++j) shell_len += g.edge_length_m[j];
  shell_len *= 2.0;

  for (int k : {0, 1, kRows - 1}) {
    const int base = k * edges_per_row;
    // Edge ending at the trailing foot: last edge of shell segment k-1.
    const LinerEdgeInfo& before = g.edges[base + trail - 1];
    EXPECT_EQ(before.owner, EdgeOwner::Shell);
    EXPECT_EQ(before.owner_index, (k + kRows - 1) % kRows);
    EXPECT_NEAR(before.s_local_m, shell_len - 0.5 * g.edge_length_m[base + trail - 1], 1e-12);
    // Edge starting at the trailing foot: first edge of lifter k.
    const LinerEdgeInfo& first = g.edges[base + trail];
    EXPECT_EQ(first.owner, EdgeOwner::Lifter);
    EXPECT_EQ(first.owner_index, k);
    EXPECT_EQ(first.row, k);
    EXPECT_EQ(first.unit_edge, trail);
    EXPECT_NEAR(first.s_local_m, 0.5 * g.edge_length_m[base + trail], 1e-12);
    // Edge ending at the leading foot: last lifter edge; s = lifter length - half edge.
    double lifter_len = 0.0;
    for (int j = trail; j < lead; ++j) lifter_len += g.edge_length_m[base + j];
    const LinerEdgeInfo& last = g.edges[base + lead - 1];
    EXPECT_EQ(last.owner, EdgeOwner::Lifter);
    EXPECT_EQ(last.owner_index, k);
    EXPECT_NEAR(last.s_local_m, lifter_len - 0.5 * g.edge_length_m[base + lead - 1], 1e-12);
    // Edge starting at the leading foot: first edge of shell segment k.
    const LinerEdgeInfo& after = g.edges[base + lead];
    EXPECT_EQ(after.owner, EdgeOwner::Shell);
    EXPECT_EQ(after.owner_index, k);
    EXPECT_NEAR(after.s_local_m, 0.5 * g.edge_length_m[base + lead], 1e-12);
  }
}

TEST(Mill, VerticalFaceEdgesBelongToTheLifter) {
  // 0 deg faces put the face edge midpoints exactly at |x| = half base.
  const Polyline rect = trapezoid_points({0.2, 0.2, 0.0, 0.0});
  const MillGeometry g = build_mill(kR, 8, {make_liner_unit(rect, kR, 8, kMesh)}, 1);
  int lifter_edges = 0;
  for (const LinerEdgeInfo& e : g.edges)
    if (e.owner == EdgeOwner::Lifter && e.owner_index == 0) ++lifter_edges;
  // 200 mm faces and top at the default 20 mm lifter edge: 10 + 10 + 10 edges.
  EXPECT_EQ(lifter_edges, 30);
}

TEST(Mill, NormalsPointOutwardIntoTheLiner) {
  const MillGeometry g = mill_2x30();
  for (std::size_t i = 0; i < g.boundary.size(); ++i) {
    EXPECT_NEAR(length(g.normal_out[i]), 1.0, 1e-12);
    if (g.edges[i].owner == EdgeOwner::Shell) {
      const Vec2 mid = 0.5 * (g.boundary[i] + g.boundary[(i + 1) % g.boundary.size()]);
      // Shell chords: the normal is the radial direction at the midpoint (exactly, by symmetry).
      EXPECT_GT(dot(g.normal_out[i], normalized(mid)), 1.0 - 1e-12);
    }
  }
}

TEST(Mill, LifterWiderThanPitchIsRejected) {
  // 120 rows in a 5 m mill: pitch 262 mm < 331 mm base of the 2x30.
  try {
    make_liner_unit(lifter_2x30(), kR, 120, kMesh);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "lifters.rows");
  }
}

TEST(Mill, LifterTallerThanHalfRadiusIsRejected) {
  try {
    make_liner_unit(lifter_2x30(), 0.35, 2, kMesh);
    FAIL() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "lifters.profile");
  }
}

TEST(Mill, LifterAreaMatchesPolarFormula) {
  // A rectangular lifter of width w, height h occupies the annular sector between R - h and
  // R over w/R radians: A = w h - w h^2 / (2R). Exact for the polygon, so 1e-12 relative.
  const double w = 0.2, h = 0.2;
  const LinerUnit u = make_liner_unit(trapezoid_points({h, w, 0.0, 0.0}), kR, kRows, kMesh);
  const LifterMetrics m = measure_lifter(u, kR);
  EXPECT_NEAR(m.area_m2, w * h - w * h * h / (2 * kR), 1e-12 * w * h);
  EXPECT_NEAR(m.height_m, h, 1e-15);
  EXPECT_NEAR(m.leading_face_angle_rad, 0.0, 1e-12);
}

TEST(Mill, NewLifterMetricsMatchTheProfile) {
  const LinerUnit u = make_liner_unit(lifter_2x30(), kR, kRows, kMesh);
  const LifterMetrics m = measure_lifter(u, kR);
  const ProfileMetrics p = measure_profile(lifter_2x30());
  EXPECT_NEAR(m.height_m, 0.2, 1e-12);
  EXPECT_NEAR(m.leading_face_angle_rad, 30 * kDeg, 1e-12);
  EXPECT_NEAR(m.trailing_face_angle_rad, 30 * kDeg, 1e-12);
  // True area is below the flat area by (1/R) * integral of y dA: a few percent here.
  EXPECT_LT(m.area_m2, p.area_m2);
  EXPECT_GT(m.area_m2, 0.97 * p.area_m2);
}

TEST(Mill, WornShellBelowTheCircleDoesNotCountAsLifter) {
  // Shell worn 10 mm below the original circle next to the lifter: the metal above the
  // circle is still the lifter only, and a worn-down top lowers the height.
  LinerUnit u = make_liner_unit(trapezoid_points({0.2, 0.2, 0.0, 0.0}), kR, kRows, kMesh);
  for (Vec2& p : u.surface) {
    if (p.y == 0.0 && std::abs(p.x) > u.lifter_half_base_m) p.y = -0.01;
    if (p.y > 0.15) p.y = 0.15;  // top worn 50 mm
  }
  const LifterMetrics m = measure_lifter(u, kR);
  EXPECT_NEAR(m.height_m, 0.15, 1e-12);
  EXPECT_NEAR(m.area_m2, 0.2 * 0.15 - 0.2 * 0.15 * 0.15 / (2 * kR), 1e-12);
}

TEST(Mill, SmoothingANewMillBoundaryRoundsEveryCornerByItsFillet) {
  // The boundary encloses the charge's space. Smoothing it with a disk of r = 10 mm rounds
  // each corner the charge sees as convex (a lifter's foot: the opening takes that fillet of
  // space) and each concave one (a lifter's top corner: the closing adds it), and moves
  // nothing else: the area changes by the sum of the fillets r^2 (tan(phi/2) - phi/2), with
  // phi each vertex's turn, to within the disk polygon's error along the arcs (0.5% of r
  // over r phi).
  const MillGeometry g = mill_2x30();
  const double r = 0.01;
  const Polygon s = smooth_by_offsets(g.boundary, r);
  EXPECT_TRUE(is_simple(s));
  EXPECT_TRUE(is_counter_clockwise(s));
  const std::size_t n = g.boundary.size();
  double expected = 0.0, tolerance = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 a = g.boundary[(i + n - 1) % n], b = g.boundary[i], c = g.boundary[(i + 1) % n];
    const double phi = std::atan2(cross(b - a, c - b), dot(b - a, c - b));  // > 0: left turn, convex
    const double fillet = r * r * (std::tan(0.5 * std::fabs(phi)) - 0.5 * std::fabs(phi));
    expected += phi > 0.0 ? -fillet : fillet;
    tolerance += 0.005 * r * r * std::fabs(phi);
  }
  EXPECT_NEAR(area(s) - area(g.boundary), expected, tolerance)
      << "area change " << area(s) - area(g.boundary) << " m^2, fillets " << expected;
}
