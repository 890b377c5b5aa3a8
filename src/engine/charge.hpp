#pragma once
// The charge's state, world frame, SI units, structure of arrays indexed by disk id.
// Both backends read and write this layout at their boundary.
#include <cstdint>
#include <vector>

#include "geometry/vec2.hpp"

namespace millwear {

struct ChargeState {
  std::vector<Vec2> position_m;
  std::vector<Vec2> velocity_m_s;
  std::vector<double> angle_rad;
  std::vector<double> spin_rad_s;
  std::vector<double> radius_m;
  std::vector<double> mass_kg;        // disk mass: density * pi r^2 * slice thickness
  std::vector<std::uint8_t> species;
  std::vector<std::uint8_t> active;   // 0 once a disk escaped or went non-finite
  double mill_angle_rad = 0.0;        // mill rotation since the start (mill frame -> world)
  double mill_speed_rad_s = 0.0;      // signed, + counter-clockwise
  double time_s = 0.0;
  std::size_t size() const { return radius_m.size(); }
};

}  // namespace millwear
