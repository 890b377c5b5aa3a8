#pragma once
// The soft backend's contacts: flat arrays in key order, split by how often they are
// touched, kept at their high-water size (no allocation per step once warm).
//
// Most disk-pair contacts are speculative margins that never carry an impulse: every solve
// and relax pass (2 x 4 a step) reads their gap (bodies, normal, start separation: 32
// bytes, two to a cache line) and the state byte, finds the row inert and goes on. The row
// proper (anchors, masses, material) and the impulses are read only for rows that act; the
// step sums are written once per substep (relax); the key is read by the matching, which
// copies a live contact's impulses alone (24 bytes, not its row); the info is cold
// (restitution; a liner contact's edge and point, for the accounting).
//
// A contact's normal, anchors and liner velocity are fixed for the step (as in Box2D);
// the substeps update only the separation, s = s0 + n . (dp_a - dp_b), with dp the
// displacement since the step began (the liner's: its velocity at the contact times the
// elapsed time). For disks the anchors lie on the normal, so the normal row has no
// rotational term.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace millwear::soft {

struct PairGap {
  int a = 0, b = 0;            // solver disk indices, a < b
  double nx = 0, ny = 0;       // unit normal from b toward a
  double s0 = 0;               // separation at the start of the step
};
// The impulses of the current substep: what the warm start applies and the matching carries
// from one step to the next. An array of their own: the matching and the lanes' loading and
// reading back touch only these, not the row around them (at 30k disks and more the rows
// stream from memory; docs/soft-solver.md).
struct Impulse {
  double ln = 0, lt = 0, lr = 0;  // normal, tangent, rolling
};
struct PairRow {
  double alpha = 0, beta = 0;  // anchors: r_a = -alpha n, r_b = +beta n
  double mn = 0, mt = 0, mr = 0;  // effective masses: normal, tangent, rolling
  double mu = 0, lever = 0;    // friction coefficient, rolling-resistance lever
};
struct LinerGap {
  int a = 0;
  double nx = 0, ny = 0;       // unit normal from the liner toward a
  double s0 = 0;
  double vlx = 0, vly = 0;     // liner velocity at the contact point
};
struct LinerRow {
  double alpha = 0;            // anchor r_a = -alpha n
  double mn = 0, mt = 0, mr = 0;
  double mu = 0, lever = 0;
};

// Per-contact state bits. kLive: some impulse of the row is not zero (kept up to date
// wherever an impulse is written, so testing it is testing the impulses). kBuilt: the
// row's anchors, masses and material (and the info's restitution and start
// velocity) have been computed. A disk-pair row is built lazily, the first time a pass
// does not skip it: most are margins that never carry load, and for them the narrow phase
// computes only the gap. A row neither built nor live has zero impulses, whatever its slot
// of the impulse array holds (nothing reads that slot before building the row zeroes it).
// kBounce: a built disk-pair row whose contact closed faster than the restitution
// threshold with a restitution above zero: the once-a-step restitution pass reads this
// byte and touches the cold info and sums of these rows only.
constexpr std::uint8_t kLive = 1, kBuilt = 2, kBounce = 4;

inline std::uint8_t has_impulse(const Impulse& p) {
  return p.ln != 0.0 || p.lt != 0.0 || p.lr != 0.0 ? kLive : 0;
}

struct StepSum {
  double pn = 0, pt = 0, pr = 0;  // impulses summed over the step
};
// What every contact carries from one step to the next, apart from the cold info: the
// matching reads it for every contact, most of which never get an info.
struct ContactKey {
  std::uint64_t key = 0;   // (a << 32) | b for disk pairs (a < b), (a << 32) | owner for liner
  double event_J = 0;      // energy dissipated since this collision began (spectrum)
};
// A disk pair's: what the restitution pass reads.
struct PairInfo {
  double e = 0;            // restitution
  double vn0 = 0;          // normal relative velocity at the start of the step (restitution)
};
// A disk-liner contact's: also the edge its work goes to and where it touches.
struct LinerInfo {
  int edge = -1;           // liner edge the contact's work goes to
  int owner = -1;          // liner edge that found it (its key)
  double px = 0, py = 0;   // contact point, world (for torque and velocity)
  double e = 0;            // restitution
  double vn0 = 0;          // normal relative velocity at the start of the step (restitution)
};

inline std::uint64_t pair_key(int a, int b) {
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

// The arrays only grow (to their high-water mark, during warm-up); n counts the contacts in
// use, so filling a step's contacts is a bounds check and plain stores, no construction.
template <class Gap, class Row, class Info>
struct ContactSet {
  std::vector<Gap> gap;
  std::vector<Row> row;
  std::vector<Impulse> impulse;
  std::vector<std::uint8_t> state;  // kLive | kBuilt | kBounce
  std::vector<StepSum> sum;
  std::vector<ContactKey> key;
  std::vector<Info> info;
  std::size_t n = 0;
  std::size_t size() const { return n; }
  void clear() { n = 0; }
  void reserve(std::size_t m) {
    if (row.size() >= m) return;
    gap.resize(m);
    row.resize(m);
    impulse.resize(m);
    state.resize(m);
    sum.resize(m);
    key.resize(m);
    info.resize(m);
  }
  void resize(std::size_t m) {
    reserve(m);
    n = m;
  }
  void swap(ContactSet& o) {
    gap.swap(o.gap);
    row.swap(o.row);
    impulse.swap(o.impulse);
    state.swap(o.state);
    sum.swap(o.sum);
    key.swap(o.key);
    info.swap(o.info);
    std::swap(n, o.n);
  }
  void copy(std::size_t to, const ContactSet& o, std::size_t from) {
    gap[to] = o.gap[from];
    row[to] = o.row[from];
    impulse[to] = o.impulse[from];
    state[to] = o.state[from];
    sum[to] = o.sum[from];
    key[to] = o.key[from];
    info[to] = o.info[from];
  }
};

using PairSet = ContactSet<PairGap, PairRow, PairInfo>;
using LinerSet = ContactSet<LinerGap, LinerRow, LinerInfo>;

// Scratch of sort_by_key, sized at warm-up.
struct SortScratch {
  std::vector<int> bucket_end, order;
};

// This step's contacts and last step's (for the warm start), each sorted by key.
struct Contacts {
  PairSet pairs, pairs_old;
  LinerSet liner, liner_old;
  SortScratch sort_scratch;

  void reserve(int disks) {
    const auto n = static_cast<std::size_t>(disks);
    // Headroom over the 1.9 to 3.1 candidate pairs per disk the benchmark charges have,
    // so that the arrays rarely grow after the first step; at least one liner contact
    // per disk.
    const std::size_t expected_pairs = 4 * n + 16;
    pairs.reserve(expected_pairs);
    pairs_old.reserve(expected_pairs);
    liner.reserve(n + 16);
    liner_old.reserve(n + 16);
    sort_scratch.order.reserve(expected_pairs);
    sort_scratch.bucket_end.reserve(n + 1);
  }
  // This step's contacts become last step's; the step before last's buffers are reused.
  void begin_step() {
    pairs_old.swap(pairs);
    liner_old.swap(liner);
  }
};

// Sort a contact set by key through the spare set (whose contents are dead at this point):
// a counting sort by the key's upper half (a pair's lower disk, a liner contact's disk:
// below `disks` either way), then each bucket (a handful of contacts) by insertion sort on
// the whole key. Keys are unique, so this is
// the one order by key. No allocation once the scratch reached its size.
template <class Set>
void sort_by_key(Set& set, Set& spare, int disks, SortScratch& scratch) {
  const std::size_t m = set.size();
  std::vector<int>& bucket = scratch.bucket_end;
  std::vector<int>& order = scratch.order;
  bucket.assign(static_cast<std::size_t>(disks) + 1, 0);
  order.resize(m);
  for (std::size_t k = 0; k < m; ++k) bucket[(set.key[k].key >> 32) + 1] += 1;
  for (int i = 0; i < disks; ++i) bucket[static_cast<std::size_t>(i) + 1] += bucket[static_cast<std::size_t>(i)];
  for (std::size_t k = 0; k < m; ++k) order[static_cast<std::size_t>(bucket[set.key[k].key >> 32]++)] = static_cast<int>(k);
  // bucket[i] is now the end of disk i's contacts.
  int b0 = 0;
  for (int i = 0; i < disks; ++i) {
    const int b1 = bucket[static_cast<std::size_t>(i)];
    for (int p = b0 + 1; p < b1; ++p)
      for (int q = p; q > b0 && set.key[static_cast<std::size_t>(order[static_cast<std::size_t>(q) - 1])].key >
                                    set.key[static_cast<std::size_t>(order[static_cast<std::size_t>(q)])].key;
           --q)
        std::swap(order[static_cast<std::size_t>(q) - 1], order[static_cast<std::size_t>(q)]);
    b0 = b1;
  }
  spare.resize(m);
  for (std::size_t t = 0; t < m; ++t) spare.copy(t, set, static_cast<std::size_t>(order[t]));
  set.swap(spare);
}

}  // namespace millwear::soft
