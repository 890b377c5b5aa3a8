#pragma once
// Changing the charge of a running mill without starting it again: disks added to or taken
// from each species when the filling changes, and disks the new liner would cut into moved
// to free space when the lifters change. The disks kept keep their state; new disks start
// at rest in free space inside the lifter tips and fall into the charge.
#include <string>

#include "engine/charge.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear::view {

// The charge `now` brought to the disk counts of `scene`'s filling (fill_charge's sizes per
// species): a species short of disks gets disks of its own sizes placed in free space, one
// with too many loses disks spread through it. Escaped disks are dropped. Throws RunError
// when the new disks do not fit in the free space.
ChargeState refill_charge(const Scene& scene, const MillGeometry& mill, const ChargeState& now);

// The charge `now` in a mill whose liner became `mill`: every disk that overlaps the new
// liner or lies outside it is placed again in free space. Throws RunError when they do not fit.
ChargeState fit_charge_to_liner(const Scene& scene, const MillGeometry& mill, const ChargeState& now);

}  // namespace millwear::view
