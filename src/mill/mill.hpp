#pragma once
// The mill's whole inner boundary (shell arcs between lifters plus the lifters) as one
// closed, simple, counter-clockwise polygon in the mill frame (origin at the mill axis,
// metres, mill angle 0), with per-edge ownership and normals.
//
// Lifter-local coordinates map to the mill frame by a polar map: a point (x, y) of row k
// sits at angle theta_k + x / R and radius R - y, theta_k = 2 pi k / rows. The shell line
// y = 0 is therefore exactly the shell circle, x is arc length along the shell, and +x is
// counter-clockwise (the forward direction of rotation).
#include <cstdint>
#include <vector>

#include "geometry/polyline.hpp"

namespace millwear {

// One row's repeat unit of liner surface in lifter-local coordinates: from x = -pitch/2
// (half-way to the previous lifter) to x = +pitch/2, shell then lifter then shell.
struct LinerUnit {
  Polyline surface;            // lifter-local, m; x strictly from -pitch/2 to +pitch/2 at ends
  double lifter_half_base_m;   // original lifter occupies |x| <= this (edge ownership)
};

enum class EdgeOwner : std::uint8_t { Lifter, Shell };

struct LinerEdgeInfo {
  EdgeOwner owner = EdgeOwner::Shell;
  int owner_index = 0;     // lifter k, or shell segment k (between lifter k and k+1)
  double s_local_m = 0.0;  // arc length of the edge midpoint along its owner, from the
                           // owner's start in counter-clockwise order
  int row = 0;             // which liner unit the edge came from
  int unit_edge = 0;       // index of the edge within that row's unit surface
};

struct MillGeometry {
  double radius_m = 0.0;   // shell (inner) radius, before wear
  int rows = 0;
  Polygon boundary;        // CCW ring; edge i joins boundary[i] and boundary[(i+1) % n]
  std::vector<LinerEdgeInfo> edges;
  std::vector<Vec2> normal_out;      // unit outward normal per edge (into the liner metal)
  std::vector<double> edge_length_m;
  std::vector<LinerUnit> units;      // one per row, or one shared by every row
  int unit_edge_count(int row) const {
    const auto& u = units[units.size() == 1 ? 0 : row];
    return static_cast<int>(u.surface.size()) - 1;
  }
};

struct MillMeshDef {
  double shell_edge_m = 0.020;  // target edge length on shell arcs
  double lifter_edge_m = 0.010; // target edge length on lifter faces
};

// Map a lifter-local point of row k into the mill frame.
Vec2 local_to_mill(Vec2 local, int row, int rows, double radius_m);
Vec2 mill_to_local(Vec2 mill, int row, int rows, double radius_m);

// The liner unit of a new lifter: shell half-gaps either side of the lifter polyline.
// Throws InputError if the lifter does not fit the pitch (touches its neighbours) or is
// taller than the mill allows.
LinerUnit make_liner_unit(const Polyline& lifter_local, double radius_m, int rows,
                          const MillMeshDef& mesh = {});

// Build the whole boundary from one unit per row (or a single unit for all rows).
MillGeometry build_mill(double radius_m, int rows, std::vector<LinerUnit> units);

// Metrics of a (possibly worn) liner unit against the original shell circle.
struct LifterMetrics {
  double area_m2 = 0.0;    // metal cross-section above the original shell (true area)
  double height_m = 0.0;   // largest y over the original lifter base
  double leading_face_angle_rad = 0.0;
  double trailing_face_angle_rad = 0.0;
};
LifterMetrics measure_lifter(const LinerUnit& unit, double radius_m);

}  // namespace millwear
