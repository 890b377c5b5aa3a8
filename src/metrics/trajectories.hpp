#pragma once
// Where the lifters throw the charge, measured from the simulation itself: the flights of
// disks leaving the liner in free flight, their first impacts (point, species, energy), the
// distribution of those impacts against the angle round the mill, the share of their energy
// that lands on the bare liner above the toe (the liner-damage figure that limits face
// angles), and the flight paths of one stretch of the window (the trajectory envelope). A
// post-processing of a sequence of charge frames from either backend, at any spacing (every
// step in `millwear charge`); the engine is not touched.
//
// Definitions (docs/trajectories.md says them with the figures):
//  - Free: between two frames a disk is free when its velocity changed by gravity alone,
//    each component within free_tolerance x g dt of the ballistic change (no contact acted).
//  - Flight from the lifters: a run of free intervals whose first starts at a frame where the
//    disk touched the liner (its centre within (1 + touch_gap) radii of the liner polyline,
//    mill frame) on the rising side (0 < angle < 180 deg), and in which the disk gets at
//    least its own diameter away from where it left. A free run that starts anywhere else (a
//    disk bouncing on the charge) is not a flight from the lifters, nor is a disk chattering
//    on the liner (free for a step or two, a millimetre or so, between contacts).
//  - First impact: the flight's last free frame; the contact that ends it comes within the
//    next frame interval, so the point is within one frame's travel of where the disk struck.
//    Its energy is the translational kinetic energy relative to the mill frame there,
//    1/2 m |v - omega x p|^2: what a surface turning with the mill (the liner, a bed riding
//    with it) takes. The spin does not change in flight and is not counted.
//  - On the liner: at the first frame of contact the disk touches the liner (as above).
//  - Above the toe: the impact's angle lies outside the bed, on the arc from the toe up the
//    falling side, over the top and down to the shoulder (toe and shoulder as
//    metrics/charge_summary.hpp measures them). A centrifuged charge has neither: no share.
//
// Angles are from 6 o'clock, + toward the side the mill lifts the charge (the frame of the
// toe and shoulder), in degrees; positions in the world frame, metres.
#include <cstddef>
#include <vector>

#include "common/units.hpp"
#include "engine/charge.hpp"
#include "geometry/polyline.hpp"
#include "metrics/batch_means.hpp"

namespace millwear {

struct FlightOptions {
  double gravity_m_s2 = kGravity;
  // A free interval's velocity change may differ from g dt by this share of g dt in each
  // component: far above the rounding of either backend (the library's floats), far below
  // any contact's impulse.
  double free_tolerance = 0.02;
  // A disk touches the liner when its centre is within (1 + touch_gap) radii of it: room for
  // the soft contact's overlap and for a frame's travel at release.
  double touch_gap = 0.25;
  // Paths: flights launched at times in [path_from_s, path_to_s] are recorded as polylines,
  // a point at most every path_interval_s (plus launch and impact), at most max_paths.
  double path_from_s = 0.0, path_to_s = -1.0;  // empty range: no paths
  double path_interval_s = 0.0;
  std::size_t max_paths = 2000;
};

// One flight's first impact.
struct Impact {
  int disk = -1;
  int species = 0;
  int batch = 0;                  // the caller's sub-window when it landed (set_batch)
  Vec2 launch_m, point_m;         // world frame
  double launch_deg = 0.0, angle_deg = 0.0;  // from 6 o'clock, + toward the rising side
  double energy_J = 0.0;          // translational KE relative to the mill frame
  bool on_liner = false;          // struck the liner itself, not the charge
};

// A flight's path in the world frame, launch to impact (or to the last frame, in the air).
struct FlightPath {
  int disk = -1;
  int species = 0;
  bool landed = false;
  std::vector<Vec2> points_m;
};

// Follows every disk through the frames it is shown, in order. Plain per-disk arrays; one
// pass over the charge per frame, the liner looked up only where a flight starts or ends.
class FlightTracker {
 public:
  // liner: the mill's inner boundary in the mill frame (MillGeometry::boundary); first: the
  // frame the tracking starts from (its flights in progress are not counted).
  FlightTracker(const Polygon& liner, const ChargeState& first, const FlightOptions& options = {});
  // The next frame, later than the last (same disks). Frames need not be evenly spaced.
  void observe(const ChargeState& frame);
  // Impacts from now on are tagged with this sub-window index.
  void set_batch(int batch) { batch_ = batch; }

  const std::vector<Impact>& impacts() const { return impacts_; }
  // The recorded paths: the landed flights' in the order they landed, then those still in
  // the air (to the last frame).
  std::vector<FlightPath> paths() const;
  // Flights from the lifters so far (landed or in the air).
  std::size_t launches() const { return launches_; }
  // Distance from a mill-frame point to the liner polyline (m); large where no liner edge is
  // within reach of the largest disk.
  double liner_distance(Vec2 mill_point) const;

 private:
  enum class Phase : unsigned char { Unknown, Bound, Flying, Hop };
  void start_flight(std::size_t i, const ChargeState& frame);
  void end_flight(std::size_t i, const ChargeState& frame);
  void count_flight(std::size_t i, Vec2 now, double radius_m);
  bool touches_liner(Vec2 world, double mill_angle_rad, double radius_m) const;

  FlightOptions options_;
  // The liner, binned by angle: bin k holds every edge a point of that angle bin may be
  // within reach of.
  Polygon liner_;
  double inner_m_ = 0.0, reach_m_ = 0.0;
  int bins_ = 1;
  std::vector<int> bin_start_, bin_edges_;
  // Per disk: the previous frame and the flight in progress.
  std::vector<Phase> phase_;
  std::vector<Vec2> prev_position_, prev_velocity_;
  double prev_time_s_ = 0.0, prev_mill_angle_rad_ = 0.0, prev_mill_speed_ = 0.0;
  std::vector<Vec2> launch_m_;
  std::vector<unsigned char> counted_;  // the flight has got a diameter away from its launch
  std::vector<FlightPath> flying_path_;  // the path of the flight in progress (empty: none)
  std::vector<double> path_last_s_;
  std::vector<FlightPath> paths_;        // landed
  std::size_t launches_ = 0;
  std::vector<Impact> impacts_;
  int batch_ = 0;
};

// The angle of a world point from 6 o'clock, + toward the rising side of a mill turning at
// mill_speed (counter-clockwise when positive), in (-180, 180] deg.
double angle_from_bottom_deg(Vec2 world, double mill_speed_rad_s);
// Whether an angle lies above the toe, outside the bed: on the arc from the toe over the top
// to the shoulder (toe < 0 < shoulder in the rising-side frame).
bool above_toe(double angle_deg, double toe_deg, double shoulder_deg);

// Impacts binned by angle: kImpactBins bins of 5 deg from -180 deg.
constexpr int kImpactBins = 72;
constexpr double kImpactBinDeg = 360.0 / kImpactBins;
struct ImpactDistribution {
  std::vector<double> count, energy_J, liner_energy_J;              // per bin, every species
  std::vector<std::vector<double>> species_count, species_energy_J;  // [species][bin]
};
ImpactDistribution bin_impacts(const std::vector<Impact>& impacts, int species_count);

// The window's impact figures, and their batch-means errors over its sub-windows.
struct ImpactShares {
  std::size_t impacts = 0;
  double energy_J = 0.0;          // first-impact energy, all flights
  double liner_energy_J = 0.0;    // of which on the bare liner above the toe
  double above_toe_energy_J = 0.0;  // of which above the toe, on the liner or the charge
  bool centrifuged = false;       // no toe: the shares are undefined (NaN)
  double liner_share = 0.0;       // liner_energy_J / energy_J
  double above_toe_share = 0.0;   // above_toe_energy_J / energy_J
};
// Over the impacts of one batch (batch >= 0) or of them all (batch < 0).
ImpactShares impact_shares(const std::vector<Impact>& impacts, double toe_deg, double shoulder_deg,
                           bool centrifuged, int batch = -1);
struct ImpactSummary {
  ImpactShares window;
  BatchMeans liner_share, above_toe_share;  // over the batches 0 .. batches-1
};
ImpactSummary summarize_impacts(const std::vector<Impact>& impacts, int batches, double toe_deg,
                                double shoulder_deg, bool centrifuged);

}  // namespace millwear
