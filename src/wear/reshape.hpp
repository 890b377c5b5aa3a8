#pragma once
// Reshape: the worn liner surface from Archard's depths. Apply the depths as vertex moves,
// cut folds, re-smooth with a disk (open and close, CGAL offsets in geometry/), resample to
// the mesh, cut back to the surface before the update (wear never adds metal) and check
// what the smoothing took. A surface that stops being a valid liner is a numerical failure
// (RunError), never wear.
#include <string>
#include <vector>

#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Move every edge of a unit into the metal by its depth (edge depths become vertex
// displacements along the vertex normals), re-smooth (open and close with a disk of radius
// smoothing_m, with the neighbouring units either side), resample to the mesh, cut back
// whatever lies outside the unit before the update (wear never adds metal) and check the
// result is simple. Throws RunError if the worn surface is not a valid liner any more.
LinerUnit apply_wear(const LinerUnit& unit, const std::vector<double>& edge_depth_m,
                     double radius_m, double smoothing_m, const MillMeshDef& mesh);

// The smoothing radius a scene uses: wear.smoothing_radius, else the smallest particle
// radius (a disk cannot reach into a hollow narrower than itself).
double smoothing_radius(const Scene& scene);

// The liner unit of kind `kind` the wear history starts from: new_liner_unit, and for a
// measured profile that, resampled and re-smoothed at smoothing_m as the wear loop does
// after every update (apply_wear with no wear), so its noise is not taken for wear.
LinerUnit starting_unit(const Scene& scene, int kind, double smoothing_m);

// What one re-smoothing at smoothing_m does to the starting lifter of a kind (apply_wear
// with no wear): the share of its area and of its height it removes. Corners round off a
// little; a feature narrower than 2 x smoothing_m goes entirely.
struct SmoothingLoss {
  double area_fraction = 0.0, height_fraction = 0.0;
  std::string failure;  // why the unit did not survive re-smoothing (then both fractions are 1)
};
SmoothingLoss smoothing_loss(const Scene& scene, double smoothing_m, int kind = 0);

// The largest share of the new lifter one re-smoothing may remove before the scene is
// refused: more means the radius is wider than the lifter's narrowest part and would wear
// it away without any shear work.
constexpr double kMaxSmoothingAreaLoss = 0.05;
constexpr double kMaxSmoothingHeightLoss = 0.05;
// The largest share of a measured lifter's area (as scanned) the first re-smoothing, which
// takes the gauge's noise, may remove: more, and the scan is mostly thinner than the particles.
constexpr double kMaxScanSmoothingLoss = 0.5;
// apply_wear merges points closer than this fraction of the lifter edge (mesh.lifter_edge_m):
// the bound on how far a worn surface can stand outside the one before (rounding aside).
constexpr double kSliverEdgeFraction = 0.01;

// Throw InputError(file, "wear.smoothing_radius", ...) if re-smoothing the new lifter at the
// scene's radius removes more than the bounds above; the message gives the largest radius
// that keeps within them.
void check_smoothing_radius(const Scene& scene, const std::string& file);
// The same for one kind of lifter of a pattern.
void check_smoothing_radius(const Scene& scene, const std::string& file, int kind);
// Every check a scene passes before a command fills, runs or writes anything: the numerical
// limits (check_run_limits, scene/limits.hpp), then check_smoothing_radius, which also checks
// a measured lifter once re-smoothed. The commands that only turn the charge check the same,
// so a scene is valid for every command or for none.
void check_scene(const Scene& scene, const std::string& file);

// Lifter area one wear update removed beyond its Archard depths (m^2): the area the
// re-smoothing took (the corners it rounded; negative: Archard's edge strips overstate what
// the vertex moves remove on a strongly curved lifter). Near zero while the radius is under
// half the lifter's narrowest part; large when a worn lifter has grown a feature the
// smoothing cuts away (a thin ridge). `before` is the unit the depths were applied to,
// `after` apply_wear's result. The wear loop stops when it removes over
// kMaxSmoothingAreaLoss of the new area.
double resmoothing_loss_m2(const LinerUnit& before, const LinerUnit& after, const std::vector<double>& edge_depth_m,
                           double radius_m);

// One wear update of every unit: apply_wear, then the re-smoothing check against the new
// lifter's area. Throws NumericalError naming `stage` and what failed: non-finite depths, a
// surface that is no valid liner any more, or a smoothing that took more than
// kMaxSmoothingAreaLoss of new_area_m2 beyond the wear.
std::vector<LinerUnit> reshape(const std::vector<LinerUnit>& units, const std::vector<std::vector<double>>& depths,
                               double radius_m, double smoothing_m, const MillMeshDef& mesh, double new_area_m2,
                               int stage);

}  // namespace millwear
