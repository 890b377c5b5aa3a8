#pragma once
// Narrow phase of the soft backend: disk pairs, each found once from the cells a disk's
// reach can touch and bucketed into key order; disk-liner contacts from the angle-bin
// lookup in the mill frame; both matched against last step's contacts to carry their
// impulses over (warm start). A disk-pair contact gets only its gap here; its row is built
// the first time a pass of the solve does not skip it (build_pair_row).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/accounting.hpp"
#include "engine/soft/broad_phase.hpp"
#include "engine/soft/contact_set.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/grid.hpp"
#include "engine/soft/liner_lookup.hpp"
#include "engine/soft/model.hpp"
#include "engine/soft/workers.hpp"

namespace millwear::soft {

// Scratch of the pair search, at its high-water size.
struct PairSearch {
  // A disk as the search sees it, stored in grid order so that a row of cells' candidates
  // are read from contiguous memory: 32 bytes, two to a cache line.
  struct Candidate {
    double x, y, reach;  // reach = radius + margin
    int j;
  };
  std::vector<Candidate> candidates;
  // Pairs as found (key: lower << 32 | upper), per range of candidates, each range's at its
  // high-water size.
  std::vector<std::vector<std::uint64_t>> found_keys;
  std::vector<std::size_t> found;
  std::vector<int> bucket_end, upper;      // the pairs bucketed by lower index
  // Scratch of the threaded bucketing: per block of ranges, each disk's count and then
  // cursor (block b's at counts[b * disks ..]); per range of disks, its pairs.
  std::vector<int> counts, range_pairs;
  void reserve(int disks) { candidates.reserve(static_cast<std::size_t>(disks)); }
};

// The liner's angle-bin lookup and the reach it must cover, and the hits of each range of
// disks (the search runs in ranges; the contacts are then written in disk order).
struct LinerSearch {
  LinerLookup lookup;
  double reach_needed_m = 0.0;  // grown (never shrunk) when a fast disk needed more
  struct Found {
    int disk;
    LinerHit hit;
  };
  std::vector<std::vector<Found>> found;  // per range, at its high-water size
  std::vector<std::vector<LinerHit>> hits;  // per range: one disk's hits (lookup.max_hits())
  std::vector<std::size_t> count, offset;
};

// After set_liner: bins for the reach of the largest disk at rest, or more if a step
// already needed more.
void build_liner_search(const Model& model, const LinerModel& liner, LinerSearch& search);
// Rebuild the bins (rarely) when a fast disk or a fast mill needs more reach than built.
void fit_liner_search(const Model& model, const LinerModel& liner, const StepBounds& bounds,
                      double mill_speed_rad_s, LinerSearch& search);

// Pairs within the sum of their reaches (radius + margin), in key order, rows unbuilt.
// The scan runs in ranges of candidates, each into its own list; the lists are bucketed by
// lower disk and each bucket sorted, so the result is the same whoever found what.
void find_pairs(const Model& model, const Disks& disks, const Grid& pair_grid,
                const StepBounds& bounds, PairSearch& search, PairSet& pairs,
                Workers& workers);

// Disk-liner contacts through the mill-frame lookup, rows built; the liner's velocity at
// a contact is omega x r.
void find_liner_contacts(const Model& model, const LinerModel& liner, LinerSearch& search,
                         const Disks& disks, double mill_angle_rad, double mill_speed_rad_s,
                         LinerSet& contacts, Workers& workers);

// Scratch of the matching: per range, the collision events that ended (in key order, with
// their spectrum bins), booked after the ranges ran in range order.
struct MatchScratch {
  std::vector<std::vector<CollisionEvent>> ended;
  std::vector<std::size_t> count;
};

// Carry last step's impulses to the contacts that persist (merge of two key-sorted lists,
// in ranges of this step's list, each starting where its first key falls in last step's).
// A disk-pair contact that ended closes its collision event for the spectrum.
void match_warm_start(Contacts& contacts, Accounting& accounting, MatchScratch& scratch,
                      Workers& workers);

// A built disk pair's material and restitution, from the state at the start of the step
// (the velocities of StepStart; masses and materials do not change within a step), so that
// building it in the middle of the solve gives the same bits as building it in the narrow
// phase. Sets the info and the state's kBuilt (and kBounce); returns the friction
// coefficient and rolling lever, which a row in lanes takes straight into its lane.
struct PairMaterial {
  double mu, lever;
};
inline PairMaterial build_pair_contact(const Model& model, const Disks& disks, const StepStart& start,
                                       PairSet& pairs, std::size_t q) {
  const PairGap& g = pairs.gap[q];
  PairInfo& info = pairs.info[q];
  const auto a = static_cast<std::size_t>(g.a), b = static_cast<std::size_t>(g.b);
  pairs.state[q] |= kBuilt;
  const double ra = disks.radius[a], rb = disks.radius[b];
  const Materials& mat = model.materials;
  const std::size_t pair = mat.pair(disks.species[a], disks.species[b]);
  info.e = mat.pair_restitution[pair];
  const StartVelocity &va = start.v[a], &vb = start.v[b];
  info.vn0 = (va.vx - vb.vx) * g.nx + (va.vy - vb.vy) * g.ny;
  if (info.e != 0.0 && !(info.vn0 > -model.restitution_threshold_m_s)) pairs.state[q] |= kBounce;
  // Rolling resistance lever: the coefficient times the pair's reduced radius (the DEM
  // convention; a disk on a flat liner gets its own radius).
  return {mat.pair_friction[pair], mat.pair_rolling[pair] * ra * rb / (ra + rb)};
}

// Everything of a serial disk-pair row beyond its gap (build_pair_contact, and the row's
// anchors and effective masses).
inline void build_pair_row(const Model& model, const Disks& disks, const StepStart& start,
                           PairSet& pairs, std::size_t q) {
  const PairGap& g = pairs.gap[q];
  PairRow& c = pairs.row[q];
  const auto a = static_cast<std::size_t>(g.a), b = static_cast<std::size_t>(g.b);
  if (!(pairs.state[q] & kLive)) pairs.impulse[q] = Impulse{};
  pairs.sum[q] = StepSum{};
  const PairMaterial m = build_pair_contact(model, disks, start, pairs, q);
  c.mu = m.mu;
  c.lever = m.lever;
  // The contact point is midway between the two surfaces.
  c.alpha = disks.radius[a] + 0.5 * g.s0;
  c.beta = disks.radius[b] + 0.5 * g.s0;
  const Body& A = disks.body[a];
  const Body& B = disks.body[b];
  const double im = A.im + B.im;
  c.mn = im > 0.0 ? 1.0 / im : 0.0;
  const double it = im + A.ii * c.alpha * c.alpha + B.ii * c.beta * c.beta;
  c.mt = it > 0.0 ? 1.0 / it : 0.0;
  const double ir = A.ii + B.ii;
  c.mr = ir > 0.0 ? 1.0 / ir : 0.0;
}

}  // namespace millwear::soft
