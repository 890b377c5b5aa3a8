#pragma once
// Numerical limits of a scene: the ranges the stability suite (tests/stability_*.cpp)
// measured as safe, checked before anything runs. docs/stability.md gives, knob by knob,
// the safe range, the measured edge and what happens beyond it.
//
// Checked here (InputError naming the key and the limit):
// - time step against particle size: a disk must not travel more than
//   kMaxStepTravelRadii of the smallest radius in one step at the scene's impact speed
//   (impact_speed_m_s): beyond it contacts are found too late, the position correction
//   cannot push the overlap out, and disks leak through the one-sided liner.
// Reported as events during a run instead (they depend on the run, not the input):
// escaped or non-finite disks (engine), a lifter worn to the shell and rule 1's one-update
// bound on wear.factor (wear loop).
#include <string>

#include "scene/scene.hpp"

namespace millwear {

// The fastest a disk meets the liner or another disk in this mill: the shell speed plus a
// free fall across the mill, omega R + sqrt(2 g D) (an upper bound: a cataracting disk
// leaves the shell at the shell speed and falls at most a diameter).
double impact_speed_m_s(const Scene& scene);

// Distance a disk at the impact speed travels in one step, in smallest particle radii.
double step_travel_radii(const Scene& scene);

// The largest step travel found safe on the Box2D backend: the sweep (bench/stability_sweep,
// docs/stability.md) ran 6, 15 and 40 mm disks clean up to 1.57 radii per step and lost the
// first disks at 1.97-3.15 radii (leaks grow with disk count and run length, so the limit
// sits at the clean edge, not the first leak).
constexpr double kMaxStepTravelRadii = 1.6;

// Throw InputError(file, key, ...) if the scene is outside a measured limit above.
void check_numerical_limits(const Scene& scene, const std::string& file);

}  // namespace millwear
