// The thinnest part of a profile's metal (see polyline.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "geometry/polyline.hpp"

namespace millwear {

bool contains(const Polygon& ring, Vec2 p) {
  bool inside = false;
  const std::size_t n = ring.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = ring[i], b = ring[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  return inside;
}

double thinnest_part(const Polyline& surface, double spacing) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // Two surface points face each other across the metal when the surface between them is over
  // twice as long as their join (a semicircular tip gives pi/2, so a round-nosed lifter passes).
  constexpr double kDetour = 2.0;
  constexpr std::size_t kMaxPoints = 4000;
  const double total = polyline_length(surface);
  if (surface.size() < 3 || !(total > 0.0) || !(spacing > 0.0)) return kInf;
  const double step = std::max(spacing, total / kMaxPoints);
  const auto n = static_cast<std::size_t>(std::ceil(total / step)) + 1;
  std::vector<Vec2> pts(n);
  std::vector<double> s(n);
  for (std::size_t i = 0; i < n; ++i) {
    s[i] = std::min(total, static_cast<double>(i) * step);
    pts[i] = point_at_length(surface, s[i]);
  }
  const Polygon metal(surface.begin(), surface.end());  // closed by the straight base
  double thinnest = kInf;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const double d = length(pts[j] - pts[i]);
      if (!(d < thinnest) || s[j] - s[i] <= kDetour * d) continue;
      if (contains(metal, 0.5 * (pts[i] + pts[j]))) thinnest = d;
    }
  return thinnest;
}

}  // namespace millwear
