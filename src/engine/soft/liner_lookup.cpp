// Angle-bin lookup of liner edges in the mill frame, and the disk-liner contact test.
#include "common/units.hpp"
#include "engine/soft/liner_lookup.hpp"

#include <algorithm>
#include <cmath>

namespace millwear::soft {

namespace {

// A stand-in for the polar angle that increases with it, in [0, 4) (the "diamond angle":
// position along the unit L1 circle). One division instead of an atan2. d/dtheta lies in
// [1/2, 1], so a bin of width w in it spans at most 2w radians.
double pseudo_angle(double x, double y) {
  if (y >= 0.0) return x >= 0.0 ? y / (x + y) : 1.0 - x / (y - x);
  return x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
}

double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double t = std::clamp(dot(p - a, ab) / length_sq(ab), 0.0, 1.0);
  return length(p - (a + t * ab));
}
}  // namespace

void LinerLookup::build(const MillGeometry& mill, double reach_m) {
  const std::size_t n = mill.boundary.size();
  reach_m_ = reach_m;
  a_.resize(n);
  u_.resize(n);
  n_in_.resize(n);
  len_.resize(n);
  reflex_start_.resize(n);
  inner_m_ = 1e300;
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = mill.boundary[k], b = mill.boundary[(k + 1) % n];
    const Vec2 prev = mill.boundary[(k + n - 1) % n];
    a_[k] = a;
    len_[k] = length(b - a);
    u_[k] = (b - a) / len_[k];
    n_in_[k] = left_perp(u_[k]);  // CCW ring: the mill's inside is on the left
    // The start vertex sticks out into the mill when the ring turns clockwise there.
    reflex_start_[k] = cross(a - prev, b - a) < 0.0 ? 1 : 0;
    inner_m_ = std::min(inner_m_, segment_distance({0.0, 0.0}, a, b));
  }
  // Angle bins only make sense for a ring around the axis with room to spare; anything else
  // (test boxes) gets one bin holding every edge.
  binned_ = n >= 16 && inner_m_ > 4.0 * reach_m;
  if (!binned_) {
    bins_ = 1;
    bin_start_ = {0, static_cast<int>(n)};
    bin_edges_.resize(n);
    for (std::size_t k = 0; k < n; ++k) bin_edges_[k] = static_cast<int>(k);
    max_hits_ = static_cast<int>(n);
    return;
  }
  // A centre within reach of a liner point sits at radius >= inner - reach, so the point is
  // at most asin(reach / (inner - reach)) away in angle. Bins are uniform in the pseudo-angle
  // (no atan2 per query); one bin at most reach / inner radians wide.
  const double spread = std::asin(std::min(1.0, reach_m / (inner_m_ - reach_m)));
  bins_ = std::max(16, static_cast<int>(std::ceil(8.0 * inner_m_ / reach_m)));
  bins_per_unit_ = bins_ / 4.0;
  std::vector<std::vector<int>> lists(static_cast<std::size_t>(bins_));
  for (std::size_t k = 0; k < n; ++k) {
    const Vec2 a = a_[k], b = mill.boundary[(k + 1) % n];
    double t0 = std::atan2(a.y, a.x);
    double t1 = t0 + std::remainder(std::atan2(b.y, b.x) - t0, 2.0 * kPi);
    if (t1 < t0) std::swap(t0, t1);
    // The edge's angular range widened by the spread, in pseudo-angle bins, with a slack of
    // 1e-9 (far above the rounding of the angle and pseudo-angle) against bin borders.
    const double p0 = pseudo_angle(std::cos(t0 - spread), std::sin(t0 - spread)) - 1e-9;
    double p1 = pseudo_angle(std::cos(t1 + spread), std::sin(t1 + spread)) + 1e-9;
    if (p1 < p0) p1 += 4.0;
    const int lo = static_cast<int>(std::floor(p0 * bins_per_unit_));
    const int hi = static_cast<int>(std::floor(p1 * bins_per_unit_));
    for (int q = lo; q <= hi && q < lo + bins_; ++q)
      lists[static_cast<std::size_t>(((q % bins_) + bins_) % bins_)].push_back(static_cast<int>(k));
  }
  bin_start_.assign(static_cast<std::size_t>(bins_) + 1, 0);
  bin_edges_.clear();
  max_hits_ = 0;
  for (int q = 0; q < bins_; ++q) {
    auto& l = lists[static_cast<std::size_t>(q)];
    std::sort(l.begin(), l.end());
    max_hits_ = std::max(max_hits_, static_cast<int>(l.size()));
    bin_edges_.insert(bin_edges_.end(), l.begin(), l.end());
    bin_start_[static_cast<std::size_t>(q) + 1] = static_cast<int>(bin_edges_.size());
  }
}

int LinerLookup::query(Vec2 p, double r, double max_gap, LinerHit* out) const {
  int bin = 0;
  if (binned_) {
    bin = std::min(static_cast<int>(pseudo_angle(p.x, p.y) * bins_per_unit_), bins_ - 1);
  }
  const int n = static_cast<int>(a_.size());
  int count = 0;
  const int* first = bin_edges_.data() + bin_start_[static_cast<std::size_t>(bin)];
  const int* last = bin_edges_.data() + bin_start_[static_cast<std::size_t>(bin) + 1];
  for (const int* it = first; it != last; ++it) {
    const int k = *it;
    const Vec2 d = p - a_[static_cast<std::size_t>(k)];
    const double t = dot(d, u_[static_cast<std::size_t>(k)]);
    if (t >= 0.0 && t < len_[static_cast<std::size_t>(k)]) {
      // Face: signed distance along the inward normal. Past the face line by up to half a
      // radius still counts (the liner knows its inside); deeper than that the centre may
      // be beside another face of a thin lifter, which must not pull it through.
      const double dist = dot(d, n_in_[static_cast<std::size_t>(k)]);
      const double gap = dist - r;
      if (gap < max_gap && dist > -0.5 * r) {
        LinerHit& h = out[count++];
        h.owner = h.edge = k;
        h.normal = n_in_[static_cast<std::size_t>(k)];
        h.gap = gap;
      }
    } else if (t < 0.0 && reflex_start_[static_cast<std::size_t>(k)]) {
      // Vertex k sticks out: the disk is in its wedge when it is also past the end of the
      // previous edge.
      const int prev = k == 0 ? n - 1 : k - 1;
      const double t_prev = dot(p - a_[static_cast<std::size_t>(prev)], u_[static_cast<std::size_t>(prev)]);
      if (t_prev < len_[static_cast<std::size_t>(prev)]) continue;
      const double dist = length(d);
      const double gap = dist - r;
      if (gap < max_gap && dist > 0.0) {
        LinerHit& h = out[count++];
        h.owner = k;
        h.normal = d / dist;
        // One contact, one edge: the face whose normal is nearer the contact normal, so a
        // disk rolling over the corner hands its work from one face to the other, the same
        // way in both directions of rotation.
        h.edge = dot(h.normal, n_in_[static_cast<std::size_t>(k)]) >=
                         dot(h.normal, n_in_[static_cast<std::size_t>(prev)])
                     ? k
                     : prev;
        h.gap = gap;
      }
    }
  }
  return count;
}

}  // namespace millwear::soft
