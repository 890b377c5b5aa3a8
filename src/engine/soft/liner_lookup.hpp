#pragma once
// The liner of the soft backend, fixed in the mill frame. Disks are turned into the mill
// frame and find their candidate edges through angle bins (an O(1) static lookup, binned by
// a pseudo-angle that needs no atan2): a disk
// far from the wall costs one radius test, a disk near it a handful of segment tests.
//
// Vertices are owned so that no contact is counted twice: edge k owns the points whose
// foot falls in [0, L_k) along it (a face contact), and the vertex it starts at when that
// vertex sticks out into the mill (a reflex vertex of the CCW mill polygon, such as a
// lifter's top corner) and the disk sits in the wedge outside it; such a vertex contact is
// attributed to whichever of the two faces meeting there has its normal nearer the contact
// normal (the key stays the owning edge k). At an inward corner
// (lifter base, shell arcs) a disk may touch both faces; those are two real contacts.
//
// The liner knows its inside: a face contact keeps working while the disk's centre is up
// to half a radius past the face line, so a disk pressed through the surface is pushed back
// out instead of being lost.
#include <cstdint>
#include <vector>

#include "geometry/vec2.hpp"
#include "mill/mill.hpp"

namespace millwear::soft {

// One candidate liner contact, mill frame.
struct LinerHit {
  int owner = -1;   // the edge that found it (contact key: at most one contact per owner)
  int edge = -1;    // the edge its work is attributed to
  Vec2 normal;      // unit, from the liner toward the disk centre
  double gap = 0.0; // centre distance to the feature minus the disk radius (< 0: overlap)
};

class LinerLookup {
 public:
  // reach_m: the largest centre-to-surface distance a query may ask about (radius plus
  // speculative margin). Bins are built for it; the narrow phase rebuilds them (rarely,
  // fit_liner_search) when a step needs more.
  void build(const MillGeometry& mill, double reach_m);
  double reach_m() const { return reach_m_; }
  // Radius inside which no disk centre with this reach can touch the liner.
  bool may_touch(Vec2 p_mill, double reach) const {
    return !binned_ || length_sq(p_mill) > (inner_m_ - reach) * (inner_m_ - reach);
  }
  // The most contacts a query can return: the most edges any bin lists (a disk in a
  // concave pocket of fine edges may touch many of them; none is ever dropped).
  int max_hits() const { return max_hits_; }
  // Write the contacts of a disk at p_mill (radius r) with gap below max_gap to out (room
  // for max_hits()), in increasing edge order; returns how many.
  int query(Vec2 p_mill, double r, double max_gap, LinerHit* out) const;

 private:
  std::vector<Vec2> a_, u_, n_in_;      // edge start, unit direction, inward normal
  std::vector<double> len_;
  std::vector<std::uint8_t> reflex_start_;  // start vertex sticks out into the mill
  std::vector<int> bin_start_, bin_edges_;  // CSR: edges near each angle bin (sorted)
  int bins_ = 1;
  int max_hits_ = 0;
  bool binned_ = false;
  double inner_m_ = 0.0;    // smallest distance from the axis to the liner
  double reach_m_ = 0.0;
  double bins_per_unit_ = 0.0;  // bins per unit of pseudo-angle (4 units a turn)
};

}  // namespace millwear::soft
