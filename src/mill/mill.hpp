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
  // One per row, or one per kind of lifter shared by every row of that kind (a pattern of
  // `kinds` lifters repeats over the rows: row k is of kind k % kinds; plain liners have 1).
  std::vector<LinerUnit> units;
  int kinds = 1;
  std::size_t unit_of_row(int row) const {
    return units.size() == static_cast<std::size_t>(rows) ? static_cast<std::size_t>(row)
                                                          : static_cast<std::size_t>(row) % units.size();
  }
  int unit_edge_count(int row) const {
    return static_cast<int>(units[unit_of_row(row)].surface.size()) - 1;
  }
};

struct MillMeshDef {
  double shell_edge_m = 0.020;  // target edge length on shell arcs
  double lifter_edge_m = 0.010; // target edge length on lifter faces
};

// Map a lifter-local point of row k into the mill frame.
Vec2 local_to_mill(Vec2 local, int row, int rows, double radius_m);
Vec2 mill_to_local(Vec2 mill, int row, int rows, double radius_m);
// Whether a point of the mill frame lies more than depth_m into the metal of its row's
// liner unit: below the unit's surface at the point's position along the row (the engines'
// test for a disk leaked into the liner).
bool deeper_than_liner_surface(const MillGeometry& mill, Vec2 p_mill, double depth_m);

// The liner unit of a new lifter: shell half-gaps either side of the lifter polyline.
// Throws InputError if the lifter does not fit the pitch (touches its neighbours) or is
// taller than the mill allows.
LinerUnit make_liner_unit(const Polyline& lifter_local, double radius_m, int rows,
                          const MillMeshDef& mesh = {});

// The shift in x make_measured_unit gives a measured surface: 0 for a scan of one lifter,
// which is in lifter-local coordinates as the surveys are (x = 0 the lifter's centre line);
// for a whole unit's scan (`whole_unit`), the one that centres the lifter's base (the
// midpoint of the feet of `lifter_local`) on x = 0.
double measured_unit_shift_m(const Polyline& lifter_local, bool whole_unit);

// The liner unit of a measured surface (profiles/profile.hpp: `measured`, with its lifter
// `lifter`): moved by measured_unit_shift_m, resampled to the mesh, continued along the shell
// at the height of its ends out to the pitch. Throws InputError if it is wider than the
// pitch about x = 0 or the lifter, |x| at most its largest, is wider than the pitch or taller
// than the mill allows. `whole_unit`: the surface is one whole liner unit, its first and last
// points the same place on neighbouring units (the caller has checked its width is the
// pitch): it is repeated either side and cut at the unit's edges, so the shell plates keep
// their measured shape instead of being clipped or continued flat.
LinerUnit make_measured_unit(const Polyline& surface, const Polyline& lifter, double radius_m, int rows,
                             const MillMeshDef& mesh = {}, bool whole_unit = false);

// Build the whole boundary from one unit per row, or one unit per kind of lifter (`kinds`
// of them repeating over the rows; rows a multiple of kinds). A mill of per-row units still
// has its scene's kinds: they say which rows' lifters are measured together.
MillGeometry build_mill(double radius_m, int rows, std::vector<LinerUnit> units, int kinds);

// Metrics of a (possibly worn) liner unit against the original shell circle.
struct LifterMetrics {
  double area_m2 = 0.0;    // metal cross-section above the original shell (true area)
  double height_m = 0.0;   // largest y over the original lifter base
  double leading_face_angle_rad = 0.0;
  double trailing_face_angle_rad = 0.0;
};
LifterMetrics measure_lifter(const LinerUnit& unit, double radius_m);

}  // namespace millwear
